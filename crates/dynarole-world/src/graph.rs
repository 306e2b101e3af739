//! Connectivity through latches: which modules turn with a hemisphere, whether a joint is
//! locked by a loop, and whether releasing a latch splits the robot.

use crate::config::Latch;
use std::collections::{BTreeMap, BTreeSet, VecDeque};

/// Modules reachable from `starts` through latches without entering `barrier`.
pub(crate) fn reachable(
    latches: &BTreeSet<Latch>,
    starts: &BTreeSet<usize>,
    barrier: Option<usize>,
) -> BTreeSet<usize> {
    let mut seen: BTreeSet<usize> = starts
        .iter()
        .copied()
        .filter(|m| Some(*m) != barrier)
        .collect();
    // Adjacency first, so the search is linear in the size of the robot rather than
    // (modules x latches).
    let mut adjacent: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for latch in latches {
        let (a, b) = (latch.male.module, latch.female.module);
        adjacent.entry(a).or_default().push(b);
        adjacent.entry(b).or_default().push(a);
    }
    let mut queue: VecDeque<usize> = seen.iter().copied().collect();
    while let Some(current) = queue.pop_front() {
        for &next in adjacent.get(&current).map(Vec::as_slice).unwrap_or(&[]) {
            if Some(next) != barrier && seen.insert(next) {
                queue.push_back(next);
            }
        }
    }
    seen
}

/// The modules latched directly to the connectors of `module` selected by `half`.
fn neighbours_on(
    latches: &BTreeSet<Latch>,
    module: usize,
    half: fn(u8) -> bool,
) -> BTreeSet<usize> {
    let mut out = BTreeSet::new();
    for latch in latches {
        for (own, other) in [(latch.male, latch.female), (latch.female, latch.male)] {
            if own.module == module && half(own.connector) {
                out.insert(other.module);
            }
        }
    }
    out
}

/// The two sides of a joint of `module`: modules attached (transitively) to the connectors
/// selected by `first_half`, and those attached to the others.
pub(crate) struct Sides {
    /// Modules that turn with the first half (north).
    pub first: BTreeSet<usize>,
    /// Modules that turn with the second half (south).
    pub second: BTreeSet<usize>,
}

impl Sides {
    /// The side that turns when the joint angle changes by `joint_quarters`, its signed quarter
    /// turns about the joint axis, and whether it is the first side. The side with fewer
    /// modules moves (tie: the first, north one); the joint angle measures the second side
    /// against the first, so the first side turns the opposite way.
    pub(crate) fn moving(self, joint_quarters: i32) -> (BTreeSet<usize>, i32, bool) {
        if self.first.len() <= self.second.len() {
            (self.first, -joint_quarters, true)
        } else {
            (self.second, joint_quarters, false)
        }
    }
}

/// Splits the structure at a joint of `module`. `Err(loop modules)` when the two halves are
/// joined through other modules, in which case the joint cannot turn.
pub(crate) fn split_at_joint(
    latches: &BTreeSet<Latch>,
    module: usize,
    first_half: fn(u8) -> bool,
    second_half: fn(u8) -> bool,
) -> Result<Sides, BTreeSet<usize>> {
    let first_start = neighbours_on(latches, module, first_half);
    let second_start = neighbours_on(latches, module, second_half);
    let first = reachable(latches, &first_start, Some(module));
    if second_start.iter().any(|m| first.contains(m)) {
        return Err(first);
    }
    let second = reachable(latches, &second_start, Some(module));
    Ok(Sides { first, second })
}

/// After a latch between modules `a` and `b` was removed: `None` if they are still connected,
/// otherwise the two parts (containing `a` and `b`).
pub(crate) fn split_parts(
    latches: &BTreeSet<Latch>,
    a: usize,
    b: usize,
) -> Option<(BTreeSet<usize>, BTreeSet<usize>)> {
    let part_a = reachable(latches, &BTreeSet::from([a]), None);
    if part_a.contains(&b) {
        return None;
    }
    Some((part_a, reachable(latches, &BTreeSet::from([b]), None)))
}
