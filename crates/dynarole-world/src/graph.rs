//! Connectivity through latches: which modules turn with a hemisphere, whether a joint is
//! locked by a loop, and whether releasing a latch splits the robot.

use crate::common::Latch;
use std::collections::BTreeSet;

/// Modules reachable from `starts` through latches without entering `barrier`.
pub fn reachable(
    latches: &BTreeSet<Latch>,
    starts: &BTreeSet<usize>,
    barrier: Option<usize>,
) -> BTreeSet<usize> {
    // Adjacency first, so the search is linear in the size of the robot rather than
    // (modules x latches): indexed by module (the indices are dense), all neighbours in one
    // vector with each module's start in `first` (few allocations: this runs for every turn).
    let size = latches
        .iter()
        .map(|l| l.male.module.max(l.female.module) + 1)
        .chain(starts.iter().map(|m| m + 1))
        .max()
        .unwrap_or(0);
    let mut first = vec![0usize; size + 1];
    for latch in latches {
        first[latch.male.module + 1] += 1;
        first[latch.female.module + 1] += 1;
    }
    for m in 0..size {
        first[m + 1] += first[m];
    }
    let mut filled = first.clone();
    let mut neighbours = vec![0usize; first[size]];
    for latch in latches {
        let (a, b) = (latch.male.module, latch.female.module);
        neighbours[filled[a]] = b;
        filled[a] += 1;
        neighbours[filled[b]] = a;
        filled[b] += 1;
    }
    let mut seen = vec![false; size];
    let mut pending: Vec<usize> = Vec::new();
    for &m in starts.iter().filter(|m| Some(**m) != barrier) {
        seen[m] = true;
        pending.push(m);
    }
    while let Some(current) = pending.pop() {
        for &next in &neighbours[first[current]..first[current + 1]] {
            if Some(next) != barrier && !seen[next] {
                seen[next] = true;
                pending.push(next);
            }
        }
    }
    (0..size).filter(|m| seen[*m]).collect()
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
pub struct Sides {
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
    pub fn moving(self, joint_quarters: i32) -> (BTreeSet<usize>, i32, bool) {
        if self.first.len() <= self.second.len() {
            (self.first, -joint_quarters, true)
        } else {
            (self.second, joint_quarters, false)
        }
    }
}

/// Splits the structure at a joint of `module`. `Err(loop modules)` when the two halves are
/// joined through other modules, in which case the joint cannot turn.
pub fn split_at_joint(
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
pub fn split_parts(
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
