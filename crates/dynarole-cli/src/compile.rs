//! `dynarole compile`: the checked sequence as a self-contained directory of C (runtime,
//! generated state machine, Makefile) for the chosen protocol.

use crate::load::{self, Failure, PluginArgs};
use crate::render;
use dynarole_codegen::{
    generate_c, generate_nesc, CompileOptions, Dissemination, PaperMerge, Protocol, TokenRetries,
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

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum ProtocolArg {
    /// dynarole's protocol: shared state as a join-semilattice (default).
    Lattice,
    /// The paper's protocol, faithfully (for reproduction and comparison).
    Paper,
    /// The token-passing baseline the paper replaced: one token, routed explicitly from
    /// module to module (needs --from: routes are computed on the configuration).
    Token,
}

/// `--token-retries`: `plain` (each hop sends once, no acknowledgement), a number of tries
/// per hop (acknowledged), or `unlimited`.
pub fn parse_token_retries(text: &str) -> Result<TokenRetries, String> {
    match text {
        "plain" => Ok(TokenRetries::Plain),
        "unlimited" => Ok(TokenRetries::Unlimited),
        n => match n.parse::<u16>() {
            Ok(tries) if tries >= 1 => Ok(TokenRetries::Tries(tries)),
            _ => Err(format!(
                "expected `plain`, `unlimited` or a number of tries from 1 to 65535, found `{n}`"
            )),
        },
    }
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum MergeArg {
    /// Fig. 3 as printed (`>` and `and`).
    Printed,
    /// The Java runtime of the original experiments (`>` and `or`).
    Java,
    /// The later C port, which the text and Fig. 4 need (`>=` and `or`).
    CPort,
}

/// Options of the protocols, shared by `compile` and `simulate`.
#[derive(Clone, Debug, clap::Args)]
pub struct ProtocolOptions {
    /// The protocol that shares the state between the modules.
    #[arg(long, value_enum, default_value_t = ProtocolArg::Lattice)]
    pub protocol: ProtocolArg,
    /// Paper protocol: which of the three historical merge functions to use.
    #[arg(long, value_enum, default_value_t = MergeArg::CPort)]
    pub merge: MergeArg,
    /// Paper protocol: add the pending state and transfer control in one step.
    #[arg(long)]
    pub single_step_handover: bool,
    /// Paper protocol: restart an interrupted pending operation after a reset (Sec. III-C).
    #[arg(long)]
    pub restart_pending: bool,
    /// Lattice protocol: the modules have no non-volatile storage (weaker reset guarantee).
    #[arg(long)]
    pub no_nv: bool,
    /// Lattice protocol: `adaptive` (default: news at once, then an interval that doubles
    /// while nothing is new) or `fixed` (a broadcast every 100 ms, as before). A usage error
    /// with the paper or token protocol, which have their own fixed period.
    #[arg(long, value_name = "MODE", value_parser = Dissemination::parse)]
    pub dissemination: Option<Dissemination>,
    /// Token protocol: `plain` (sent once per hop), tries per hop (acknowledged; the
    /// original experiments used 32 and 128) or `unlimited`.
    #[arg(long, value_name = "TRIES", value_parser = parse_token_retries, default_value = "32")]
    pub token_retries: TokenRetries,
    /// The robot (or swarm) identity every packet carries: modules drop packets of another
    /// robot in range (a build can override it at flash time with -DDR_ROBOT_ID=N).
    #[arg(long, value_name = "ID", default_value_t = 0)]
    pub robot_id: u16,
    /// A shared 128-bit key, as 32 hexadecimal digits: every packet then carries a 4-byte
    /// authentication tag (SipHash-2-4) and modules drop packets without a valid one.
    #[arg(long, value_name = "HEX", value_parser = parse_key)]
    pub key: Option<[u8; 16]>,
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
        if let (Some(d), false) = (self.dissemination, self.protocol_is_lattice()) {
            return Err(Failure::Usage(format!(
                "--dissemination {} applies to the lattice protocol only; the {} protocol has its own fixed broadcast period",
                d.name(),
                self.protocol_name()
            )));
        }
        Ok(CompileOptions {
            protocol: match self.protocol {
                ProtocolArg::Lattice => Protocol::Lattice,
                ProtocolArg::Paper => Protocol::Paper,
                ProtocolArg::Token => Protocol::Token,
            },
            merge: match self.merge {
                MergeArg::Printed => PaperMerge::Printed,
                MergeArg::Java => PaperMerge::Java,
                MergeArg::CPort => PaperMerge::CPort,
            },
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
        })
    }

    fn protocol_is_lattice(&self) -> bool {
        matches!(self.protocol, ProtocolArg::Lattice)
    }

    /// The protocol's name as the command line spells it.
    fn protocol_name(&self) -> String {
        use clap::ValueEnum;
        self.protocol
            .to_possible_value()
            .map(|v| v.get_name().to_string())
            .unwrap_or_default()
    }
}

/// What `compile` was asked to do.
pub struct CompileArgs<'a> {
    pub file: &'a Path,
    pub sequences: &'a [String],
    pub target: Target,
    pub options: &'a ProtocolOptions,
    pub epochs: u16,
    pub out_dir: &'a Path,
    /// The start configuration: `--target promela` and the token protocol need it.
    pub from: Option<&'a Path>,
    pub plugins: &'a PluginArgs,
}

/// C or nesC (`--target promela` is `model::compile`, which lib.rs calls instead).
pub fn run(args: &CompileArgs) -> Result<ExitCode, Failure> {
    load::with_program(args.file, args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let names = load::select_sequences(program, &display, args.sequences)?;
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
        if let Err(diagnostics) = add_token_routes(&mut options, program, &plans, args.from)? {
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
        std::fs::create_dir_all(args.out_dir).map_err(|e| {
            Failure::Input(format!("cannot create {}: {e}", args.out_dir.display()))
        })?;
        for (name, text) in &generated.files {
            let path = args.out_dir.join(name);
            std::fs::write(&path, text)
                .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))?;
        }
        println!(
            "compiled {} ({} protocol): {} statements, {} modules/roles, window {}, packet {} bytes, fingerprint {:08x}, robot {} -> {}",
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
        Ok(ExitCode::SUCCESS)
    })
}

/// Token protocol: computes its routes on the configuration `from` (required) into
/// `options`; other protocols need nothing. The inner error is the statement that cannot be
/// routed.
pub fn add_token_routes(
    options: &mut CompileOptions,
    program: &dynarole_core::Program,
    plans: &[dynarole_core::expand::Plan],
    from: Option<&Path>,
) -> Result<Result<(), Vec<Diagnostic>>, Failure> {
    if options.protocol != Protocol::Token {
        return Ok(Ok(()));
    }
    let Some(from) = from else {
        return Err(Failure::Usage(
            "--protocol token needs --from CONFIG: its hand-over routes are computed on the configuration".into(),
        ));
    };
    let start = crate::world::read_configuration(from)?;
    Ok(
        dynarole_replay::token_routes(program, plans, &start).map(|routes| {
            options.routes = Some(routes);
        }),
    )
}
