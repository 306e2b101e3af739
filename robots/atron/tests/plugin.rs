//! The ATRON plugin (`atron.robot.toml`) loads, declares what each operation does, and
//! reverses a turn by swapping its angles and its direction.

use dynarole_core::robot::{OperationKind, Value};
use dynarole_core::RobotApi;
use dynarole_world::RobotKind;

fn plugin() -> RobotApi {
    let (file, text) = dynarole_robot_atron::KIND.plugin();
    RobotApi::from_toml(text).unwrap_or_else(|e| panic!("{file}: {e}"))
}

#[test]
fn the_plugin_loads_under_the_kinds_name() {
    assert_eq!(plugin().name, dynarole_robot_atron::KIND.name());
}

#[test]
fn every_operation_declares_its_kind() {
    let kinds: Vec<(String, OperationKind)> = (plugin().parts.iter())
        .flat_map(|p| p.operations.iter().map(|o| (o.name.clone(), o.kind)))
        .collect();
    let expected = [
        ("extend", OperationKind::Extend),
        ("retract", OperationKind::Retract),
        ("rotateFromToBy", OperationKind::Turn),
        ("rotateToBy", OperationKind::TurnTo),
    ]
    .map(|(n, k)| (n.to_string(), k));
    assert_eq!(kinds, expected);
}

#[test]
fn a_rotation_reverses_with_its_angles_and_direction_swapped() {
    let atron = plugin();
    let (part, _) = atron.part("Joint").expect("joint");
    let args = [
        Value::Int(0),
        Value::Int(324),
        Value::Bool(false),
        Value::Int(150),
    ];
    let inverted = atron.invert(part, 0, &args).expect("invertible");
    let swapped = vec![
        Value::Int(324),
        Value::Int(0),
        Value::Bool(true),
        Value::Int(150),
    ];
    assert_eq!(inverted, (0, swapped));
    assert_eq!(
        atron.invert(part, 1, &args[1..]),
        None,
        "rotateToBy has no inverse"
    );
}
