//! The model of `verify` and `compile --target promela`: the arguments that bound the
//! environment, turned into `dynarole_verify`'s options; the configuration read and the
//! sequences modelled; the library's errors turned into exit codes; and the model files that
//! `compile --target promela` writes.

use crate::compile::{CompileArgs, ProtocolOptions};
use crate::load::{self, Failure};
use crate::render;
use crate::world::{prepare, read_configuration};
use dynarole_codegen::Fault;
use dynarole_verify::{BuildOptions, Built, Inputs, Method, Models, VerifyError};
use std::path::Path;
use std::process::ExitCode;

/// The bounds of the environment, shared by `verify` and `compile --target promela`.
#[derive(Clone, Debug, clap::Args)]
pub struct ModelArgs {
    /// Module resets, at most, in a run (any module, at any moment, mid-operation included).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub resets: u8,
    /// Only this module may reset (its name in the configuration); may be repeated.
    #[arg(long = "reset-only", value_name = "MODULE")]
    pub reset_only: Vec<String>,
    /// Packets that can be in flight at once and be delivered late (again and again, so also
    /// duplicated and reordered). Losses are not bounded: any packet may be lost.
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub late: u8,
    /// How to model the robot: `full` (every module's logic and every link), `compositional`
    /// (lattice only: one model per module, every packet any state the robot has reached;
    /// scales to large robots), `auto` (compositional for the lattice protocol on more than
    /// three modules).
    #[arg(long, value_enum, default_value_t = MethodArg::Auto)]
    pub method: MethodArg,
}

/// How the robot is modelled (see docs/verification.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodArg {
    Auto,
    Full,
    Compositional,
}

/// A deliberately broken lattice protocol (for the tests of the checker itself).
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum FaultArg {
    /// The join drops the other copy's done bit of the lowest incomplete statement.
    JoinDropsDone,
    /// The join raises the low-water mark without re-basing the bits.
    JoinNoRebase,
}

/// What a counterexample's recording is drawn on: the statements as lowered (the model's
/// statement numbers) and the start configuration.
pub struct Scene {
    pub statements: Vec<dynarole_core::check::ResolvedStatement>,
    pub start: dynarole_world::Configuration,
}

/// What a model is made from: a checked source, its sequences, a configuration, options.
pub struct Request<'a> {
    pub program: &'a dynarole_core::Program<'a>,
    pub source: &'a str,
    pub display: &'a str,
    pub sequences: &'a [String],
    pub from: &'a Path,
    pub options: &'a ProtocolOptions,
    pub model: &'a ModelArgs,
    pub epochs: u16,
}

/// The library's options for these arguments; the model is named after `names`.
fn build_options(
    req: &Request,
    names: &[String],
    fault: Option<FaultArg>,
) -> Result<BuildOptions, Failure> {
    Ok(BuildOptions {
        compile: req.options.compile_options(req.epochs, names.join(" + "))?,
        method: match req.model.method {
            MethodArg::Auto => Method::Auto,
            MethodArg::Full => Method::Full,
            MethodArg::Compositional => Method::Compositional,
        },
        resets: req.model.resets,
        reset_only: req.model.reset_only.clone(),
        late: req.model.late,
        fault: fault.map(|f| match f {
            FaultArg::JoinDropsDone => Fault::JoinDropsDone,
            FaultArg::JoinNoRebase => Fault::JoinNoRebase,
        }),
    })
}

/// The exit code or failure of a library error; the source's problems are rendered here.
pub fn failed(error: VerifyError, req: &Request) -> Result<ExitCode, Failure> {
    match error {
        VerifyError::Source(diagnostics) => {
            render::diagnostics(req.display, req.source, &diagnostics);
            Ok(ExitCode::from(1))
        }
        VerifyError::Input(m) => Err(Failure::Input(m)),
        VerifyError::Usage(m) => Err(Failure::Usage(m)),
        VerifyError::Internal(m) => Err(Failure::Internal(m)),
    }
}

/// Reads the configuration, expands the sequences and models them. `Err(code)` inside: the
/// problem was rendered as a diagnostic of the source.
pub fn build(
    req: &Request,
    fault: Option<FaultArg>,
) -> Result<Result<(Built, BuildOptions, Scene), ExitCode>, Failure> {
    let config = read_configuration(req.from)?;
    let prepared = match prepare(req.program, req.display, req.sequences, config)? {
        Ok(p) => p,
        Err(diagnostics) => {
            render::diagnostics(req.display, req.source, &diagnostics);
            return Ok(Err(ExitCode::from(1)));
        }
    };
    let options = build_options(req, &prepared.names, fault)?;
    let configuration = req.from.display().to_string();
    let inputs = Inputs {
        program: req.program,
        names: &prepared.names,
        plans: &prepared.plans,
        assignment: &prepared.assignment,
        world: &prepared.world,
        configuration: &configuration,
    };
    let scene = Scene {
        statements: prepared.statements(),
        start: prepared.start.clone(),
    };
    match dynarole_verify::build(&inputs, &options) {
        Ok(built) => Ok(Ok((built, options, scene))),
        Err(e) => failed(e, req).map(Err),
    }
}

/// `dynarole compile --target promela`: the model of the sequences on `--from CONFIG`.
pub fn compile(args: &CompileArgs, model: &ModelArgs) -> Result<ExitCode, Failure> {
    let Some(from) = args.from else {
        return Err(Failure::Usage(
            "--target promela needs --from CONFIG (the model is of a robot's communication graph)"
                .into(),
        ));
    };
    load::with_program(args.file, args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let request = Request {
            program,
            source,
            display: &display,
            sequences: args.sequences,
            from,
            options: args.options,
            model,
            epochs: args.epochs,
        };
        write_model(&request, args.out_dir)
    })
}

/// `dynarole compile --target promela`: writes DIR/model.pml (the compositional method:
/// DIR/model-MODULE.pml for each module).
fn write_model(req: &Request, out_dir: &Path) -> Result<ExitCode, Failure> {
    let (built, _, _) = match build(req, None)? {
        Ok(b) => b,
        Err(code) => return Ok(code),
    };
    std::fs::create_dir_all(out_dir)
        .map_err(|e| Failure::Input(format!("cannot create {}: {e}", out_dir.display())))?;
    let mut written = Vec::new();
    for (name, model) in built.model_files() {
        let path = out_dir.join(name);
        std::fs::write(&path, &model.text)
            .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))?;
        written.push(path.display().to_string());
    }
    let what = match built.models {
        Models::Full(_) => "model",
        Models::Compositional { .. } => "compositional models",
    };
    println!(
        "{what} of {}: {} statements, {} modules, {} links -> {}",
        built.name,
        built.ir.statements.len(),
        built.topology.modules.len(),
        built.topology.links.len(),
        written.join(", ")
    );
    Ok(ExitCode::SUCCESS)
}
