//! Shared by the commands that run sequences on a configuration (`replay`, `check --from`):
//! load the configuration, expand the sequences, and find the module behind every label.

use crate::load::{self, Failure};
use dynarole_core::expand::Plan;
use dynarole_core::{Diagnostic, Program};
use dynarole_replay::{assign_modules, Assignment, RobotWorld};
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
    /// The configuration the run must end in (up to rigid motion).
    #[arg(long, value_name = "CONFIG")]
    pub expect: Option<std::path::PathBuf>,
}

/// Everything needed to run `plans` on the model.
pub struct Prepared {
    /// The sequences run, in turn (the named ones, or the file's first).
    pub names: Vec<String>,
    pub plans: Vec<Plan>,
    pub assignment: Assignment,
    pub world: RobotWorld,
    /// The configuration the world starts from.
    pub start: Configuration,
}

/// Reads a configuration in the data-file JSON format; errors name the file and the field.
pub fn read_configuration(path: &Path) -> Result<Configuration, Failure> {
    let text = load::read_source(path)?;
    Configuration::from_json_str(&text)
        .map_err(|e| Failure::Input(format!("{}: {e}", path.display())))
}

/// The plans of `sequences` (the first declared sequence when none is named) of the source
/// `display`, the modules of their labels on `config`, and the world to run them in. Label
/// problems come back as diagnostics of the source file.
pub fn prepare(
    program: &Program,
    display: &str,
    sequences: &[String],
    config: Configuration,
) -> Result<Result<Prepared, Vec<Diagnostic>>, Failure> {
    let names = load::select_sequences(program, display, sequences)?;
    let plans = plans(program, display, &names)?;
    let world = RobotWorld::new(config.clone(), &program.robot).map_err(Failure::Input)?;
    Ok(
        assign_modules(program, &plans, &config).map(|assignment| Prepared {
            names,
            plans,
            assignment,
            world,
            start: config,
        }),
    )
}

/// The expanded plans of sequences chosen by [`load::select_sequences`].
pub fn plans(program: &Program, display: &str, names: &[String]) -> Result<Vec<Plan>, Failure> {
    dynarole_core::driver::plans(program, names).map_err(|e| load::selection(&e, display))
}
