//! What every run of sequences on a configuration starts from (`replay`, `check --from`,
//! `parallelise`, `verify`): the sequences chosen, their plans, the module behind every
//! label, and the world to run them in; and what `check --from` reports of such a run.

use crate::{assign_modules, check_independence, replay, token_routes, Assignment, RobotWorld};
use dynarole_core::check::ResolvedStatement;
use dynarole_core::diagnostic::has_errors;
use dynarole_core::driver::{self, SelectError};
use dynarole_core::expand::Plan;
use dynarole_core::{Diagnostic, Program};
use dynarole_world::Configuration;

/// Everything needed to run `plans` on the model.
pub struct Prepared {
    /// The sequences run, in turn (the named ones, or the file's first).
    pub names: Vec<String>,
    pub plans: Vec<Plan>,
    pub assignment: Assignment,
    pub world: RobotWorld,
    /// The configuration as given (the world's starting point).
    pub start: Configuration,
}

/// Why sequences cannot be run on a configuration.
#[derive(Debug)]
pub enum PrepareError {
    /// No such sequence (the command line names one the file lacks).
    Select(SelectError),
    /// The configuration is not of the program's robot.
    World(String),
    /// Labels without exactly one module, as diagnostics of the source.
    Labels(Vec<Diagnostic>),
}

/// The sequences `wanted` (the first declared when none is named) of `program`, prepared to
/// run on `config`.
pub fn prepare(
    program: &Program,
    wanted: &[String],
    config: Configuration,
) -> Result<Prepared, PrepareError> {
    let names = driver::select_sequences(program, wanted).map_err(PrepareError::Select)?;
    let plans = driver::plans(program, &names).map_err(PrepareError::Select)?;
    let world = RobotWorld::new(config.clone(), &program.robot).map_err(PrepareError::World)?;
    let assignment = assign_modules(program, &plans, &config).map_err(PrepareError::Labels)?;
    Ok(Prepared {
        names,
        plans,
        assignment,
        world,
        start: config,
    })
}

impl Prepared {
    /// The statements of the plans in order (the numbering of lowered statements).
    pub fn statements(&self) -> Vec<ResolvedStatement> {
        self.plans
            .iter()
            .flat_map(|p| p.statements().into_iter().cloned())
            .collect()
    }

    /// What a run of the sequences on the model shows: refused and suspicious steps, with
    /// `routes` (the token baseline) the statements whose hand-over has no chain of latched
    /// modules (only when nothing was refused), and the `&`-joined statements that are not
    /// independent.
    pub fn diagnose(&self, program: &Program, routes: bool) -> Vec<Diagnostic> {
        let run = replay(program, &self.plans, self.world.clone(), &self.assignment);
        let mut diagnostics = run.diagnostics;
        if routes && !has_errors(&diagnostics) {
            if let Err(unroutable) = token_routes(program, &self.plans, &self.start) {
                diagnostics.extend(unroutable);
            }
        }
        diagnostics.extend(check_independence(
            program,
            &self.plans,
            self.world.clone(),
            &self.assignment,
        ));
        diagnostics
    }
}
