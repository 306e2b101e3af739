//! Makespans of sequences as the robot's default timing preset weighs them: the critical path of
//! their dependencies, no network. `dynarole parallelise` compares a sequence with the
//! parallel forms found for it by these, and keeps the shortest.

use crate::critical::critical_path;
use crate::scenario::default_durations;
use crate::sequence::Sequence;
use dynarole_codegen::Protocol;
use dynarole_core::expand::Plan;
use dynarole_core::{driver, parse, Program, RobotApi};
use dynarole_replay::{Form, Parallelised};

/// The critical path of `plans` in ms, as `protocol`'s code orders them: lowered for the
/// shapes it runs and weighed by the robot's default timing preset (`default_durations`). No C is generated: the critical path is a
/// property of the dependencies and durations alone.
pub fn makespan(program: &Program, plans: &[Plan], protocol: Protocol) -> Result<u64, String> {
    let ir =
        driver::lower(program, plans, protocol.shape()).map_err(|d| format!("{:?}", d.kind))?;
    let resolved = plans
        .iter()
        .flat_map(|p| p.statements().into_iter().cloned())
        .collect();
    let sequence = Sequence::new(program.robot.clone(), ir, resolved);
    let durations = default_durations(&program.robot);
    Ok(critical_path(&sequence, &durations).duration_ms)
}

/// The makespans of a parallelised sequence's written forms and the one to write.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Estimated {
    /// One estimate per form of `Parallelised::forms`, in their order.
    pub estimates: Vec<Result<u64, String>>,
    /// The index of the form to write: the shortest estimate (`shortest`).
    pub chosen: usize,
}

/// Estimates every form of `found` (sequence `name`) as `protocol`'s code would run it and
/// chooses the one to write.
pub fn choose_form(
    found: &Parallelised,
    name: &str,
    protocol: Protocol,
    robot: &RobotApi,
) -> Estimated {
    let estimates: Vec<Result<u64, String>> = (found.forms.iter())
        .map(|form| form_makespan(found, form, name, protocol, robot))
        .collect();
    let chosen = shortest(&estimates);
    Estimated { estimates, chosen }
}

/// The makespan of a written form of sequence `name`, from its text (what the user gets).
pub fn form_makespan(
    found: &Parallelised,
    form: &Form,
    name: &str,
    protocol: Protocol,
    robot: &RobotApi,
) -> Result<u64, String> {
    let source = format!("{}\n{}", found.header, form.text);
    let parsed = parse(&source);
    let program = driver::check_for(&parsed, robot).map_err(|diagnostics| {
        format!(
            "the output does not check ({} diagnostics)",
            diagnostics.len()
        )
    })?;
    let plan = program
        .expand(name)
        .ok_or_else(|| format!("no sequence `{name}` in the output"))?;
    makespan(&program, &[plan], protocol)
}

/// The index of the shortest estimate; the first on a tie or when none could be estimated.
pub fn shortest(estimates: &[Result<u64, String>]) -> usize {
    let mut best = 0;
    for (k, e) in estimates.iter().enumerate() {
        if let (Ok(ms), Ok(top)) = (e, &estimates[best]) {
            if ms < top {
                best = k;
            }
        } else if e.is_ok() && estimates[best].is_err() {
            best = k;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::shortest;

    #[test]
    fn the_shortest_estimate_wins_and_the_first_on_a_tie() {
        let e = |ms: &[Option<u64>]| -> Vec<Result<u64, String>> {
            ms.iter()
                .map(|m| m.ok_or_else(|| "no".to_string()))
                .collect()
        };
        assert_eq!(shortest(&e(&[Some(5), Some(3), Some(3)])), 1);
        assert_eq!(shortest(&e(&[None, Some(7)])), 1);
        assert_eq!(shortest(&e(&[None, None])), 0);
        assert_eq!(shortest(&e(&[Some(2), None])), 0);
    }
}
