//! `dynarole reverse`: print the reverse of a sequence as a complete, checkable file.

use crate::load::{self, Failure, PluginArgs};
use dynarole_core::format::format_items;
use dynarole_core::standalone::standalone;
use std::path::Path;
use std::process::ExitCode;

/// What `reverse` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct ReverseArgs {
    /// The `.dr` file holding the sequence.
    pub file: std::path::PathBuf,
    /// The sequence to reverse.
    pub sequence: String,
    /// Name of the reversed sequence (default: the file's `X = reverse SEQUENCE`,
    /// else `b2a` for `a2b`, else `SEQUENCE_reversed`).
    #[arg(long)]
    pub name: Option<String>,
    #[command(flatten)]
    pub plugins: crate::load::PluginArgs,
}

pub fn run(args: &ReverseArgs) -> Result<ExitCode, Failure> {
    let text = reverse_text(
        &args.file,
        &args.sequence,
        args.name.as_deref(),
        &args.plugins,
    )?;
    print!("{text}");
    Ok(ExitCode::SUCCESS)
}

/// The reverse of `sequence` in the file at `path` as a complete, checkable file (what
/// `dynarole reverse` prints), named `name` or by the file's convention.
pub fn reverse_text(
    path: &Path,
    sequence: &str,
    name: Option<&str>,
    plugins: &PluginArgs,
) -> Result<String, Failure> {
    if let Some(name) = name.filter(|n| !dynarole_core::lexer::is_identifier(n)) {
        return Err(Failure::Usage(format!(
            "--name `{}`: expected a name (a letter or `_`, then letters, digits or `_`; not a keyword)",
            name.escape_debug()
        )));
    }
    load::with_program(path, plugins, |program, source| {
        let display = path.display().to_string();
        reverse_in(program, source, &display, sequence, name)
    })
}

fn reverse_in(
    program: &dynarole_core::Program,
    source: &str,
    display: &str,
    sequence: &str,
    name: Option<&str>,
) -> Result<String, Failure> {
    let new_name = name.map_or_else(|| program.reverse_name(sequence), str::to_string);
    let reversed = match program.reverse_sequence(sequence, &new_name) {
        None => return Err(load::unknown_sequence(program, display, sequence)),
        Some(Err(errors)) => return Err(Failure::checked(display, source, errors)),
        Some(Ok(decl)) => decl,
    };
    let items = standalone(program.file, reversed).map_err(|taken| {
        Failure::Usage(format!(
            "`{taken}` is already used by a sequence the reverse needs; choose another with --name"
        ))
    })?;
    Ok(format_items(items))
}
