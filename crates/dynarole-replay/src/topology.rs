//! Who can hear whom during a reconfiguration: the communication graph that the model
//! checker's links are made of (`dynarole verify`), by the simulator's own link rule
//! (`dynarole_world::View::link_target`, the robot's own topology) on every configuration a replay of the plans visits.

use crate::{Assignment, RobotWorld};
use dynarole_core::expand::Plan;
use dynarole_core::Program;
use dynarole_world::Port;
use std::collections::BTreeSet;

/// The modules of a configuration (file order) and the directed links `(from, to)` between
/// them: `always` exist in every configuration the replay visits, `sometimes` in some only.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CommGraph {
    pub names: Vec<String>,
    pub always: BTreeSet<(usize, usize)>,
    pub sometimes: BTreeSet<(usize, usize)>,
    /// The links of each configuration visited: `stages[k]` after the first k statements
    /// (the start, then one after each statement; a refused step changes nothing).
    pub stages: Vec<BTreeSet<(usize, usize)>>,
}

/// Replays `plans` statement by statement (in source order, as `dynarole replay` does) from
/// `world` and collects who can send to whom before and after every step. A step the model
/// refuses changes nothing (`dynarole check --from` reports it).
pub fn communication_graph(
    program: &Program,
    plans: &[Plan],
    mut world: RobotWorld,
    assignment: &Assignment,
) -> CommGraph {
    let view = world.view();
    let names: Vec<String> = (0..view.len()).map(|m| view.name(m)).collect();
    let first = links(&world);
    let mut always = first.clone();
    let mut sometimes = first.clone();
    let mut stages = vec![first];
    for statement in plans.iter().flat_map(Plan::statements) {
        if let Some(module) = assignment.get(&statement.label) {
            let _ = world.apply(&program.robot, statement, module);
        }
        let now = links(&world);
        always = always.intersection(&now).copied().collect();
        sometimes.extend(now.iter().copied());
        stages.push(now);
    }
    let sometimes = sometimes.difference(&always).copied().collect();
    CommGraph {
        names,
        always,
        sometimes,
        stages,
    }
}

/// Who can send to whom on `world` now: the directed links of the robot's link rule.
pub(crate) fn links(world: &RobotWorld) -> BTreeSet<(usize, usize)> {
    let view = world.view();
    let mut out = BTreeSet::new();
    for module in 0..view.len() {
        for connector in 0..view.connectors() {
            if let Some(to) = view.link_target(Port { module, connector }) {
                if to.module != module {
                    out.insert((module, to.module));
                }
            }
        }
    }
    out
}
