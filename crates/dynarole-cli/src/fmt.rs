//! `dynarole fmt`: rewrite files in the canonical layout, or check that they are.

use crate::load::{self, Failure};
use crate::render;
use dynarole_core::diagnostic::has_errors;
use dynarole_core::format::format_file;
use dynarole_core::parse;
use std::path::PathBuf;
use std::process::ExitCode;

pub fn run(files: &[PathBuf], check_only: bool) -> Result<ExitCode, Failure> {
    if files.is_empty() {
        return Err(Failure::Usage(
            "no files given: `dynarole fmt [--check] FILE...`".into(),
        ));
    }
    let mut failed = false;
    for path in files {
        let source = load::read_source(path)?;
        let parsed = parse(&source);
        if has_errors(&parsed.diagnostics) {
            // Formatting a broken tree would drop the broken parts: refuse instead.
            render::diagnostics(&path.display().to_string(), &source, &parsed.diagnostics);
            failed = true;
            continue;
        }
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
