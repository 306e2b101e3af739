//! The plugin and the model read one table: the plugin's operations are `Move::NAMES` in
//! order, each of kind `move` with the model's steps, and every inverse the plugin gives is
//! the model's reverse, for every argument the plugin allows.

use dynarole_core::robot::{OperationKind, ParamType, Value};
use dynarole_core::RobotApi;
use dynarole_robot_cubes::lattice::Move;
use dynarole_world::RobotKind;

fn plugin() -> RobotApi {
    let (_, text) = dynarole_robot_cubes::KIND.plugin();
    RobotApi::from_toml(text).expect("the plugin loads")
}

#[test]
fn the_plugins_operations_are_the_models_moves_in_order() {
    let api = plugin();
    let (_, cube) = api.part("Cube").expect("a part `Cube`");
    let names: Vec<&str> = cube.operations.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, Move::NAMES);
    for mv in Move::all() {
        let (operation, _) = mv.operation();
        let op = &cube.operations[usize::from(operation)];
        assert_eq!(op.kind, OperationKind::Move, "{}", op.name);
        assert_eq!(op.steps, mv.steps(), "{}", op.name);
    }
}

#[test]
fn every_inverse_of_the_plugin_is_the_models_reverse() {
    let api = plugin();
    let (part, cube) = api.part("Cube").expect("a part `Cube`");
    let mut checked = 0;
    for (k, op) in cube.operations.iter().enumerate() {
        for args in arguments(&op.params.iter().map(|p| p.ty.clone()).collect::<Vec<_>>()) {
            let values: Vec<Value> = args.iter().map(|a| Value::Int(*a)).collect();
            let operation = u8::try_from(k).expect("few operations");
            let Ok(mv) = Move::from_operation(operation, padded(&args)) else {
                continue;
            };
            let (back, back_args) = api.invert(part, k, &values).expect("an inverse");
            let ints: Vec<i64> = (back_args.iter())
                .map(|v| match v {
                    Value::Int(n) => *n,
                    Value::Bool(_) => panic!("a move takes integers"),
                })
                .collect();
            let back = u8::try_from(back).expect("few operations");
            assert_eq!(
                Move::from_operation(back, padded(&ints)),
                Ok(mv.reverse()),
                "{} {args:?}",
                op.name
            );
            checked += 1;
        }
    }
    assert_eq!(checked, Move::all().len());
}

/// Every combination of the parameters' listed values.
fn arguments(params: &[ParamType]) -> Vec<Vec<i64>> {
    let mut out = vec![Vec::new()];
    for param in params {
        let ParamType::Int {
            values: Some(values),
            ..
        } = param
        else {
            panic!("a move's parameter lists its values");
        };
        out = (out.iter())
            .flat_map(|args| {
                values.iter().map(move |v| {
                    let mut next = args.clone();
                    next.push(*v);
                    next
                })
            })
            .collect();
    }
    out
}

fn padded(args: &[i64]) -> [i64; 4] {
    std::array::from_fn(|k| args.get(k).copied().unwrap_or(0))
}
