//! The M-TRAN plugin (`mtran.robot.toml`) loads under the kind's name and declares what each
//! operation does.

use dynarole_core::robot::OperationKind;
use dynarole_core::RobotApi;
use dynarole_world::RobotKind;

#[test]
fn the_plugin_loads_and_every_operation_declares_its_kind() {
    let (file, text) = dynarole_robot_mtran::KIND.plugin();
    let api = RobotApi::from_toml(text).unwrap_or_else(|e| panic!("{file}: {e}"));
    assert_eq!(api.name, dynarole_robot_mtran::KIND.name());
    let kinds: Vec<(String, OperationKind)> = (api.parts.iter())
        .flat_map(|p| p.operations.iter().map(|o| (o.name.clone(), o.kind)))
        .collect();
    let expected = [
        ("extend", OperationKind::Extend),
        ("retract", OperationKind::Retract),
        ("rotateFromToBy", OperationKind::Turn),
    ]
    .map(|(n, k)| (n.to_string(), k));
    assert_eq!(kinds, expected);
}
