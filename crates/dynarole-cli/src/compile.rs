//! `dynarole compile`: the checked sequence as a self-contained directory of C (runtime,
//! generated state machine, Makefile) for the chosen protocol.

use crate::load::{self, Failure};
use crate::render;
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use dynarole_codegen::{
    default_failure_policy, generate_c, generate_nesc, Choice, CompileOptions, Dissemination,
    OnFailure, PaperMerge, Protocol, Setting, TokenRetries, MAX_RETRIES,
};
use dynarole_core::{driver, Diagnostic};
use std::path::Path;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Target {
    /// Portable C99 plus the runtime and a Makefile.
    C,
    /// The same C wrapped in a TinyOS 2 component (DynaRoleC.nc, DynaRoleP.nc).
    Nesc,
    /// A Promela model for spin (`model.pml`) on the configuration given with --from; see
    /// `dynarole verify`.
    Promela,
}

/// The value parser of a flag that takes one of a set of names from the protocol table (or
/// the simulator's stepping): clap lists the names in the help and suggests the closest one for
/// a typo, and the table parses the value.
pub fn choice<T: Choice + Send + Sync>() -> impl TypedValueParser<Value = T> {
    let values = T::ALL.iter().map(|v| match v.help() {
        "" => PossibleValue::new(v.name()),
        help => PossibleValue::new(v.name()).help(help),
    });
    PossibleValuesParser::new(values).try_map(|name| dynarole_codegen::choice::parse::<T>(&name))
}

/// Options of the protocols, shared by `compile` and `simulate`.
#[derive(Clone, Debug, clap::Args)]
pub struct ProtocolOptions {
    /// The protocol that shares the state between the modules.
    #[arg(long, value_parser = choice::<Protocol>(), default_value_t = Protocol::Lattice)]
    pub protocol: Protocol,
    /// Paper protocol: which of the three historical merge functions to use.
    #[arg(long, value_parser = choice::<PaperMerge>(), default_value_t = PaperMerge::CPort)]
    pub merge: PaperMerge,
    /// Paper protocol: add the pending state and transfer control in one step.
    #[arg(long)]
    pub single_step_handover: bool,
    /// Paper protocol: restart an interrupted pending operation after a reset (Sec. III-C).
    #[arg(long)]
    pub restart_pending: bool,
    /// Lattice protocol: the modules have no non-volatile storage (weaker reset guarantee).
    #[arg(long)]
    pub no_nv: bool,
    /// Lattice protocol: how the state is broadcast. A usage error with the paper or token
    /// protocol, which have their own fixed period.
    #[arg(long, value_name = "MODE", value_parser = choice::<Dissemination>())]
    pub dissemination: Option<Dissemination>,
    /// Lattice protocol: what a module does when one of its operations fails (a connector
    /// that does not latch, a joint that stalls). Default: the runtime's, `retry`.
    #[arg(long, value_name = "POLICY", value_parser = choice::<OnFailure>())]
    pub on_failure: Option<OnFailure>,
    /// Lattice protocol, `--on-failure retry`: times a failed operation is issued again
    /// before the module stops (0 to 100; default: the runtime's, 3).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u8).range(0..=i64::from(MAX_RETRIES)))]
    pub retries: Option<u8>,
    /// Token protocol: `plain` (sent once per hop), tries per hop (acknowledged; the
    /// original experiments used 32 and 128) or `unlimited`.
    #[arg(long, value_name = "TRIES", value_parser = str::parse::<TokenRetries>, default_value = "32")]
    pub token_retries: TokenRetries,
    /// The robot (or swarm) identity every packet carries: modules drop packets of another
    /// robot in range (a build can override it at flash time with -DDR_ROBOT_ID=N).
    #[arg(long, value_name = "ID", default_value_t = 0)]
    pub robot_id: u16,
    /// A shared 128-bit key, as 32 hexadecimal digits: every packet then carries a 4-byte
    /// authentication tag (SipHash-2-4) and modules drop packets without a valid one.
    #[arg(long, value_name = "HEX", value_parser = parse_key)]
    pub key: Option<[u8; 16]>,
    /// This launch's execution, a 32-bit value (decimal, or hexadecimal after 0x) chosen anew
    /// for every launch of the robot: packets and non-volatile records of another launch are
    /// refused, so a recorded packet cannot be replayed into this one (a build can override
    /// it at flash time with -DDR_EXECUTION=N; every module of a robot needs the same value).
    #[arg(long, value_name = "N", value_parser = parse_execution, default_value_t = 0)]
    pub execution: u32,
}

/// `--execution`: a 32-bit value, decimal or `0x` hexadecimal.
pub fn parse_execution(text: &str) -> Result<u32, String> {
    let parsed = match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(hex, 16),
        None => text.parse::<u32>(),
    };
    parsed.map_err(|_| {
        format!("expected a 32-bit value (0 to 4294967295, or 0x0 to 0xffffffff), found `{text}`")
    })
}

/// `--key`: exactly 32 hexadecimal digits (16 bytes).
pub fn parse_key(text: &str) -> Result<[u8; 16], String> {
    let digits = text.as_bytes();
    let expected = "expected 32 hexadecimal digits (a 128-bit key)";
    if digits.len() != 32 {
        return Err(format!("{expected}, found {} characters", digits.len()));
    }
    if let Some(bad) = text.chars().find(|c| !c.is_ascii_hexdigit()) {
        return Err(format!("{expected}, found `{bad}`"));
    }
    let mut key = [0u8; 16];
    for (byte, pair) in key.iter_mut().zip(digits.chunks(2)) {
        let pair = std::str::from_utf8(pair).map_err(|_| expected.to_string())?;
        *byte = u8::from_str_radix(pair, 16).map_err(|_| format!("{expected}, found `{pair}`"))?;
    }
    Ok(key)
}

impl ProtocolOptions {
    /// The back-end's options for these flags; a usage error for `--dissemination` with a
    /// protocol other than lattice (it would silently change nothing).
    pub fn compile_options(&self, epochs: u16, name: String) -> Result<CompileOptions, Failure> {
        let runs = (epochs != 1).then(|| (Some(Setting::Epochs), format!("--epochs {epochs}")));
        let given = self.flag_list().into_iter().chain(runs);
        for (setting, flag) in given {
            if let Some(setting) = setting.filter(|s| !self.protocol.takes(*s)) {
                return Err(Failure::Usage(format!(
                    "{flag} applies to the {} protocol only; the {} protocol {}",
                    Protocol::taking(setting).join(" and "),
                    self.protocol,
                    setting.without_it()
                )));
            }
        }
        let (default_policy, default_retries) = default_failure_policy();
        let on_failure = self.on_failure.unwrap_or(default_policy);
        if let (Some(n), OnFailure::Stop) = (self.retries, on_failure) {
            return Err(Failure::Usage(format!(
                "--retries {n} applies to --on-failure retry; --on-failure stop retries nothing"
            )));
        }
        Ok(CompileOptions {
            on_failure,
            retries: self.retries.unwrap_or(default_retries),
            protocol: self.protocol,
            merge: self.merge,
            single_step_handover: self.single_step_handover,
            restart_pending: self.restart_pending,
            epochs,
            no_nv: self.no_nv,
            dissemination: self.dissemination.unwrap_or_default(),
            token_retries: self.token_retries,
            routes: None,
            name,
            robot_id: self.robot_id,
            key: self.key,
            execution: self.execution,
        })
    }
}

impl ProtocolOptions {
    /// The command-line flags that give these options again: every one that differs from its
    /// default, so a printed command (`simulate`'s `replay with:`) runs the same build. The
    /// destructuring names every field, so a new option cannot be left out without a compile
    /// error.
    pub fn flags(&self) -> Vec<String> {
        self.flag_list().into_iter().map(|(_, flag)| flag).collect()
    }

    /// `flags`, each with the protocol setting it belongs to (none for the protocol itself
    /// and the packet identity, which every protocol takes).
    fn flag_list(&self) -> Vec<(Option<Setting>, String)> {
        let ProtocolOptions {
            protocol,
            merge,
            single_step_handover,
            restart_pending,
            no_nv,
            dissemination,
            on_failure,
            retries,
            token_retries,
            robot_id,
            key,
            execution,
        } = self;
        let defaults = Self::defaults();
        let mut flags = vec![(None, format!("--protocol {protocol}"))];
        if *merge != defaults.merge {
            flags.push((Some(Setting::Merge), format!("--merge {merge}")));
        }
        let switches = [
            (
                *single_step_handover,
                Setting::PaperVariants,
                "--single-step-handover",
            ),
            (
                *restart_pending,
                Setting::PaperVariants,
                "--restart-pending",
            ),
            (*no_nv, Setting::NoNv, "--no-nv"),
        ];
        flags.extend(
            (switches.iter())
                .filter(|(on, _, _)| *on)
                .map(|(_, setting, f)| (Some(*setting), f.to_string())),
        );
        if let Some(d) = dissemination {
            let flag = format!("--dissemination {}", d.name());
            flags.push((Some(Setting::Dissemination), flag));
        }
        if let Some(policy) = on_failure {
            let flag = format!("--on-failure {}", policy.name());
            flags.push((Some(Setting::OnFailure), flag));
        }
        if let Some(n) = retries {
            flags.push((Some(Setting::OnFailure), format!("--retries {n}")));
        }
        if *token_retries != defaults.token_retries {
            let flag = format!("--token-retries {}", token_retries.name());
            flags.push((Some(Setting::TokenRetries), flag));
        }
        if *robot_id != defaults.robot_id {
            flags.push((None, format!("--robot-id {robot_id}")));
        }
        if let Some(key) = key {
            let hex: String = key.iter().map(|b| format!("{b:02x}")).collect();
            flags.push((None, format!("--key {hex}")));
        }
        if *execution != defaults.execution {
            flags.push((None, format!("--execution {execution}")));
        }
        flags
    }

    /// The options of a command line that gives none: the defaults of the clap attributes
    /// above, read from there rather than restated.
    pub fn defaults() -> Self {
        #[derive(clap::Parser)]
        struct Bare {
            #[command(flatten)]
            options: ProtocolOptions,
        }
        match <Bare as clap::Parser>::try_parse_from(["dynarole"]) {
            Ok(bare) => bare.options,
            // Every option has a default: an empty command line always parses.
            Err(e) => unreachable!("the protocol options have defaults: {e}"),
        }
    }
}

/// What `compile` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct CompileArgs {
    /// The `.dr` file holding the sequences.
    pub file: std::path::PathBuf,
    /// Sequence to compile; repeat to run several in turn (default: the first in the file).
    #[arg(long = "sequence", value_name = "NAME")]
    pub sequences: Vec<String>,
    /// What to generate: C for the modules, nesC (TinyOS), or the Promela model for spin.
    #[arg(long, value_enum, default_value_t = Target::C)]
    pub target: Target,
    #[command(flatten)]
    pub options: ProtocolOptions,
    /// Lattice protocol: how many times the whole sequence runs (0: forever).
    #[arg(long, default_value_t = 1)]
    pub epochs: u16,
    /// The directory to write.
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub out_dir: std::path::PathBuf,
    /// The configuration the sequence starts from: required by `--target promela` (whose
    /// model uses its communication graph) and `--protocol token` (whose hand-over routes
    /// are computed on it).
    #[arg(long, value_name = "CONFIG")]
    pub from: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub model: crate::bounds::ModelArgs,
    #[command(flatten)]
    pub plugins: crate::load::PluginArgs,
}

/// C or nesC (`--target promela` is `model::compile`, which lib.rs calls instead).
pub fn run(args: &CompileArgs) -> Result<ExitCode, Failure> {
    load::with_program(&args.file, &args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let names = load::select_sequences(program, &display, &args.sequences)?;
        let plans = crate::world::plans(program, &display, &names)?;
        let mut options = args
            .options
            .compile_options(args.epochs, names.join(" + "))?;
        // What the sequence cannot be compiled for is bad input (exit 1), shown in the source.
        let refused = |diagnostics: &[Diagnostic]| {
            render::diagnostics(&display, source, diagnostics);
            Ok(ExitCode::from(1))
        };
        let ir = match driver::lower(program, &plans, options.protocol.shape()) {
            Ok(ir) => ir,
            Err(d) => return refused(&[d]),
        };
        if let Err(diagnostics) = add_routes(&mut options, program, &plans, args.from.as_deref())? {
            return refused(&diagnostics);
        }
        let generate = match args.target {
            Target::C | Target::Promela => generate_c,
            Target::Nesc => generate_nesc,
        };
        let generated = match generate(&ir, &program.robot, &options) {
            Ok(g) => g,
            Err(e) => return refused(&[e.into()]),
        };
        std::fs::create_dir_all(&args.out_dir).map_err(|e| {
            Failure::Input(format!("cannot create {}: {e}", args.out_dir.display()))
        })?;
        for (name, text) in &generated.files {
            let path = args.out_dir.join(name);
            std::fs::write(&path, text)
                .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))?;
        }
        // The execution is shown once it was chosen (0 is the default, and every build's
        // before executions existed).
        let execution = match options.execution {
            0 => String::new(),
            n => format!(", execution {n}"),
        };
        println!(
            "compiled {} ({} protocol): {} statements, {} modules/roles, window {}, packet {} bytes, fingerprint {:08x}, robot {}{execution} -> {}",
            options.name,
            options.protocol.name(),
            ir.statements.len(),
            ir.addresses.len(),
            ir.window,
            generated.packet_bytes,
            generated.fingerprint,
            options.robot_id,
            args.out_dir.display()
        );
        if options.key.is_some() && options.execution == 0 {
            // The key stops forgers; only a new execution per launch stops a recording of
            // an earlier launch from being replayed (docs/runtime.md).
            eprintln!("note: a keyed build for execution 0: packets recorded in another launch of execution 0 would be accepted; give each launch its own --execution N (or -DDR_EXECUTION=N at flash time)");
        }
        Ok(ExitCode::SUCCESS)
    })
}

/// A protocol that needs routes (the token baseline): computes them on the configuration
/// `from` (required) into `options`; other protocols need nothing. The inner error is the statement that cannot be
/// routed.
pub fn add_routes(
    options: &mut CompileOptions,
    program: &dynarole_core::Program,
    plans: &[dynarole_core::expand::Plan],
    from: Option<&Path>,
) -> Result<Result<(), Vec<Diagnostic>>, Failure> {
    if !options.protocol.needs_routes() {
        return Ok(Ok(()));
    }
    let Some(from) = from else {
        return Err(Failure::Usage(format!(
            "--protocol {} needs --from CONFIG: its hand-over routes are computed on the configuration",
            options.protocol
        )));
    };
    let start = crate::world::read_configuration(from)?;
    Ok(
        dynarole_replay::token_routes(program, plans, &start).map(|routes| {
            options.routes = Some(routes);
        }),
    )
}

#[cfg(test)]
mod flag_tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Line {
        #[command(flatten)]
        options: ProtocolOptions,
    }

    fn round_trip(args: &[&str]) {
        let given = Line::try_parse_from(std::iter::once("dynarole").chain(args.iter().copied()))
            .expect("the flags parse")
            .options;
        let flags = given.flags().join(" ");
        let again = Line::try_parse_from(
            std::iter::once("dynarole").chain(flags.split(' ').filter(|w| !w.is_empty())),
        )
        .expect("the flags parse")
        .options;
        assert_eq!(format!("{given:?}"), format!("{again:?}"), "flags: {flags}");
    }

    #[test]
    fn the_printed_flags_give_the_same_options() {
        round_trip(&[]);
        round_trip(&[
            "--robot-id",
            "7",
            "--key",
            "000102030405060708090a0b0c0d0eff",
            "--execution",
            "0xfffffffe",
        ]);
        round_trip(&[
            "--protocol",
            "paper",
            "--merge",
            "java",
            "--restart-pending",
        ]);
        round_trip(&["--protocol", "paper", "--single-step-handover"]);
        round_trip(&["--no-nv", "--dissemination", "fixed"]);
        round_trip(&["--protocol", "token", "--token-retries", "unlimited"]);
        round_trip(&["--protocol", "token", "--token-retries", "plain"]);
    }

    #[test]
    fn a_keyed_build_prints_its_key_and_identity() {
        let line = Line::try_parse_from([
            "dynarole",
            "--robot-id",
            "9",
            "--key",
            "ffeeddccbbaa99887766554433221100",
        ])
        .expect("the flags parse");
        let flags = line.options.flags().join(" ");
        assert!(flags.contains("--robot-id 9"), "{flags}");
        assert!(
            flags.contains("--key ffeeddccbbaa99887766554433221100"),
            "{flags}"
        );
    }

    #[test]
    fn an_execution_is_32_bits_in_decimal_or_hexadecimal() {
        assert_eq!(parse_execution("41"), Ok(41));
        assert_eq!(parse_execution("0xDEAD0002"), Ok(0xDEAD_0002));
        assert_eq!(parse_execution("4294967295"), Ok(u32::MAX));
        for bad in ["4294967296", "0x100000000", "-1", "", "0x", "seven"] {
            let error = parse_execution(bad).expect_err(bad);
            assert!(error.contains("32-bit"), "{error}");
        }
    }
}
