//! Every completion order of a parallel group at once: the states after each subset of its
//! elements, reached from each of the subsets one element smaller.
//!
//! A group of k elements can complete in k! orders, but every order passes through the same
//! 2^k sets of completed elements. The state after a set is reached from each of its subsets
//! one element smaller (k · 2^(k−1) steps): if all of them are accepted and end alike, every
//! order is accepted and ends alike (by induction over the size of the set), and the
//! warnings of the orders are those of the paths through the sets, kept as their distinct
//! multisets. So three statements that are fine two by two but split the robot when two of
//! them end before the third (eight2car's two retracts of M3 and M1's extend) are caught
//! without running the six orders.

use crate::robot_world::{RobotWorld, Warned};
use crate::warnings::unmatched;
use std::collections::btree_map::Entry;
use std::collections::BTreeMap;

/// The most elements of one group whose completion orders are all checked: 12 · 2^11 =
/// 24,576 steps on copies of the world. A larger group that needs it is not accepted.
pub(crate) const EVERY_ORDER_UP_TO: usize = 12;

/// The most different multisets of warnings the paths to one set may give before the
/// check stops counting them and refuses the group (a bound on memory; groups met in
/// practice give one or two).
const DISTINCT_WARNINGS_UP_TO: usize = 16;

/// Runs an element on a world, adding the model's warnings; the error says why it was
/// refused.
pub(crate) type Apply<'a, E> =
    dyn Fn(&E, &mut RobotWorld, &mut Vec<Warned>) -> Result<(), String> + 'a;

/// A group's elements and how to run and name one.
pub(crate) struct Elements<'a, E> {
    pub elements: &'a [E],
    pub apply: &'a Apply<'a, E>,
    pub describe: &'a dyn Fn(&E) -> String,
}

/// An order of a group that goes wrong where the written one does not.
#[derive(Debug)]
pub(crate) struct Wrong {
    /// The element (index) where it shows, and one the written order completes before it
    /// that this order does not (or the other order's last, for two different ends).
    pub at: usize,
    pub other: usize,
    pub reason: String,
}

#[derive(Debug)]
pub(crate) enum Verdict {
    /// Every order is accepted, ends alike and warns as the written one does (or the written
    /// order itself is refused: the replay reports that).
    Same,
    Wrong(Wrong),
    /// More elements than `EVERY_ORDER_UP_TO`.
    TooLarge,
}

/// One way of reaching a set of completed elements: its order and its warnings.
#[derive(Clone, Default)]
struct Path {
    order: Vec<usize>,
    warnings: Vec<Warned>,
}

/// A set of completed elements: the state after it, and the distinct ways of warning on the
/// way there (each with the first order that gave it).
struct Reached {
    world: RobotWorld,
    paths: Vec<Path>,
}

/// Checks every completion order of `group` from `start` (see the module's comment).
pub(crate) fn every_order<E>(group: &Elements<E>, start: &RobotWorld) -> Verdict {
    let k = group.elements.len();
    if k > EVERY_ORDER_UP_TO {
        return Verdict::TooLarge;
    }
    let Some(written) = written_order(group, start) else {
        return Verdict::Same;
    };
    let mut layer = BTreeMap::from([(
        0u32,
        Reached {
            world: start.clone(),
            paths: vec![Path::default()],
        },
    )]);
    for _ in 0..k {
        match next_layer(group, &layer) {
            Ok(next) => layer = next,
            Err(wrong) => return Verdict::Wrong(wrong),
        }
    }
    let all = layer
        .into_values()
        .next()
        .map(|r| r.paths)
        .unwrap_or_default();
    match all
        .iter()
        .find_map(|p| warned_otherwise(group, p, &written))
    {
        Some(wrong) => Verdict::Wrong(wrong),
        None => Verdict::Same,
    }
}

/// The warnings of the written order, `None` when one of its steps is refused.
fn written_order<E>(group: &Elements<E>, start: &RobotWorld) -> Option<Vec<Warned>> {
    let mut world = start.clone();
    let mut warnings = Vec::new();
    for element in group.elements {
        (group.apply)(element, &mut world, &mut warnings).ok()?;
    }
    Some(warnings)
}

/// The sets one element larger than those of `layer`, each reached from all of its
/// subsets in `layer`: the first refusal, difference or excess of warnings found is wrong.
fn next_layer<E>(
    group: &Elements<E>,
    layer: &BTreeMap<u32, Reached>,
) -> Result<BTreeMap<u32, Reached>, Wrong> {
    let mut next: BTreeMap<u32, Reached> = BTreeMap::new();
    for (&set, reached) in layer {
        for e in (0..group.elements.len()).filter(|&e| set & (1 << e) == 0) {
            let first = &reached.paths[0];
            let mut world = reached.world.clone();
            let mut warnings = Vec::new();
            if let Err(reason) = (group.apply)(&group.elements[e], &mut world, &mut warnings) {
                let order = extended(&first.order, e);
                let reason = format!("{}: {reason}", ending_in(group, &order));
                return Err(wrong_at(group.elements.len(), &order, reason));
            }
            let paths = reached.paths.iter().map(|p| Path {
                order: extended(&p.order, e),
                warnings: [p.warnings.clone(), warnings.clone()].concat(),
            });
            match next.entry(set | (1 << e)) {
                Entry::Vacant(slot) => {
                    let mut into = Vec::new();
                    merge(group, &mut into, paths)?;
                    slot.insert(Reached { world, paths: into });
                }
                Entry::Occupied(mut slot) => {
                    let here = slot.get_mut();
                    if let Some(difference) = here.world.difference(&world) {
                        let mine = extended(&first.order, e);
                        return Err(different_ends(
                            group,
                            &here.paths[0].order,
                            &mine,
                            &difference,
                        ));
                    }
                    merge(group, &mut here.paths, paths)?;
                }
            }
        }
    }
    Ok(next)
}

fn extended(order: &[usize], e: usize) -> Vec<usize> {
    let mut order = order.to_vec();
    order.push(e);
    order
}

/// Adds the paths whose warnings no path of `into` already has (as multisets).
fn merge<E>(
    group: &Elements<E>,
    into: &mut Vec<Path>,
    paths: impl Iterator<Item = Path>,
) -> Result<(), Wrong> {
    for path in paths {
        let known = into
            .iter()
            .any(|p| same_multiset(&p.warnings, &path.warnings));
        if known {
            continue;
        }
        if into.len() == DISTINCT_WARNINGS_UP_TO {
            let reason = format!(
                "{}: its orders warn in more than {DISTINCT_WARNINGS_UP_TO} different ways, \
                 more than are followed",
                ending_in(group, &path.order)
            );
            return Err(wrong_at(group.elements.len(), &path.order, reason));
        }
        into.push(path);
    }
    Ok(())
}

fn same_multiset(a: &[Warned], b: &[Warned]) -> bool {
    unmatched(a, b).is_none() && unmatched(b, a).is_none()
}

/// Why the complete order `path` warns where the written order does not, or not where it
/// does.
fn warned_otherwise<E>(group: &Elements<E>, path: &Path, written: &[Warned]) -> Option<Wrong> {
    let (step, warning) = match unmatched(&path.warnings, written) {
        Some(warned) => warned,
        None => {
            let (step, warning) = unmatched(written, &path.warnings)?;
            let reason = format!(
                "{}: `{step}` does not give the warning it gives in the written order ({warning})",
                ending_in(group, &path.order)
            );
            return Some(wrong_at(group.elements.len(), &path.order, reason));
        }
    };
    let at = (path.order.iter())
        .position(|&e| (group.describe)(&group.elements[e]) == *step)
        .unwrap_or(path.order.len() - 1);
    let reason = format!("{}: `{step}`: {warning}", ending_in(group, &path.order));
    Some(wrong_at(group.elements.len(), &path.order[..=at], reason))
}

/// The wrong order `order`, shown at its last element, with an element this order
/// completes before it that the written order completes after it (or one the written order
/// completes before it that this order does not).
fn wrong_at(k: usize, order: &[usize], reason: String) -> Wrong {
    let at = order.last().copied().unwrap_or(0);
    let before = &order[..order.len().saturating_sub(1)];
    let other = (before.iter().copied().find(|&e| e > at))
        .or_else(|| (0..at).find(|e| !before.contains(e)))
        .or_else(|| (0..k).find(|&e| e != at))
        .unwrap_or(at);
    Wrong { at, other, reason }
}

fn different_ends<E>(group: &Elements<E>, a: &[usize], b: &[usize], difference: &str) -> Wrong {
    let first = (difference.lines().map(str::trim))
        .find(|l| !l.is_empty() && !l.ends_with(':'))
        .unwrap_or("they differ");
    Wrong {
        at: b.last().copied().unwrap_or(0),
        other: a.last().copied().unwrap_or(0),
        reason: format!(
            "the orders {} and {} end in different configurations ({first})",
            order_words(group, a),
            order_words(group, b)
        ),
    }
}

/// "if they end `A`, then `B`, then `C`" (the first elements to end, in that order).
fn ending_in<E>(group: &Elements<E>, order: &[usize]) -> String {
    format!("if they end {}", order_words(group, order))
}

fn order_words<E>(group: &Elements<E>, order: &[usize]) -> String {
    let names: Vec<String> = order
        .iter()
        .map(|&e| format!("`{}`", (group.describe)(&group.elements[e])))
        .collect();
    names.join(", then ")
}
