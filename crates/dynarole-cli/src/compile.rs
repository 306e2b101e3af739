//! `dynarole compile`: the checked sequence as a self-contained directory of C (runtime,
//! generated state machine, Makefile) for the chosen protocol.

use crate::load::{self, Failure, PluginArgs};
use crate::render;
use dynarole_codegen::{generate_c, generate_nesc, CompileOptions, PaperMerge, Protocol};
use dynarole_core::{Diagnostic, DiagnosticKind};
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
}

impl ProtocolOptions {
    /// The back-end's options for these flags.
    pub fn compile_options(&self, epochs: u16, name: String) -> CompileOptions {
        CompileOptions {
            protocol: match self.protocol {
                ProtocolArg::Lattice => Protocol::Lattice,
                ProtocolArg::Paper => Protocol::Paper,
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
            name,
        }
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
    /// The configuration, for `--target promela`.
    pub from: Option<&'a Path>,
    pub model: &'a crate::verify::ModelArgs,
    pub plugins: &'a PluginArgs,
}

pub fn run(args: &CompileArgs) -> Result<ExitCode, Failure> {
    if let Target::Promela = args.target {
        let Some(from) = args.from else {
            return Err(Failure::Usage(
                "--target promela needs --from CONFIG (the model is of a robot's communication graph)".into(),
            ));
        };
        return load::with_program(args.file, args.plugins, |program, source| {
            let display = args.file.display().to_string();
            let request = crate::verify::Request {
                program,
                source,
                display: &display,
                sequences: args.sequences,
                from,
                options: args.options,
                model: args.model,
                epochs: args.epochs,
            };
            crate::verify::write_model(&request, args.out_dir)
        });
    }
    load::with_program(args.file, args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let names = load::sequence_names(program, args.sequences);
        let mut plans = Vec::new();
        for name in &names {
            let plan = program
                .expand(name)
                .ok_or_else(|| Failure::Input(format!("{display}: no sequence named `{name}`")))?;
            if let (ProtocolArg::Paper, Err(d)) = (args.options.protocol, plan.flatten_for_paper())
            {
                render::diagnostics(&display, source, &[d]);
                return Ok(ExitCode::from(1));
            }
            plans.push(plan);
        }
        let limit_error = |e: dynarole_core::lower::LimitError| {
            Diagnostic::new(DiagnosticKind::TargetLimit { message: e.message }, e.span)
        };
        let ir = match program.lower(&plans) {
            Ok(ir) => ir,
            Err(e) => {
                render::diagnostics(&display, source, &[limit_error(e)]);
                return Ok(ExitCode::from(1));
            }
        };
        let options = args.options.compile_options(args.epochs, names.join(" + "));
        let generate = match args.target {
            Target::C | Target::Promela => generate_c,
            Target::Nesc => generate_nesc,
        };
        let generated = match generate(&ir, &program.robot, &options) {
            Ok(g) => g,
            Err(e) => {
                render::diagnostics(&display, source, &[limit_error(e)]);
                return Ok(ExitCode::from(1));
            }
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
            "compiled {} ({:?} protocol): {} statements, {} modules/roles, window {}, packet {} bytes, program id {} -> {}",
            options.name,
            args.options.protocol,
            ir.statements.len(),
            ir.addresses.len(),
            ir.window,
            generated.packet_bytes,
            generated.program_id,
            args.out_dir.display()
        );
        Ok(ExitCode::SUCCESS)
    })
}
