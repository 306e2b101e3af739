//! The contract of a synchronous group (`sync { A & B; }`): how long its turns take and how
//! far apart in time they may start, which the checks verify and the runtime and the
//! simulator keep.
//!
//! Lock-step: every turn of the group takes as long as its longest one (each moves at the
//! pace that makes it so), and each starts within [`SKEW_PER_HOP_MS`] per hop between the
//! group's modules of the others: the runtime's countdown (runtime/lattice/README.md,
//! "Synchronous groups") is late at a module by the transit times of the packets that
//! brought it the news, one per hop. A turn's fraction grows linearly in time, so two turns'
//! fractions never differ by more than the skew over the group's duration. The check takes
//! the shortest duration any timing preset of the robot gives the group: the widest band, so
//! its verdict holds under every preset.

use crate::check::ResolvedStatement;
use crate::robot::{Durations, OperationKind, RobotApi, Value};

/// The most the start of a synchronous group's turns may spread per hop (latched link)
/// between its two farthest modules, in ms: a frame's transit, one frame queued before it
/// included (measured in docs/benchmarks.md, "Synchronous groups").
pub const SKEW_PER_HOP_MS: u64 = 50;

/// Quarter turns `statement`, a turn from a stated angle, passes through; `None` for
/// anything else (a synchronous group holds only such turns: the checker says so).
pub fn quarter_turns(robot: &RobotApi, statement: &ResolvedStatement) -> Option<u64> {
    if robot.kind(statement.part, statement.operation) != OperationKind::Turn {
        return None;
    }
    match statement.args.as_slice() {
        [Value::Int(from), Value::Int(to), Value::Bool(increasing), ..] => {
            Some(robot.joint_angle.quarter_turns(*from, *to, *increasing))
        }
        _ => None,
    }
}

/// How long every turn of the group `members` takes with `durations`: its longest turn's.
pub fn lockstep_ms(robot: &RobotApi, durations: Durations, members: &[&ResolvedStatement]) -> u64 {
    (members.iter())
        .filter_map(|s| quarter_turns(robot, s))
        .map(|q| durations.turn_ms(q))
        .max()
        .unwrap_or(0)
}

/// How far apart the fractions of the group's turns may be (0 to 1) when its two farthest
/// modules are `hops` latched links apart: the start skew over the group's shortest
/// lock-step duration under the robot's timing presets; 1 (any timing) when that is 0.
pub fn fraction_skew(robot: &RobotApi, members: &[&ResolvedStatement], hops: usize) -> f64 {
    let shortest_ms = (robot.timing_presets().iter())
        .map(|(_, durations)| lockstep_ms(robot, *durations, members))
        .min()
        .unwrap_or(0);
    if shortest_ms == 0 {
        return 1.0;
    }
    let skew_ms = SKEW_PER_HOP_MS.saturating_mul(hops as u64);
    (skew_ms as f64 / shortest_ms as f64).min(1.0)
}
