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
    for (name, _) in common::FILES {
        let config = common::load(name).expect("a bundled data file");
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
