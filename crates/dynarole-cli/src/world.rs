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
    /// Sequence to run; repeat to run several in turn.
    #[arg(long = "sequence", value_name = "NAME", required = true)]
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
    pub plans: Vec<Plan>,
    pub assignment: Assignment,
    pub world: RobotWorld,
}

/// Reads a configuration in the data-file JSON format; errors name the file and the field.
pub fn read_configuration(path: &Path) -> Result<Configuration, Failure> {
    let text = load::read_source(path)?;
    Configuration::from_json_str(&text)
        .map_err(|e| Failure::Input(format!("{}: {e}", path.display())))
}

/// The plans of `sequences` (the first declared sequence when none is named), the modules of
/// their labels on `config`, and the world to run them in. Label problems come back as
/// diagnostics of the source file.
pub fn prepare(
    program: &Program,
    sequences: &[String],
    config: Configuration,
) -> Result<Result<Prepared, Vec<Diagnostic>>, Failure> {
    let names = crate::load::sequence_names(program, sequences);
    let mut plans = Vec::new();
    for name in &names {
        let plan = program
            .expand(name)
            .ok_or_else(|| Failure::Input(format!("no sequence named `{name}`")))?;
        plans.push(plan);
    }
    let world = RobotWorld::new(config.clone(), &program.robot).map_err(Failure::Input)?;
    Ok(
        assign_modules(program, &plans, &config).map(|assignment| Prepared {
            plans,
            assignment,
            world,
        }),
    )
}
