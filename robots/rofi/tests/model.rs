//! The robot model behind the robot API: every accepted turn moves the shoes its motion says
//! to where the kinematics puts them after it, connect makes only mated connections,
//! disconnect never lets the robot come apart, and the angles of a turn are checked.

mod common;

use common::{configuration, edge, module};
use dynarole_robot_rofi::{poses, Dock, Orientation, RofiModel, RofiRobot, Side};
use dynarole_world::{Action, Metadata, OpError, RobotModel, Warning};
use std::collections::BTreeMap;

/// Four modules end to end, some joints already bent.
fn snake(joints: [(f64, f64, f64); 4]) -> RofiModel {
    let modules: Vec<_> = (1..=4u32)
        .zip(joints)
        .map(|(id, (a, b, g))| module(id, a, b, g))
        .collect();
    let edges: Vec<_> = (1..4u32)
        .map(|id| {
            edge(
                (id, Side::B, Dock::MinusZ),
                Orientation::North,
                (id + 1, Side::A, Dock::MinusZ),
            )
        })
        .collect();
    let config = configuration(&modules, &edges);
    let robot = RofiRobot::new(config, &BTreeMap::new(), Metadata::default()).expect("valid");
    RofiModel::new(robot)
}

fn turn(joint: u8, from: i64, to: i64, increasing: bool) -> Action {
    Action::Turn {
        joint,
        from: Some(from),
        to,
        increasing,
    }
}

fn centres(model: &RofiModel) -> Vec<[f64; 3]> {
    let poses = poses(model.robot().configuration()).expect("poses");
    poses.centres().map(|(_, c)| [c.x, c.y, c.z]).collect()
}

#[test]
fn every_accepted_turn_moves_its_shoes_where_the_kinematics_puts_them() {
    let start = snake([
        (0.0, 30.0, 0.0),
        (45.0, 0.0, 90.0),
        (0.0, -30.0, 0.0),
        (0.0, 0.0, 0.0),
    ]);
    let mut checked = 0;
    for m in 0..4 {
        let name = start.shape().name(m).expect("a name").to_string();
        for joint in 0..3u8 {
            let now = start.shape().joint(m, joint).expect("a joint");
            for (to, increasing) in [(now + 40, true), (now - 35, false), (now + 170, true)] {
                let to = if joint == 2 {
                    (to + 180).rem_euclid(360) - 180
                } else {
                    to
                };
                let action = turn(joint, now, to, increasing);
                let Some(motion) = start.motion(&name, &action) else {
                    continue;
                };
                let mut after = start.clone();
                if after.apply(&name, &action).is_err() {
                    continue;
                }
                let before = centres(&start);
                let moved = centres(&after);
                let points = start.sweep_points().expect("points");
                for (k, ((_, at), end)) in points.iter().zip(&moved).enumerate() {
                    let moving = motion.moving.iter().any(|(_, p)| p == at);
                    let expected = if moving {
                        motion.position_at(*at, 1.0)
                    } else {
                        before[k]
                    };
                    let gap: f64 = (0..3).map(|i| (expected[i] - end[i]).powi(2)).sum();
                    assert!(gap.sqrt() < 1e-9, "{name} joint {joint} to {to}: shoe {k} is {end:?}, the motion says {expected:?}");
                }
                checked += 1;
            }
        }
    }
    assert!(checked >= 10, "only {checked} turns were accepted");
}

#[test]
fn a_shoe_joint_turns_only_the_way_its_target_lies_and_within_its_range() {
    let mut model = snake([(0.0, 0.0, 0.0); 4]);
    let wrong_way = model.apply("M2", &turn(0, 0, 45, false));
    assert!(
        matches!(wrong_way, Err(OpError::InvalidAngle { angle: 45, .. })),
        "{wrong_way:?}"
    );
    let beyond = model.apply("M2", &turn(0, 0, 100, true));
    assert!(
        matches!(beyond, Err(OpError::InvalidAngle { angle: 100, .. })),
        "{beyond:?}"
    );
    let not_there = model.apply("M2", &turn(0, 10, 45, true));
    assert!(
        matches!(not_there, Err(OpError::WrongStartAngle { actual: 0, .. })),
        "{not_there:?}"
    );
    assert!(model.apply("M2", &turn(0, 0, 45, true)).is_ok());
}

#[test]
fn gamma_turns_round_either_way() {
    let mut model = snake([(0.0, 0.0, 0.0); 4]);
    assert!(
        model.apply("M2", &turn(2, 0, -90, true)).is_ok(),
        "0 to -90 the increasing way: 270"
    );
    assert_eq!(model.shape().joint(1, 2), Some(-90));
    assert!(model.apply("M2", &turn(2, -90, 180, false)).is_ok());
    assert_eq!(model.shape().joint(1, 2), Some(180));
    assert_eq!(model.quarter_turns(0, -90, true), 3);
    assert_eq!(model.quarter_turns(0, -90, false), 1);
}

#[test]
fn a_disconnect_that_would_split_the_robot_is_refused_and_changes_nothing() {
    let mut model = snake([(0.0, 0.0, 0.0); 4]);
    let before = model.clone();
    let split = model.apply("M2", &Action::Retract { connector: 5 });
    let Err(OpError::WouldSplit { apart, .. }) = split else {
        panic!("{split:?}");
    };
    assert_eq!(apart, ["M3", "M4"]);
    assert_eq!(model, before);
    let nothing = model.apply("M2", &Action::Retract { connector: 0 });
    assert!(
        matches!(nothing, Ok(o) if matches!(o.warnings.as_slice(), [Warning::NothingLatched { .. }]))
    );
}

#[test]
fn connect_needs_a_mated_free_connector_and_closes_a_loop() {
    // The ring of four that snake-to-ring.txt folds into, still open at M1's shoe A.
    let mut model = snake([
        (0.0, 0.0, 0.0),
        (0.0, -90.0, 90.0),
        (90.0, 0.0, 90.0),
        (0.0, 0.0, 0.0),
    ]);
    let none = model.apply("M1", &Action::Extend { connector: 2 });
    assert!(
        matches!(none, Err(OpError::NothingToLatchOnto { .. })),
        "{none:?}"
    );
    let made = model.apply("M1", &Action::Extend { connector: 0 });
    assert!(made.is_ok(), "{made:?}");
    assert_eq!(
        model
            .shape()
            .latched_to(dynarole_world::Port {
                module: 0,
                connector: 0
            })
            .map(|p| (p.module, p.connector)),
        Some((3, 4))
    );
    // Closed, the ring locks M2's beta: a turn of it would open the loop.
    let locked = model.apply("M2", &turn(1, -90, -60, true));
    assert!(
        matches!(locked, Err(OpError::JointLocked { .. })),
        "{locked:?}"
    );
    // Opened again anywhere, it is a snake and may come apart nowhere.
    assert!(model.apply("M2", &Action::Retract { connector: 5 }).is_ok());
}

#[test]
fn a_turn_that_sweeps_a_shoe_through_another_is_refused_and_changes_nothing() {
    // M2 on M1's shoe A (+X dock), M3 on M1's shoe B (-X dock): for some twists, a quarter
    // turn of M2's alpha swings M2 onto M3.
    let mut refused = 0;
    for twist in Orientation::ALL {
        let config = configuration(
            &[
                module(1, 0.0, 0.0, 0.0),
                module(2, 0.0, 0.0, 0.0),
                module(3, 0.0, 0.0, 0.0),
            ],
            &[
                edge((1, Side::A, Dock::PlusX), twist, (2, Side::A, Dock::MinusZ)),
                edge(
                    (1, Side::B, Dock::MinusX),
                    Orientation::North,
                    (3, Side::A, Dock::MinusZ),
                ),
            ],
        );
        let robot = RofiRobot::new(config, &BTreeMap::new(), Metadata::default()).expect("valid");
        let start = RofiModel::new(robot);
        for to in [-90, 90] {
            let mut model = start.clone();
            if let Err(OpError::SweepCollision {
                moving,
                still,
                distance,
                ..
            }) = model.apply("M2", &turn(0, 0, to, to > 0))
            {
                assert!(distance < 1.0, "{distance}");
                assert_eq!((moving.as_str(), still.as_str()), ("M2", "M3"));
                assert_eq!(model, start, "a refused turn changes nothing");
                refused += 1;
            }
        }
    }
    assert_eq!(refused, 2, "the two turns that end on M3 are refused");
}
