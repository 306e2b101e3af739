//! The kinematics and validity of RoFI configurations on shapes whose geometry is known by
//! hand: straight chains, a closed square of two modules, a loop that cannot close, and a
//! module bent back onto another; and that where the robot is pinned changes nothing.

mod common;
use common::{configuration, module};

use dynarole_robot_rofi::{
    poses, poses_from, validate, Connection, Connector, Dock, Invalid, KinematicsError, Module,
    Orientation, RofiConfiguration, Side,
};
use nalgebra::{Matrix4, Point3};
use proptest::prelude::*;

fn port(id: u32, side: Side, dock: Dock) -> (u32, Connector) {
    (id, Connector::new(side, dock))
}

fn edge(from: (u32, Connector), orientation: Orientation, to: (u32, Connector)) -> Connection {
    Connection {
        from,
        orientation,
        to,
    }
}

fn near(a: Point3<f64>, b: Point3<f64>) -> bool {
    (a - b).norm() < 1e-9
}

#[test]
fn a_straight_module_has_its_shoes_one_unit_apart_along_z() {
    let config = configuration(&[module(7, 0.0, 0.0, 0.0)], &[]);
    let poses = poses(&config).expect("poses");
    let a = poses.centre((7, Side::A)).expect("shoe A");
    let b = poses.centre((7, Side::B)).expect("shoe B");
    assert!(near(a, Point3::origin()), "{a}");
    assert!(near(b, Point3::new(0.0, 0.0, 1.0)), "{b}");
}

#[test]
fn two_straight_modules_joined_end_to_end_make_a_line_of_four_shoes() {
    let n = Orientation::North;
    let joined = edge(
        port(1, Side::B, Dock::MinusZ),
        n,
        port(2, Side::A, Dock::MinusZ),
    );
    let config = configuration(
        &[module(1, 0.0, 0.0, 0.0), module(2, 0.0, 0.0, 0.0)],
        &[joined],
    );
    let poses = validate(&config).expect("valid");
    let zs: Vec<f64> = [(1, Side::A), (1, Side::B), (2, Side::A), (2, Side::B)]
        .iter()
        .map(|s| poses.centre(*s).expect("a shoe"))
        .map(|c| {
            assert!(c.x.abs() < 1e-9 && c.y.abs() < 1e-9, "{c}");
            c.z
        })
        .collect();
    for (z, expected) in zs.iter().zip([0.0, 1.0, 2.0, 3.0]) {
        assert!((z - expected).abs() < 1e-9, "{zs:?}");
    }
}

#[test]
fn a_module_turned_alpha_swings_its_other_shoe_about_shoe_a() {
    let config = configuration(&[module(1, 90.0, 0.0, 0.0)], &[]);
    let b = poses(&config)
        .expect("poses")
        .centre((1, Side::B))
        .expect("B");
    // About shoe A's X axis: from +Z a quarter turn goes to -Y.
    assert!(near(b, Point3::new(0.0, -1.0, 0.0)), "{b}");
}

#[test]
fn two_modules_joined_at_both_ends_do_not_close_when_both_point_away() {
    // Shoe A to shoe A puts module 2 below module 1; its shoe B cannot then meet shoe B of 1.
    let n = Orientation::North;
    let edges = [
        edge(
            port(1, Side::A, Dock::MinusZ),
            n,
            port(2, Side::A, Dock::MinusZ),
        ),
        edge(
            port(1, Side::B, Dock::MinusZ),
            n,
            port(2, Side::B, Dock::MinusZ),
        ),
    ];
    let config = configuration(
        &[module(1, 0.0, 0.0, 0.0), module(2, 0.0, 0.0, 0.0)],
        &edges,
    );
    match poses(&config) {
        Err(KinematicsError::LoopDoesNotClose { gap, .. }) => assert!(gap > 1.0, "{gap}"),
        other => panic!("{other:?}"),
    }
}

/// Two straight modules side by side, joined at shoe A (1's +X to a ±X dock of 2) and at
/// shoe B (a ±X dock of each), in every twist: the configurations whose loop closes.
fn side_by_side() -> Vec<(RofiConfiguration, Result<(), KinematicsError>)> {
    let x_docks = [Dock::PlusX, Dock::MinusX];
    let mut out = Vec::new();
    for (da, oa, d1, d2, ob) in itertools(&x_docks) {
        let edges = [
            edge(port(1, Side::A, Dock::PlusX), oa, port(2, Side::A, da)),
            edge(port(1, Side::B, d1), ob, port(2, Side::B, d2)),
        ];
        let modules = [module(1, 0.0, 0.0, 0.0), module(2, 0.0, 0.0, 0.0)];
        let config = configuration(&modules, &edges);
        let result = poses(&config).map(|_| ());
        out.push((config, result));
    }
    out
}

/// Every (dock of 2's A, twist, dock of 1's B, dock of 2's B, twist) over ±X docks.
fn itertools(docks: &[Dock]) -> Vec<(Dock, Orientation, Dock, Dock, Orientation)> {
    let mut out = Vec::new();
    for &da in docks {
        for oa in Orientation::ALL {
            for &d1 in docks {
                for &d2 in docks {
                    for ob in Orientation::ALL {
                        out.push((da, oa, d1, d2, ob));
                    }
                }
            }
        }
    }
    out
}

#[test]
fn two_modules_side_by_side_close_their_square_only_in_the_twists_that_fit() {
    let all = side_by_side();
    let closed: Vec<&RofiConfiguration> = all
        .iter()
        .filter(|(_, r)| r.is_ok())
        .map(|(c, _)| c)
        .collect();
    assert!(!closed.is_empty(), "no twist closes the square");
    assert!(closed.len() < all.len(), "every twist closes the square");
    for config in closed {
        // Module 2 stands beside module 1, one unit along +X, parallel to it.
        let p = poses(config).expect("poses");
        let a2 = p.centre((2, Side::A)).expect("A of 2");
        let b2 = p.centre((2, Side::B)).expect("B of 2");
        assert!(near(a2, Point3::new(1.0, 0.0, 0.0)), "{a2}");
        assert!(near(b2, Point3::new(1.0, 0.0, 1.0)), "{b2}");
    }
    // Every failure is a loop, never a disconnection.
    for (_, result) in &all {
        if let Err(e) = result {
            assert!(
                matches!(e, KinematicsError::LoopDoesNotClose { .. }),
                "{e:?}"
            );
        }
    }
}

#[test]
fn a_module_bent_onto_another_collides_with_it() {
    // Modules 2 and 3 stand on module 1's two shoes, both pointing along +X: 2 on shoe A's +X
    // dock (at (1, 0, 0)), 3 on shoe B's -X dock, which faces +X since shoe B is turned half
    // round (at (1, 0, 1)). Straight, 2's shoe B is at (2, 0, 0); bent a quarter turn the
    // right way for its twist, it lands on 3's shoe A.
    let mut collisions = 0;
    for alpha in [-90.0, 0.0, 90.0] {
        for o12 in Orientation::ALL {
            let edges = [
                edge(
                    port(1, Side::A, Dock::PlusX),
                    o12,
                    port(2, Side::A, Dock::MinusZ),
                ),
                edge(
                    port(1, Side::B, Dock::MinusX),
                    Orientation::North,
                    port(3, Side::A, Dock::MinusZ),
                ),
            ];
            let modules = [
                module(1, 0.0, 0.0, 0.0),
                module(2, alpha, 0.0, 0.0),
                module(3, 0.0, 0.0, 0.0),
            ];
            match validate(&configuration(&modules, &edges)) {
                Ok(_) => {}
                Err(Invalid::Collision(c)) => {
                    assert_ne!(alpha, 0.0, "straight, module 2 points away: {c:?}");
                    assert_eq!(c.shoes, ((2, Side::B), (3, Side::A)), "{c:?}");
                    assert!(c.distance < 1e-9, "{c:?}");
                    collisions += 1;
                }
                Err(other) => panic!("{other:?}"),
            }
        }
    }
    // Of the eight bends (two directions, four twists), one direction in each of the two
    // twists that turn 2 about the Y axis.
    assert_eq!(collisions, 2);
}

#[test]
fn a_module_no_connection_reaches_is_reported() {
    let config = configuration(&[module(1, 0.0, 0.0, 0.0), module(5, 0.0, 0.0, 0.0)], &[]);
    assert_eq!(
        poses(&config).map(|_| ()),
        Err(KinematicsError::NotConnected {
            pinned: 1,
            unreached: vec![5]
        })
    );
}

fn any_dock() -> impl Strategy<Value = Dock> {
    prop_oneof![Just(Dock::PlusX), Just(Dock::MinusX), Just(Dock::MinusZ)]
}

fn any_orientation() -> impl Strategy<Value = Orientation> {
    (0usize..4).prop_map(|k| Orientation::ALL[k])
}

proptest! {
    #[test]
    fn where_the_robot_is_pinned_changes_no_distance(
        angles in proptest::collection::vec((-90.0f64..90.0, -90.0f64..90.0, -360.0f64..360.0), 3),
        links in proptest::collection::vec((any_dock(), any_orientation(), any_dock()), 2),
        pinned_side in proptest::bool::ANY,
    ) {
        // A chain 1 - 2 - 3: B of 1 to A of 2, B of 2 to A of 3, at any docks and twists.
        let modules: Vec<Module> = (angles.iter().enumerate())
            .map(|(i, &(a, b, g))| module(i as u32 + 1, a, b, g))
            .collect();
        let edges: Vec<Connection> = (links.iter().enumerate())
            .map(|(i, &(d1, o, d2))| {
                let id = i as u32 + 1;
                edge(port(id, Side::B, d1), o, port(id + 1, Side::A, d2))
            })
            .collect();
        let config = configuration(&modules, &edges);
        let side = if pinned_side { Side::B } else { Side::A };
        let first = poses(&config).expect("a chain always closes");
        let second = poses_from(&config, (3, side), Matrix4::identity()).expect("again");
        let a: Vec<_> = first.centres().collect();
        let b: Vec<_> = second.centres().collect();
        for (i, (sa, pa)) in a.iter().enumerate() {
            for (k, (sb, pb)) in a.iter().enumerate().skip(i + 1) {
                let d1 = (pa - pb).norm();
                let d2 = (b[i].1 - b[k].1).norm();
                prop_assert!((d1 - d2).abs() < 1e-9, "{sa:?} {sb:?}: {d1} and {d2}");
            }
        }
    }
}

#[test]
fn a_plan_in_the_old_format_reads_and_its_open_loop_is_found() {
    let text = "# two modules end to end, then joined at both ends\nC\nM 1 0 0 0\nM 2 0 0 0\n\
                E 1 B -Z N -Z A 2\n\nC\nM 1 0 0 0\nM 2 0 0 0\nE 1 A -Z N -Z A 2\n\
                E 1 B -Z N -Z B 2\nlength 2\n";
    let plan = dynarole_robot_rofi::read_old_format(text).expect("a plan");
    let lines: Vec<usize> = plan.configurations.iter().map(|(line, _)| *line).collect();
    assert_eq!(lines, [2, 7]);
    assert!(validate(&plan.configurations[0].1).is_ok());
    match validate(&plan.configurations[1].1) {
        Err(Invalid::Kinematics(KinematicsError::LoopDoesNotClose { .. })) => {}
        other => panic!("{other:?}"),
    }
}
