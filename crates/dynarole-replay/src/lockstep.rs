//! A synchronous group (`sync { A & B; }`) on the model: its turns moved together along the
//! lock-step timing (`dynarole_core::synchronous`), checked as one motion over that band of
//! timings, then applied without their own sweeps, which the band's search includes.

use crate::robot_world::{RobotWorld, Warned};
use crate::roles::Assignment;
use crate::simultaneous::{turns_at, Approach, Pairs, Timings, Together};
use dynarole_core::check::ResolvedStatement;
use dynarole_core::expand::Plan;
use dynarole_core::synchronous::{fraction_skew, SKEW_PER_HOP_MS};
use dynarole_core::Program;
use dynarole_world::{Motion, SweepCheck};
use std::collections::VecDeque;

/// Does the synchronous group `plan` on `world`, adding the model's warnings to `warnings`;
/// the error says why it is refused, and then `world` is unchanged.
pub(crate) fn apply_synchronous(
    program: &Program,
    plan: &Plan,
    world: &mut RobotWorld,
    assignment: &Assignment,
    warnings: &mut Vec<Warned>,
) -> Result<(), String> {
    let robot = &program.robot;
    let statements = plan.statements();
    let mut members = Vec::with_capacity(statements.len());
    for statement in &statements {
        let module = assignment
            .get(&statement.label)
            .ok_or_else(|| format!("`{}`: no module for its label", statement.describe(robot)))?;
        members.push((
            *statement,
            module.as_str(),
            motion(program, statement, module, world)?,
        ));
    }
    let statements: Vec<&ResolvedStatement> = members.iter().map(|(s, _, _)| *s).collect();
    let turners: Vec<usize> = members.iter().map(|(_, _, (_, turner))| *turner).collect();
    let hops = farthest_apart(world, &turners);
    let skew = fraction_skew(robot, &statements, hops);
    check_together(&members, world, (skew, hops))?;
    let mut after = world.clone();
    for (statement, module, _) in &members {
        let outcome = after
            .apply_swept(robot, statement, module, SweepCheck::WithOthers)
            .map_err(|reason| format!("`{}`: {reason}", statement.describe(robot)))?;
        let text = statement.describe(robot);
        warnings.extend(outcome.warnings.into_iter().map(|w| (text.clone(), w)));
    }
    *world = after;
    Ok(())
}

/// The motion of one member from where the group starts, with its module's index; the error
/// is why the model refuses it (found by trying it alone on a copy).
fn motion(
    program: &Program,
    statement: &ResolvedStatement,
    module: &str,
    world: &RobotWorld,
) -> Result<(Motion, usize), String> {
    let robot = &program.robot;
    let turner = world.view().index(module);
    match (world.motion(robot, statement, module), turner) {
        (Some(motion), Some(turner)) => Ok((motion, turner)),
        _ => {
            let reason = world.clone().apply(robot, statement, module).err();
            let reason = reason.unwrap_or_else(|| "the model gives no motion for it".into());
            Err(format!("`{}`: {reason}", statement.describe(robot)))
        }
    }
}

/// The members' turns that move something, searched together over the lock-step timings:
/// fractions at most `skew` apart, the start skew of modules `hops` links apart.
fn check_together(
    members: &[(&ResolvedStatement, &str, (Motion, usize))],
    world: &RobotWorld,
    (skew, hops): (f64, usize),
) -> Result<(), String> {
    let turns: Vec<(&Motion, usize)> = (members.iter())
        .map(|(_, _, (motion, turner))| (motion, *turner))
        .filter(|(motion, _)| motion.moves())
        .collect();
    if turns.is_empty() {
        return Ok(());
    }
    let timings = Timings {
        lockstep: vec![Some(0); turns.len()],
        skew,
    };
    let limit = turns.iter().map(|(m, _)| m.limit).fold(0.0, f64::max);
    let unit = world.model().length_unit();
    let names = |a: &Approach| {
        let view = world.view();
        (view.name(a.modules.0), view.name(a.modules.1))
    };
    let skew_ms = SKEW_PER_HOP_MS.saturating_mul(hops as u64);
    let band = format!("moving in lock-step (started within {skew_ms} ms of each other)");
    match turns_at(&turns, world, &timings, Pairs::All) {
        Some(Together::Clear) => Ok(()),
        Some(Together::Closest(Approach { rule: Some(rule), .. })) => Err(format!("{band}, {rule}")),
        Some(Together::Closest(a)) => {
            let ((x, y), d) = (names(&a), a.distance);
            Err(format!("{band}, the turns bring {x} and {y} within {d:.3} {unit} of each other (limit {limit})"))
        }
        Some(Together::Unproven(a)) => {
            let ((x, y), d) = (names(&a), a.distance);
            Err(format!("{band}, the turns could not be proven to keep {x} and {y} {limit} {unit} apart (lower bound {d:.3})"))
        }
        None => Err("its turns cannot be checked together: they are not each one rotation of whole parts of a tree of modules that the robot's model gives points for".into()),
    }
}

/// The most latched links between two of the modules `turners` on `world` (the links the
/// simulator's packets take, `topology.rs`); every module when some are not linked at all.
fn farthest_apart(world: &RobotWorld, turners: &[usize]) -> usize {
    let n = world.view().len();
    let mut next: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (from, to) in crate::topology::links(world) {
        next[from].push(to);
    }
    let mut farthest = 0;
    for &start in turners {
        let mut hops = vec![usize::MAX; n];
        let mut queue = VecDeque::from([start]);
        hops[start] = 0;
        while let Some(m) = queue.pop_front() {
            for &k in &next[m] {
                if hops[k] == usize::MAX {
                    hops[k] = hops[m] + 1;
                    queue.push_back(k);
                }
            }
        }
        for &other in turners {
            farthest = farthest.max(if hops[other] == usize::MAX {
                n
            } else {
                hops[other]
            });
        }
    }
    farthest
}

/// `sync { A & B; }`, as a step is named in messages (what the source would say).
pub(crate) fn describe(program: &Program, plan: &Plan) -> String {
    let steps: Vec<String> = (plan.statements().iter())
        .map(|s| s.describe(&program.robot))
        .collect();
    format!("sync {{ {}; }}", steps.join(" & "))
}
