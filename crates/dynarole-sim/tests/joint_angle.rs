//! The critical path counts a turn's quarter turns from the plugin's `[joint_angle]`, with no
//! model at hand; a run asks the robot's model. For every built-in robot the two agree on
//! every pair of angles its turn takes, both ways round.

use dynarole_core::robot::JointAngle;

/// A configuration of each built-in robot, by plugin name.
const STARTS: [(&str, &str); 2] = [
    ("atron", "../../robots/atron/examples/eight.json"),
    (
        "mtran",
        "../../robots/mtran/examples/mtran-snake4-moved.json",
    ),
];

/// Angles a turn may take on `robot`: its plugin's listed values, or its range in steps.
fn angles(robot: &dynarole_core::RobotApi) -> Vec<i64> {
    let turn = robot
        .parts
        .iter()
        .flat_map(|p| &p.operations)
        .find(|op| op.name == "rotateFromToBy")
        .expect("the robot has a turn");
    let to = turn.params.iter().find(|p| p.name == "to").expect("`to`");
    (-1000..=1000).filter(|a| to.ty.allows(*a)).collect()
}

#[test]
fn the_plugins_count_of_quarter_turns_is_the_models() {
    let registry = dynarole_robots::plugins();
    for (name, path) in STARTS {
        let robot = registry.get(name).expect("a built-in plugin");
        let text = std::fs::read_to_string(path).expect("an example configuration");
        let model = dynarole_robots::read_configuration(&text)
            .expect("a valid configuration")
            .into_model();
        let values = angles(robot);
        assert!(values.len() >= 4, "{name}: {values:?}");
        for &from in &values {
            for &to in &values {
                for increasing in [false, true] {
                    assert_eq!(
                        robot.joint_angle.quarter_turns(from, to, increasing),
                        model.quarter_turns(from, to, increasing),
                        "{name}: {from} to {to}, increasing {increasing}"
                    );
                }
            }
        }
    }
}

#[test]
fn a_joint_that_turns_round_counts_the_way_it_goes() {
    let round = JointAngle {
        quarter: 108,
        wraps: true,
    };
    assert_eq!(round.quarter_turns(0, 108, true), 1);
    assert_eq!(round.quarter_turns(0, 108, false), 3);
    assert_eq!(round.quarter_turns(324, 0, true), 1);
    assert_eq!(round.quarter_turns(0, 54, true), 1, "rounded up");
    let stops = JointAngle::default();
    assert_eq!(stops.quarter_turns(-90, 90, false), 2);
    assert_eq!(stops.quarter_turns(45, 0, true), 1);
    assert_eq!(
        stops.quarter_turns(i64::MIN, i64::MAX, true),
        i64::MAX as u64 / 90 + 1
    );
}
