//! `dynarole fmt`: rewrite files in the canonical layout, or check that they are.

use crate::check::check_one;
use crate::load::{self, Failure, PluginArgs};
use crate::render;
use dynarole_codegen::Protocol;
use dynarole_core::diagnostic::has_errors;
use dynarole_core::format::format_file;
use dynarole_core::parse;
use std::path::PathBuf;
use std::process::ExitCode;

/// Formats (or with `check_only`, checks the layout of) every file that `check` accepts; a
/// file `check` rejects is left alone and its errors reported, so the two commands agree on
/// what a valid file is.
/// What `fmt` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct FmtArgs {
    /// The `.dr` files to format in place.
    #[arg(value_name = "FILE")]
    pub files: Vec<std::path::PathBuf>,
    /// Change nothing; exit 1 if a file is not formatted.
    #[arg(long)]
    pub check: bool,
    #[command(flatten)]
    pub plugins: crate::load::PluginArgs,
}

pub fn run(args: &FmtArgs) -> Result<ExitCode, Failure> {
    format_files(&args.files, args.check, &args.plugins)
}

fn format_files(
    files: &[PathBuf],
    check_only: bool,
    plugins: &PluginArgs,
) -> Result<ExitCode, Failure> {
    if files.is_empty() {
        return Err(Failure::Usage(
            "no files given: `dynarole fmt [--check] FILE...`".into(),
        ));
    }
    let mut failed = false;
    for path in files {
        let source = load::read_source(path)?;
        let diagnostics = check_one(path, &source, plugins, Protocol::Lattice, None)?;
        if has_errors(&diagnostics) {
            // Formatting a broken tree would drop the broken parts: refuse instead.
            render::diagnostics(&path.display().to_string(), &source, &diagnostics);
            failed = true;
            continue;
        }
        let parsed = parse(&source);
        let formatted = format_file(&parsed.file, &source);
        if formatted == source {
            continue;
        }
        if check_only {
            println!("not formatted: {}", path.display());
            failed = true;
        } else {
            std::fs::write(path, formatted)
                .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))?;
            println!("formatted: {}", path.display());
        }
    }
    Ok(ExitCode::from(u8::from(failed)))
}
