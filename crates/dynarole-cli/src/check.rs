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

pub fn run(
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
    } else if protocol == Protocol::Token && program.is_some() {
        eprintln!("note: {}: the token baseline's hand-over routes are checked only on a configuration (--from CONFIG)", path.display());
    }
    if let Some(program) = program {
        diagnostics.extend(target_limits(&program, protocol));
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
    let prepared = match crate::world::prepare(
        program,
        &path.display().to_string(),
        on.sequences,
        config.clone(),
    )? {
        Ok(prepared) => prepared,
        Err(errors) => return Ok(errors),
    };
    let replay = dynarole_replay::replay(
        program,
        &prepared.plans,
        prepared.world.clone(),
        &prepared.assignment,
    );
    let mut diagnostics = replay.diagnostics;
    if protocol == Protocol::Token && !has_errors(&diagnostics) {
        if let Err(unroutable) = dynarole_replay::token_routes(program, &prepared.plans, &config) {
            diagnostics.extend(unroutable);
        }
    }
    diagnostics.extend(dynarole_replay::check_independence(
        program,
        &prepared.plans,
        prepared.world,
        &prepared.assignment,
    ));
    Ok(diagnostics)
}

/// What the generated code of each sequence could not encode, for the chosen protocol.
fn target_limits(program: &dynarole_core::Program, protocol: Protocol) -> Vec<Diagnostic> {
    let shape = protocol.shape();
    let mut out = Vec::new();
    for decl in program.file.sequences() {
        let plan = program.expand(&decl.name.name).unwrap_or_default();
        let fits =
            driver::lower(program, std::slice::from_ref(&plan), shape).and_then(
                |ir| match protocol {
                    Protocol::Paper => ir.paper_layout().map(|_| ()).map_err(Diagnostic::from),
                    Protocol::Lattice | Protocol::Token => Ok(()),
                },
            );
        out.extend(fits.err());
    }
    out
}
