//! The modules that never declared the end of a run that otherwise reached its goal, and
//! whether they could have heard it: a run's verdict must not pass over them in silence.

use dynarole_world::{Port, View};
use std::collections::VecDeque;

/// One line per module that never declared the end (`finished[m]` false), in module order:
/// whether, at the end of the run, latched connections still join it to a module that did.
pub fn never_ended(view: View<'_>, finished: &[bool]) -> Vec<String> {
    let heard = joined_to_finished(view, finished);
    (0..finished.len())
        .filter(|&m| !finished[m])
        .map(|m| {
            let name = view.name(m);
            if heard[m] {
                format!("{name} never declared the end, although latched connections join it to modules that did")
            } else {
                format!("{name} never declared the end: no latched connection joins it to a module that did, so it could not hear the end")
            }
        })
        .collect()
}

/// Which modules latched connections join to a module that declared the end (a breadth-first
/// walk from all of those at once).
fn joined_to_finished(view: View<'_>, finished: &[bool]) -> Vec<bool> {
    let mut joined = finished.to_vec();
    let mut queue: VecDeque<usize> = (0..finished.len()).filter(|&m| finished[m]).collect();
    while let Some(m) = queue.pop_front() {
        for connector in 0..view.connectors() {
            let Some(other) = view.latched_to(Port {
                module: m,
                connector,
            }) else {
                continue;
            };
            if !joined[other.module] {
                joined[other.module] = true;
                queue.push_back(other.module);
            }
        }
    }
    joined
}
