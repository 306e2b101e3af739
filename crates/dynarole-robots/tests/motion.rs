//! Every robot's motions say what its world does: for every quarter turn of every joint of
//! every module of every bundled data file that the world accepts, the motion planned before
//! it (`RobotModel::motion`) carries exactly the parts that move, and its legs take each
//! carried part and the connectors on it to where the world puts them; an extend or retract moves in place.

mod common;

use dynarole_world::{Action, Configuration, ModulePose, Motion, RobotModel};

/// Farthest a carried part may end from where the world puts it (rounding only).
const TOLERANCE: f64 = 1e-9;

#[test]
fn every_accepted_turn_moves_what_its_motion_carries_to_where_the_world_puts_it() {
    let plugins = dynarole_robots::plugins();
    let mut checked = 0;
    for (name, _) in common::FILES {
        let config = common::load(name).expect("a bundled data file");
        let api = plugins.get(config.kind().name()).expect("its plugin");
        let (quarter, wraps) = (api.joint_angle.quarter, api.joint_angle.wraps);
        let model = config.clone().into_model();
        for m in 0..config.shape().len() {
            for action in quarter_turns(&config, m, quarter, wraps) {
                checked += usize::from(check_turn(name, &config, model.as_ref(), m, &action));
            }
        }
    }
    assert!(checked > 50, "only {checked} turns were accepted");
}

#[test]
fn extends_and_retracts_move_in_place() {
    let plugins = dynarole_robots::plugins();
    for (name, _) in common::FILES {
        let config = common::load(name).expect("a bundled data file");
        let api = plugins.get(config.kind().name()).expect("its plugin");
        let latches = (api.parts.iter()).any(|p| p.operations.iter().any(|o| o.kind.is_latch()));
        if !latches {
            continue;
        }
        let model = config.clone().into_model();
        let module = config.shape().name(0).expect("a module").to_string();
        for action in [
            Action::Extend { connector: 0 },
            Action::Retract { connector: 0 },
        ] {
            let motion = model.motion(&module, &action).expect("a motion");
            assert!(!motion.moves(), "{name}: {action:?} moves {motion:?}");
            assert!(motion.carried.is_empty() && motion.moving.is_empty());
        }
        assert_eq!(
            model.motion("no such module", &Action::Extend { connector: 0 }),
            None
        );
    }
}

/// Every move (kind `move`) of every module of every bundled data file that the world
/// accepts, with every argument its plugin allows: its motion carries the module, whole, to
/// the cell the world puts it in. (A lattice module's faces are named by the way they face,
/// so a pivot renames them: connectors and up axes are not compared.)
#[test]
fn every_accepted_move_carries_its_module_to_where_the_world_puts_it() {
    let plugins = dynarole_robots::plugins();
    let mut checked = 0;
    for (name, _) in common::FILES {
        let config = common::load(name).expect("a bundled data file");
        let api = plugins.get(config.kind().name()).expect("its plugin");
        let model = config.clone().into_model();
        for action in moves(api) {
            for m in 0..config.shape().len() {
                checked += usize::from(check_move(name, &config, model.as_ref(), m, &action));
            }
        }
    }
    assert!(checked > 5, "only {checked} moves were accepted");
}

/// Every move action of a plugin, with every combination of its parameters' listed values.
fn moves(api: &dynarole_core::RobotApi) -> Vec<Action> {
    use dynarole_core::robot::{OperationKind, ParamType};
    let mut out = Vec::new();
    for part in &api.parts {
        for (k, op) in part.operations.iter().enumerate() {
            if op.kind != OperationKind::Move {
                continue;
            }
            let mut lists: Vec<[i64; 4]> = vec![[0; 4]];
            for (slot, param) in op.params.iter().enumerate() {
                let ParamType::Int {
                    values: Some(values),
                    ..
                } = &param.ty
                else {
                    continue;
                };
                lists = (lists.iter())
                    .flat_map(|args| {
                        values.iter().map(move |v| {
                            let mut next = *args;
                            next[slot] = *v;
                            next
                        })
                    })
                    .collect();
            }
            let operation = u8::try_from(k).expect("a small plugin");
            out.extend(
                lists
                    .into_iter()
                    .map(|args| Action::Move { operation, args }),
            );
        }
    }
    out
}

/// Checks one move the world accepts against its motion; false when the world refuses it.
fn check_move(
    file: &str,
    config: &Configuration,
    model: &dyn RobotModel,
    m: usize,
    action: &Action,
) -> bool {
    let module = config.shape().name(m).expect("a name").to_string();
    let motion = model.motion(&module, action);
    let mut after = model.clone_model();
    if after.apply(&module, action).is_err() {
        assert_eq!(
            motion, None,
            "{file}: {module} {action:?} refused, with a motion"
        );
        return false;
    }
    let motion = motion.unwrap_or_else(|| panic!("{file}: {module} {action:?} has no motion"));
    assert!(
        (motion.carried.iter()).all(|c| c.module == module && c.part.is_none()),
        "{file}: {module} {action:?} carries {:?}",
        motion.carried
    );
    let end = after.configuration().expect("a configuration").poses();
    for (k, (before, after)) in config.poses().iter().zip(&end).enumerate() {
        let expected = if k == m {
            motion.position_at(before.centre(), 1.0)
        } else {
            before.centre()
        };
        let off = distance(expected, after.centre());
        assert!(
            off < TOLERANCE,
            "{file}: {module} {action:?}: module {k} ends {off} off"
        );
    }
    true
}

/// A quarter turn each way from where each of module `m`'s joints is; a joint that turns
/// round (`[joint_angle] wraps`) counts its angles modulo four quarters.
fn quarter_turns(config: &Configuration, m: usize, quarter: i64, wraps: bool) -> Vec<Action> {
    let mut out = Vec::new();
    for joint in 0..2u8 {
        let Some(at) = config.shape().joint(m, joint) else {
            continue;
        };
        for (to, increasing) in [(at + quarter, true), (at - quarter, false)] {
            out.push(Action::Turn {
                joint,
                from: Some(at),
                to: if wraps {
                    to.rem_euclid(4 * quarter)
                } else {
                    to
                },
                increasing,
            });
        }
    }
    out
}

/// Checks one turn the world accepts against its motion; false when the world refuses it.
fn check_turn(
    file: &str,
    config: &Configuration,
    model: &dyn RobotModel,
    m: usize,
    action: &Action,
) -> bool {
    let module = config.shape().name(m).expect("a name").to_string();
    let motion = model.motion(&module, action);
    let mut after = model.clone_model();
    if after.apply(&module, action).is_err() {
        return false;
    }
    let motion = motion.unwrap_or_else(|| panic!("{file}: {module} {action:?} has no motion"));
    let end = after.configuration().expect("a configuration").poses();
    let start = config.poses();
    let what = format!("{file}: {module} {action:?}");
    for (k, (before, after)) in start.iter().zip(&end).enumerate() {
        let name = config.shape().name(k).expect("a name");
        let carried: Vec<Option<usize>> = motion
            .carried
            .iter()
            .filter(|c| c.module == name)
            .map(|c| c.part)
            .collect();
        for (p, (b, a)) in before.parts.iter().zip(&after.parts).enumerate() {
            let is_carried = carried.contains(&None) || carried.contains(&Some(p));
            let expected = if is_carried {
                motion.position_at(b.centre, 1.0)
            } else {
                b.centre
            };
            let off = distance(expected, a.centre);
            assert!(
                off < TOLERANCE,
                "{what}: part {p} of {name} ends {off} from its motion's end"
            );
        }
        check_ups(&what, &motion, (before, after), &carried);
        for (c, (b, a)) in before.connectors.iter().zip(&after.connectors).enumerate() {
            let part = config
                .shape()
                .side(u8::try_from(c).expect("a connector number"));
            let is_carried = carried.contains(&None) || carried.contains(&Some(part));
            let expected = if is_carried {
                motion.position_at(*b, 1.0)
            } else {
                *b
            };
            let off = distance(expected, *a);
            assert!(
                off < TOLERANCE,
                "{what}: connector {c} of {name} ends {off} from its motion's end"
            );
        }
    }
    true
}

/// Every carried part's up direction ends turned as its motion's legs turn it.
fn check_ups(
    what: &str,
    motion: &Motion,
    (before, after): (&ModulePose, &ModulePose),
    carried: &[Option<usize>],
) {
    for (p, (b, a)) in before.parts.iter().zip(&after.parts).enumerate() {
        if carried.contains(&None) || carried.contains(&Some(p)) {
            let off = distance(motion.direction_at(b.up, 1.0), a.up);
            assert!(
                off < TOLERANCE,
                "{what}: part {p}'s up ends {off} from its motion's"
            );
        }
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}
