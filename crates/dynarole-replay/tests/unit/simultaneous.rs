//! Unit tests of `src/simultaneous.rs`, kept beside the integration tests
//! because they read the robots' example files.

use super::*;
use dynarole_world::Action;

const CAR: &str = include_str!("../../../../robots/atron/examples/car.json");
const CHAIN10: &str = include_str!("../../../../robots/atron/examples/rotation-chain-10.json");
const SNAKE: &str = include_str!("../../../../robots/atron/examples/snake.json");
const MTRAN_SNAKE: &str = include_str!("../../../../robots/mtran/examples/mtran-snake4.json");

fn world(text: &str) -> RobotWorld {
    let config = dynarole_robots::read_configuration(text).expect("a bundled file");
    let plugins = dynarole_robots::plugins();
    let api = plugins.get(config.kind().name()).expect("its plugin");
    RobotWorld::new(config, api).expect("a world")
}

/// A quarter turn up of module `m`'s joint `joint` from where it is, in the units of the
/// robot's plugin (`[joint_angle]`).
fn quarter_of(world: &RobotWorld, m: usize, joint: u8) -> Action {
    let config = world.configuration().expect("a configuration");
    let plugins = dynarole_robots::plugins();
    let angle = plugins
        .get(config.kind().name())
        .expect("its plugin")
        .joint_angle;
    let at = world.view().joint(m, joint).expect("a joint");
    let to = at + angle.quarter;
    Action::Turn {
        joint,
        from: Some(at),
        to: if angle.wraps {
            to.rem_euclid(4 * angle.quarter)
        } else {
            to
        },
        increasing: true,
    }
}

fn quarter(world: &RobotWorld, m: usize) -> Action {
    quarter_of(world, m, 0)
}

/// Every two points' distance, row by row.
fn distances(points: &[(usize, [f64; 3])]) -> Vec<f64> {
    let pairs = points
        .iter()
        .enumerate()
        .flat_map(|(i, (_, p))| points[i + 1..].iter().map(move |(_, q)| distance(*p, *q)));
    pairs.collect()
}

fn points_of(world: &RobotWorld) -> Vec<(usize, [f64; 3])> {
    world.model().sweep_points().expect("sweep points")
}

fn linkage_of_two(
    (a, i): (&Motion, usize),
    (b, k): (&Motion, usize),
    world: &RobotWorld,
    points: &[(usize, [f64; 3])],
) -> Linkage {
    let (found, linkage) = linkage_of(&[(a, i), (b, k)], world).expect("a tree at these joints");
    assert_eq!(found, points, "the robot's sweep points");
    linkage
}

fn same(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
}

/// The linkage's corners are the world's own ends, up to rigid motion: one turn done (either
/// one), and both. Checked on every pair of quarter turns the world accepts in both
/// orders on three ATRON shapes and an M-TRAN snake (its blocks, both joints of each
/// module), so that the linkage is the world's kinematics.
#[test]
fn the_linkages_corners_are_where_the_world_puts_the_modules() {
    let mut checked = 0;
    for (text, joints) in [(CAR, 1), (CHAIN10, 1), (SNAKE, 1), (MTRAN_SNAKE, 2)] {
        let start = world(text);
        let n = start.view().len();
        let modules = (0..n).flat_map(|i| (i + 1..n).map(move |k| (i, k)));
        let turns =
            |(i, k)| (0..joints).flat_map(move |ja| (0..joints).map(move |jb| (i, k, ja, jb)));
        for (i, k, ja, jb) in modules.flat_map(turns) {
            let (ta, tb) = (quarter_of(&start, i, ja), quarter_of(&start, k, jb));
            checked += usize::from(corners_agree(&start, (i, &ta), (k, &tb)));
        }
    }
    assert!(checked > 30, "only {checked} pairs checked");
}

/// For turns `a` and `b` the world accepts alone and one after the other: the linkage's
/// corners have every two points as far apart as the world's ends. False when the world
/// refuses one.
fn corners_agree(start: &RobotWorld, (i, ta): (usize, &Action), (k, tb): (usize, &Action)) -> bool {
    let names = (start.view().name(i), start.view().name(k));
    let done = |first: (&str, &Action), then: Option<(&str, &Action)>| {
        let mut model = start.model().clone_model();
        model.apply(first.0, first.1).ok()?;
        if let Some((name, action)) = then {
            model.apply(name, action).ok()?;
        }
        Some(distances(&model.sweep_points()?))
    };
    let (Some(a), Some(b), Some(both)) = (
        done((&names.0, ta), None),
        done((&names.1, tb), None),
        done((&names.0, ta), Some((&names.1, tb))),
    ) else {
        return false;
    };
    let (Some(ma), Some(mb)) = (
        start.model().motion(&names.0, ta),
        start.model().motion(&names.1, tb),
    ) else {
        return false;
    };
    let points = points_of(start);
    let linkage = linkage_of_two((&ma, i), (&mb, k), start, &points);
    let at = |f: [f64; 2]| {
        let moved: Vec<(usize, [f64; 3])> = (points.iter().enumerate())
            .map(|(m, (module, p))| (*module, linkage.position(m, *p, &f)))
            .collect();
        distances(&moved)
    };
    assert!(same(&at([1.0, 1.0]), &both), "{names:?}: both turns");
    assert!(same(&at([1.0, 0.0]), &a), "{names:?}: the first turn alone");
    assert!(
        same(&at([0.0, 1.0]), &b),
        "{names:?}: the second turn alone"
    );
    true
}

/// The smallest distance over a dense grid of the box (`steps` intervals per turn), for
/// every two points at least two turns move apart (those the search looks at).
fn sampled_minimum(linkage: &Linkage, points: &[(usize, [f64; 3])], steps: u32) -> f64 {
    let turns = linkage.sides.len();
    let corners = (u64::from(steps) + 1).pow(u32::try_from(turns).expect("few turns"));
    let pairs: Vec<(usize, usize)> = (0..points.len())
        .flat_map(|i| (i + 1..points.len()).map(move |k| (i, k)))
        .filter(|&(i, k)| !linkage.rigid(i, k) && linkage.between(i, k).len() > 1)
        .collect();
    let mut best = f64::INFINITY;
    for index in 0..corners {
        let f: Vec<f64> = (0..turns)
            .map(|t| {
                let digit = index / (u64::from(steps) + 1).pow(t as u32) % (u64::from(steps) + 1);
                digit as f64 / f64::from(steps)
            })
            .collect();
        let moved: Vec<[f64; 3]> = (points.iter().enumerate())
            .map(|(m, (_, p))| linkage.position(m, *p, &f))
            .collect();
        for &(i, k) in &pairs {
            best = best.min(distance(moved[i], moved[k]));
        }
    }
    best
}

/// Every three quarter turns of the shapes' modules that make a tree (three ATRON shapes,
/// and the M-TRAN snake's blocks): the group search agrees with a dense grid of their
/// three-dimensional box (clear where the grid is, and a found approach no farther than
/// the grid's closest).
#[test]
fn three_turns_together_agree_with_a_dense_grid() {
    let mut compared = 0;
    for text in [CAR, SNAKE, CHAIN10, MTRAN_SNAKE] {
        let start = world(text);
        let points = points_of(&start);
        let n = start.view().len();
        let motion = |m: usize| {
            let name = start.view().name(m);
            start
                .model()
                .motion(&name, &quarter(&start, m))
                .filter(|x| x.moves())
        };
        let motions: Vec<Option<Motion>> = (0..n).map(motion).collect();
        for (a, b, c) in
            (0..n).flat_map(|a| (a + 1..n).flat_map(move |b| (b + 1..n).map(move |c| (a, b, c))))
        {
            let (Some(ma), Some(mb), Some(mc)) = (&motions[a], &motions[b], &motions[c]) else {
                continue;
            };
            let group = [(ma, a), (mb, b), (mc, c)];
            let Some((_, linkage)) = linkage_of(&group, &start) else {
                continue;
            };
            let Some(found) = turns_together(&group, &start) else {
                continue;
            };
            let sampled = sampled_minimum(&linkage, &points, 16);
            match &found {
                Together::Clear => assert!(sampled >= ma.limit, "{a} {b} {c}: {sampled}"),
                Together::Closest(x) => assert!(
                    x.distance <= sampled + REFINEMENT,
                    "{a} {b} {c}: {} {sampled}",
                    x.distance
                ),
                Together::Unproven(_) => {}
            }
            compared += 1;
        }
    }
    assert!(compared >= 20, "only {compared} groups compared");
}

/// On the snake, M3 and M4 a quarter up and M6 from a half turn back to 0: every two of
/// them are clear together, all three are not (the CLI's golden case
/// `check_from_three_turns_meet_only_together`).
#[test]
fn three_turns_can_meet_where_every_two_are_clear() {
    let start = world(SNAKE);
    let index = |name: &str| start.view().index(name).expect("a module");
    let (m3, m4, m6) = (index("M3"), index("M4"), index("M6"));
    let down = Action::Turn {
        joint: 0,
        from: Some(216),
        to: 0,
        increasing: true,
    };
    let motion = |m: usize, action: &Action| {
        let name = start.view().name(m);
        start.model().motion(&name, action).expect("a turn")
    };
    let (a, b, c) = (
        motion(m3, &quarter(&start, m3)),
        motion(m4, &quarter(&start, m4)),
        motion(m6, &down),
    );
    let group = [(&a, m3), (&b, m4), (&c, m6)];
    for (x, y) in [(0, 1), (0, 2), (1, 2)] {
        let pair = turns_together(&[group[x], group[y]], &start);
        assert_eq!(pair, Some(Together::Clear), "turns {x} and {y}");
    }
    let Some(Together::Closest(found)) = turns_together(&group, &start) else {
        panic!("the three turns meet");
    };
    assert_eq!(found.turns, vec![0, 1, 2]);
    let (_, linkage) = linkage_of(&group, &start).expect("a tree");
    let sampled = sampled_minimum(&linkage, &points_of(&start), 24);
    assert!(found.distance <= sampled + REFINEMENT && sampled - found.distance < 0.02);
}

/// The car's driver and an axle turned together, each fine alone and in either order, come
/// within the limit part-way (the search finds what a dense grid finds); two joints of the
/// rotation chain turned together stay clear everywhere in their box.
#[test]
fn the_search_finds_what_a_dense_grid_of_the_box_finds() {
    let car = world(CAR);
    let (m0, m6) = (0, car.view().index("M6").expect("M6"));
    let a = car
        .model()
        .motion("M0", &quarter(&car, m0))
        .expect("a turn");
    let b = car
        .model()
        .motion(
            "M6",
            &Action::Turn {
                joint: 0,
                from: Some(108),
                to: 324,
                increasing: true,
            },
        )
        .expect("a turn");
    let Some(Together::Closest(found)) = turns_together(&[(&a, m0), (&b, m6)], &car) else {
        panic!("the car's turns collide part-way");
    };
    let found = found.distance;
    let points = points_of(&car);
    let linkage = linkage_of_two((&a, m0), (&b, m6), &car, &points);
    let sampled = sampled_minimum(&linkage, &points, 300);
    assert!(
        found <= sampled + 1e-9 && sampled - found < 0.01,
        "{found} against {sampled}"
    );
    assert!(found < a.limit);

    let chain = world(CHAIN10);
    let (m2, m4) = (2, 4);
    let a = chain
        .model()
        .motion("M2", &quarter(&chain, m2))
        .expect("a turn");
    let b = chain
        .model()
        .motion("M4", &quarter(&chain, m4))
        .expect("a turn");
    assert!(
        a.moving.iter().any(|x| b.moving.contains(x)),
        "the turns share modules"
    );
    assert_eq!(
        turns_together(&[(&a, m2), (&b, m4)], &chain),
        Some(Together::Clear)
    );
    let points = points_of(&chain);
    let linkage = linkage_of_two((&a, m2), (&b, m4), &chain, &points);
    assert!(sampled_minimum(&linkage, &points, 100) >= a.limit);
}

/// On the M-TRAN snake (points are blocks), every pair of quarter turns of two modules
/// that the search calls clear stays the limit apart on a dense grid of the box, and a
/// found approach is the grid's to within its spacing.
#[test]
fn the_search_agrees_with_a_dense_grid_on_blocks() {
    let start = world(MTRAN_SNAKE);
    let points = points_of(&start);
    let n = start.view().len();
    let mut compared = 0;
    for (i, k) in (0..n).flat_map(|i| (i + 1..n).map(move |k| (i, k))) {
        for (ja, jb) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let (ta, tb) = (quarter_of(&start, i, ja), quarter_of(&start, k, jb));
            let names = (start.view().name(i), start.view().name(k));
            let (Some(ma), Some(mb)) = (
                start.model().motion(&names.0, &ta),
                start.model().motion(&names.1, &tb),
            ) else {
                continue;
            };
            let Some(found) = turns_together(&[(&ma, i), (&mb, k)], &start) else {
                continue;
            };
            let linkage = linkage_of_two((&ma, i), (&mb, k), &start, &points);
            let sampled = sampled_minimum(&linkage, &points, 60);
            match found {
                Together::Clear => assert!(sampled >= ma.limit, "{names:?}: {sampled}"),
                Together::Closest(found) => {
                    let d = found.distance;
                    assert!(d <= sampled + 1e-9, "{names:?}: {d} {sampled}")
                }
                Together::Unproven(_) => {}
            }
            compared += 1;
        }
    }
    assert!(compared >= 6, "only {compared} pairs compared");
}
