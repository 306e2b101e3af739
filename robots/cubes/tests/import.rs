//! The importer against the simplest independent model of a scenario, the viewer's own: every
//! line moves its module by its displacement, so a module ends at its start plus the sum of
//! its lines. Every example scenario imports to exactly that, and a scenario without moves is
//! a configuration for `--from` while one with moves is refused there.

use dynarole_robot_cubes::scen::read_scen;
use dynarole_robot_cubes::{CubesRobot, KIND};
use dynarole_world::{ImportOptions, RobotKind};
use std::collections::BTreeMap;

const EXAMPLES: [&str; 6] = [
    include_str!("../examples/slide.scen"),
    include_str!("../examples/corner-slide.scen"),
    include_str!("../examples/pivot.scen"),
    include_str!("../examples/pivot180.scen"),
    include_str!("../examples/four-slides.scen"),
    include_str!("../examples/monkey.scen"),
];

/// Where the viewer puts every module at the end: its start plus all its displacements.
fn viewer_ends(text: &str) -> BTreeMap<u32, [i32; 3]> {
    let scenario = read_scen(text).expect("the scenario reads");
    let mut at: BTreeMap<u32, [i32; 3]> = (scenario.modules.iter())
        .map(|m| (m.id, m.position))
        .collect();
    for line in scenario.sets.iter().flat_map(|s| &s.moves) {
        let cell = at.get_mut(&line.id).expect("a declared module");
        for (c, d) in cell.iter_mut().zip(line.d) {
            *c += d;
        }
    }
    at
}

#[test]
fn every_example_ends_where_the_viewer_puts_its_modules() {
    for text in EXAMPLES {
        let plan = KIND
            .import_plan(text, "plan", &ImportOptions::default())
            .expect("a scenario")
            .expect("imports");
        let end = plan.expect.downcast_ref::<CubesRobot>().expect("cubes");
        let reached: BTreeMap<u32, [i32; 3]> =
            (end.cubes().iter()).map(|c| (c.id, c.position)).collect();
        assert_eq!(reached, viewer_ends(text), "{}", plan.program);
    }
}

#[test]
fn a_scenario_is_a_configuration_only_without_moves() {
    let text = EXAMPLES[0];
    let with_moves = KIND.read_native(text).expect("a scenario");
    let refused = with_moves.expect_err("a plan is no configuration");
    assert!(refused.message.contains("dynarole import"), "{refused}");
    let modules_only = text.split("\n*").next().expect("the modules");
    let config = KIND
        .read_native(modules_only)
        .expect("a scenario")
        .expect("a configuration");
    assert_eq!(config.shape().len(), 3);
}
