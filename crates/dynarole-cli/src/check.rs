//! `dynarole check`: report every problem in every file.

use crate::load::{self, Failure, PluginArgs};
use crate::render;
use dynarole_codegen::Protocol;
use dynarole_core::diagnostic::has_errors;
use dynarole_core::{driver, parse, Diagnostic};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `--from CONFIG [--sequence NAME...]`: run the sequences on a configuration too.
pub struct OnConfiguration<'a> {
    pub path: &'a Path,
    pub sequences: &'a [String],
}

/// What `check` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct CheckArgs {
    /// The `.dr` files to check.
    #[arg(value_name = "FILE")]
    pub files: Vec<std::path::PathBuf>,
    #[command(flatten)]
    pub plugins: crate::load::PluginArgs,
    /// Also report what the given protocol cannot run.
    #[arg(long, value_parser = crate::compile::choice::<dynarole_codegen::Protocol>(), default_value_t = dynarole_codegen::Protocol::Lattice)]
    pub protocol: dynarole_codegen::Protocol,
    /// Also run the sequences on this configuration: report refused and suspicious steps,
    /// and `&`-joined statements that are not independent.
    #[arg(long, value_name = "CONFIG")]
    pub from: Option<std::path::PathBuf>,
    /// With --from: the sequences to run, in turn (default: the first in the file).
    #[arg(long = "sequence", value_name = "NAME", requires = "from")]
    pub sequences: Vec<String>,
}

pub fn run(args: &CheckArgs) -> Result<ExitCode, Failure> {
    let on = args.from.as_deref().map(|path| OnConfiguration {
        path,
        sequences: &args.sequences,
    });
    check_files(&args.files, &args.plugins, args.protocol, on.as_ref())
}

fn check_files(
    files: &[PathBuf],
    plugins: &PluginArgs,
    protocol: Protocol,
    on: Option<&OnConfiguration>,
) -> Result<ExitCode, Failure> {
    if files.is_empty() {
        return Err(Failure::Usage(
            "no files given: `dynarole check FILE...`".into(),
        ));
    }
    let mut failed = false;
    for path in files {
        let source = load::read_source(path)?;
        let diagnostics = check_one(path, &source, plugins, protocol, on)?;
        render::diagnostics(&path.display().to_string(), &source, &diagnostics);
        if has_errors(&diagnostics) {
            failed = true;
        } else {
            println!("ok: {}", path.display());
        }
    }
    Ok(ExitCode::from(u8::from(failed)))
}

/// Every diagnostic of one file: syntax, checking, protocol limits and, with a configuration,
/// the replay's refused steps and the independence warnings.
pub fn check_one(
    path: &Path,
    source: &str,
    plugins: &PluginArgs,
    protocol: Protocol,
    on: Option<&OnConfiguration>,
) -> Result<Vec<Diagnostic>, Failure> {
    let parsed = parse(source);
    let registry = load::registry(plugins, path, load::robot_name(&parsed.file))?;
    let (program, mut diagnostics) = driver::analyze_all(&parsed, &registry);
    if let (Some(program), Some(on)) = (&program, on) {
        diagnostics.extend(on_configuration(program, path, on, protocol)?);
    } else if protocol.needs_routes() && program.is_some() {
        eprintln!(
            "note: {}: the {}'s hand-over routes are checked only on a configuration (--from CONFIG)",
            path.display(),
            protocol.info().description
        );
    }
    if let Some(program) = program {
        diagnostics.extend(dynarole_codegen::target_limits(&program, protocol));
    }
    diagnostics.sort_by_key(|d| d.span);
    diagnostics.dedup();
    Ok(diagnostics)
}

fn on_configuration(
    program: &dynarole_core::Program,
    path: &Path,
    on: &OnConfiguration,
    protocol: Protocol,
) -> Result<Vec<Diagnostic>, Failure> {
    let config = crate::world::read_configuration(on.path)?;
    let display = path.display().to_string();
    match crate::world::prepare(program, &display, on.sequences, config)? {
        Ok(prepared) => Ok(prepared.diagnose(program, protocol.needs_routes())),
        Err(errors) => Ok(errors),
    }
}
