//! Replay: the statements of one or more plans executed one group at a time on the model.

use crate::lockstep;
use crate::robot_world::RobotWorld;
use crate::roles::Assignment;
use dynarole_core::diagnostic::{Diagnostic, DiagnosticKind};
use dynarole_core::expand::{Plan, PlanKind};
use dynarole_core::{Program, Span};

/// The end of a replay: the robot as it ends and every refused or suspicious step.
#[derive(Clone, Debug)]
pub struct Replay {
    /// The robot after the last step (`final_world.configuration()` in the file format).
    pub final_world: RobotWorld,
    pub diagnostics: Vec<Diagnostic>,
    pub n_statements: usize,
    pub n_rejected: usize,
}

/// Runs `plans` one after the other from the world's configuration. Groups run in order and
/// the elements of a group in source order (the model has no time; the independence check
/// says whether the order matters). A refused step changes nothing and the replay goes on, so
/// that every problem is reported at once.
pub fn replay(
    program: &Program,
    plans: &[Plan],
    mut world: RobotWorld,
    assignment: &Assignment,
) -> Replay {
    let mut steps = Steps::default();
    for plan in plans {
        run_plan(program, plan, &mut world, assignment, &mut steps);
    }
    Replay {
        final_world: world,
        diagnostics: steps.diagnostics,
        n_statements: steps.n_statements,
        n_rejected: steps.n_rejected,
    }
}

/// What the steps of a replay found so far.
#[derive(Default)]
struct Steps {
    diagnostics: Vec<Diagnostic>,
    n_statements: usize,
    n_rejected: usize,
}

fn run_plan(
    program: &Program,
    plan: &Plan,
    world: &mut RobotWorld,
    assignment: &Assignment,
    report: &mut Steps,
) {
    for element in &plan.elements {
        match &element.kind {
            PlanKind::Block(inner) if inner.synchronous => {
                run_synchronous(program, (inner, element.span), world, assignment, report)
            }
            PlanKind::Block(inner) => run_plan(program, inner, world, assignment, report),
            PlanKind::Op(statement) => {
                report.n_statements += 1;
                let Some(module) = assignment.get(&statement.label) else {
                    continue;
                };
                let step = statement.describe(&program.robot);
                match world.apply(&program.robot, statement, module) {
                    Ok(outcome) => {
                        for warning in outcome.warnings {
                            let kind = DiagnosticKind::StepSuspicious {
                                step: step.clone(),
                                reason: warning.to_string(),
                            };
                            report
                                .diagnostics
                                .push(Diagnostic::new(kind, statement.span));
                        }
                    }
                    Err(reason) => {
                        report.n_rejected += 1;
                        report.diagnostics.push(Diagnostic::new(
                            DiagnosticKind::StepRejected { step, reason },
                            statement.span,
                        ));
                    }
                }
            }
        }
    }
}

/// A synchronous group: its turns checked together along the lock-step timing and done as
/// one step (`lockstep.rs`); refused whole, changing nothing, or done whole.
fn run_synchronous(
    program: &Program,
    (plan, span): (&Plan, Span),
    world: &mut RobotWorld,
    assignment: &Assignment,
    report: &mut Steps,
) {
    report.n_statements += plan.statements().len();
    let mut warnings = Vec::new();
    let step = || lockstep::describe(program, plan);
    match lockstep::apply_synchronous(program, plan, world, assignment, &mut warnings) {
        Ok(()) => {
            for (step, warning) in warnings {
                let kind = DiagnosticKind::StepSuspicious {
                    step,
                    reason: warning.to_string(),
                };
                report.diagnostics.push(Diagnostic::new(kind, span));
            }
        }
        Err(reason) => {
            report.n_rejected += 1;
            let kind = DiagnosticKind::StepRejected {
                step: step(),
                reason,
            };
            report.diagnostics.push(Diagnostic::new(kind, span));
        }
    }
}
