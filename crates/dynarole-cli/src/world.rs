//! Shared by the commands that run sequences on a configuration (`replay`, `check --from`,
//! `simulate`, `parallelise`, `verify`): their arguments, the configuration read, and
//! `dynarole_replay::prepare`'s errors turned into the command's.

use crate::load::{self, Failure};
use dynarole_core::expand::Plan;
use dynarole_core::{Diagnostic, Program};
use dynarole_replay::PrepareError;
pub use dynarole_replay::Prepared;
use dynarole_world::Configuration;
use std::path::Path;

/// `--sequence NAME... --from CONFIG [--expect CONFIG]`, shared by `replay` and `simulate`.
#[derive(clap::Args, Clone, Debug)]
pub struct RunArgs {
    /// Sequence to run; repeat to run several in turn (default: the first in the file).
    #[arg(long = "sequence", value_name = "NAME")]
    pub sequences: Vec<String>,
    /// The configuration to start from (JSON).
    #[arg(long, value_name = "CONFIG")]
    pub from: std::path::PathBuf,
    /// The configuration the run must end in (up to rigid motion; a lattice robot's cells in place).
    #[arg(long, value_name = "CONFIG")]
    pub expect: Option<std::path::PathBuf>,
}

/// Reads a configuration in the data-file JSON format; errors name the file and the field.
pub fn read_configuration(path: &Path) -> Result<Configuration, Failure> {
    let text = load::read_source(path)?;
    crate::robots::robots()
        .read_configuration(&text)
        .map_err(|e| Failure::Input(format!("{}: {e}", path.display())))
}

/// The sequences (the first declared when none is named) of the source `display` prepared
/// to run on `config`; label problems come back as diagnostics of the source file.
pub fn prepare(
    program: &Program,
    display: &str,
    sequences: &[String],
    config: Configuration,
) -> Result<Result<Prepared, Vec<Diagnostic>>, Failure> {
    match dynarole_replay::prepare(program, sequences, config) {
        Ok(prepared) => Ok(Ok(prepared)),
        Err(PrepareError::Labels(diagnostics)) => Ok(Err(diagnostics)),
        Err(PrepareError::Select(e)) => Err(load::selection(&e, display)),
        Err(PrepareError::World(message)) => Err(Failure::Input(message)),
    }
}

/// The expanded plans of sequences chosen by [`load::select_sequences`].
pub fn plans(program: &Program, display: &str, names: &[String]) -> Result<Vec<Plan>, Failure> {
    dynarole_core::driver::plans(program, names).map_err(|e| load::selection(&e, display))
}
