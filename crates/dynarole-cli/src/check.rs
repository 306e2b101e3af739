//! `dynarole check`: report every problem in every file.

use crate::load::{self, Failure, PluginArgs};
use crate::render;
use dynarole_core::diagnostic::has_errors;
use dynarole_core::{analyze, parse, Diagnostic};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Protocol {
    /// The paper's protocol: one pending set, no nested blocks.
    Paper,
    /// dynarole's own protocol (runs every sequence the language accepts).
    Lattice,
}

pub fn run(
    files: &[PathBuf],
    plugins: &PluginArgs,
    protocol: Protocol,
) -> Result<ExitCode, Failure> {
    if files.is_empty() {
        return Err(Failure::Usage(
            "no files given: `dynarole check FILE...`".into(),
        ));
    }
    let mut failed = false;
    for path in files {
        let source = load::read_source(path)?;
        let diagnostics = check_one(path, &source, plugins, protocol)?;
        render::diagnostics(&path.display().to_string(), &source, &diagnostics);
        if has_errors(&diagnostics) {
            failed = true;
        } else {
            println!("ok: {}", path.display());
        }
    }
    Ok(ExitCode::from(u8::from(failed)))
}

pub fn check_one(
    path: &std::path::Path,
    source: &str,
    plugins: &PluginArgs,
    protocol: Protocol,
) -> Result<Vec<Diagnostic>, Failure> {
    let parsed = parse(source);
    let registry = load::registry(plugins, path, load::robot_name(&parsed.file))?;
    let (program, mut diagnostics) = analyze(&parsed.file, &registry);
    diagnostics.extend(parsed.diagnostics);
    if let (Some(program), Protocol::Paper) = (program, protocol) {
        for decl in parsed.file.sequences() {
            let plan = program.expand(&decl.name.name).unwrap_or_default();
            if let Err(d) = plan.flatten_for_paper() {
                diagnostics.push(d);
            }
        }
    }
    diagnostics.sort_by_key(|d| d.span);
    diagnostics.dedup();
    Ok(diagnostics)
}
