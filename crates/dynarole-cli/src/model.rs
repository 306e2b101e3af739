//! The model of `verify` and `compile --target promela`: the arguments that bound the
//! environment, turned into `dynarole_verify`'s options; the configuration read and the
//! sequences modelled; the library's errors turned into exit codes; and the model files that
//! `compile --target promela` writes.

pub use crate::bounds::{MethodArg, ModelArgs};
use crate::compile::{CompileArgs, ProtocolOptions};
use crate::load::{self, Failure, PluginArgs};
use crate::world::{prepare, read_configuration};
use dynarole_codegen::Fault;
use dynarole_verify::{BuildOptions, Built, Inputs, Method, Models, VerifyError};
use std::path::Path;
use std::process::ExitCode;

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

/// What a model is asked of, as `verify` and `compile --target promela` give it: a source
/// file (and the plugins it may need), its sequences, a configuration, options.
pub struct Asked<'a> {
    pub file: &'a Path,
    pub plugins: &'a PluginArgs,
    pub sequences: &'a [String],
    pub from: &'a Path,
    pub options: &'a ProtocolOptions,
    pub model: &'a ModelArgs,
    pub epochs: u16,
}

/// What a model is made from: the checked source of what was asked.
pub struct Request<'a> {
    pub program: &'a dynarole_core::Program<'a>,
    pub source: &'a str,
    /// The source file's name in messages.
    pub display: &'a str,
    pub asked: &'a Asked<'a>,
}

/// Loads and checks the source `asked` names, then runs `then` on the request of its model
/// (a source that does not check is `Failure::Checked`, as in every command).
pub fn with_request<T>(
    asked: &Asked,
    then: impl FnOnce(&Request) -> Result<T, Failure>,
) -> Result<T, Failure> {
    load::with_program(asked.file, asked.plugins, |program, source| {
        let display = asked.file.display().to_string();
        then(&Request {
            program,
            source,
            display: &display,
            asked,
        })
    })
}

/// The library's options for these arguments; the model is named after `names`.
fn build_options(
    asked: &Asked,
    names: &[String],
    fault: Option<FaultArg>,
) -> Result<BuildOptions, Failure> {
    Ok(BuildOptions {
        compile: asked
            .options
            .compile_options(asked.epochs, names.join(" + "))?,
        method: match asked.model.method {
            MethodArg::Auto => Method::Auto,
            MethodArg::Full => Method::Full,
            MethodArg::Compositional => Method::Compositional,
        },
        resets: asked.model.resets,
        reset_only: asked.model.reset_only.clone(),
        late: asked.model.late,
        fault: fault.map(|f| match f {
            FaultArg::JoinDropsDone => Fault::JoinDropsDone,
            FaultArg::JoinNoRebase => Fault::JoinNoRebase,
        }),
    })
}

/// The failure of a library error; the source's problems are `Failure::Checked`.
pub fn failed(error: VerifyError, req: &Request) -> Failure {
    match error {
        VerifyError::Source(diagnostics) => Failure::checked(req.display, req.source, diagnostics),
        VerifyError::Input(m) => Failure::Input(m),
        VerifyError::Usage(m) => Failure::Usage(m),
        VerifyError::Internal(m) => Failure::Internal(m),
        // Only the library's callers ask a check to stop (Ctrl-C in Python).
        e @ VerifyError::Interrupted => Failure::Input(e.to_string()),
    }
}

/// Reads the configuration, expands the sequences and models them.
pub fn build(
    req: &Request,
    fault: Option<FaultArg>,
) -> Result<(Built, BuildOptions, Scene), Failure> {
    let asked = req.asked;
    let config = read_configuration(asked.from)?;
    let prepared = match prepare(req.program, req.display, asked.sequences, config)? {
        Ok(p) => p,
        Err(diagnostics) => return Err(Failure::checked(req.display, req.source, diagnostics)),
    };
    let options = build_options(asked, &prepared.names, fault)?;
    let configuration = asked.from.display().to_string();
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
        Ok(built) => Ok((built, options, scene)),
        Err(e) => Err(failed(e, req)),
    }
}

/// `dynarole compile --target promela`: the model of the sequences on `--from CONFIG`.
pub fn compile(args: &CompileArgs) -> Result<ExitCode, Failure> {
    let Some(from) = &args.from else {
        return Err(Failure::Usage(
            "--target promela needs --from CONFIG (the model is of a robot's communication graph)"
                .into(),
        ));
    };
    let asked = Asked {
        file: &args.file,
        plugins: &args.plugins,
        sequences: &args.sequences,
        from,
        options: &args.options,
        model: &args.model,
        epochs: args.epochs,
    };
    with_request(&asked, |request| write_model(request, &args.out_dir))
}

/// `dynarole compile --target promela`: writes DIR/model.pml (the compositional method:
/// DIR/model-MODULE.pml for each module).
fn write_model(req: &Request, out_dir: &Path) -> Result<ExitCode, Failure> {
    let (built, _, _) = build(req, None)?;
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
