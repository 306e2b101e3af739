//! The dynarole command-line tool as a library: argument parsing and one module per subcommand.
//!
//! **Architecture invariant**: only this crate knows about files, exit codes and colours.

pub mod check;
pub mod fmt;
pub mod load;
pub mod render;
pub mod reverse;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// dynarole: robust and reversible self-reconfiguration of modular robots.
#[derive(Parser)]
#[command(name = "dynarole", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check `.dr` files: syntax, names, types, reversibility. Exit 1 on any error.
    Check {
        files: Vec<PathBuf>,
        #[command(flatten)]
        plugins: load::PluginArgs,
        /// Also report what the given protocol cannot run.
        #[arg(long, value_enum, default_value_t = check::Protocol::Lattice)]
        protocol: check::Protocol,
    },
    /// Rewrite `.dr` files in the canonical layout (comments kept).
    Fmt {
        files: Vec<PathBuf>,
        /// Change nothing; exit 1 if a file is not formatted.
        #[arg(long)]
        check: bool,
    },
    /// Print the reverse of SEQUENCE as a complete `.dr` file that `check` accepts.
    Reverse {
        file: PathBuf,
        sequence: String,
        /// Name of the reversed sequence (default: the file's `X = reverse SEQUENCE`,
        /// else `b2a` for `a2b`, else `SEQUENCE_reversed`).
        #[arg(long)]
        name: Option<String>,
        #[command(flatten)]
        plugins: load::PluginArgs,
    },
}

/// Runs the command line; the exit code follows the README (0 ok, 1 bad input, 2 usage).
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Check {
            files,
            plugins,
            protocol,
        } => check::run(&files, &plugins, protocol),
        Command::Fmt { files, check } => fmt::run(&files, check),
        Command::Reverse {
            file,
            sequence,
            name,
            plugins,
        } => reverse::run(&file, &sequence, name.as_deref(), &plugins),
    };
    match outcome {
        Ok(code) => code,
        Err(failure) => {
            render::failure(&failure);
            failure.exit_code()
        }
    }
}
