//! Unit tests of `src/simultaneous.rs`, kept beside the integration tests
//! because they read the robots' example files.

use super::*;
use dynarole_world::{Action, OpError};

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
    quarters_of(world, m, joint, 1)
}

/// `quarters` quarter turns up of module `m`'s joint `joint` from where it is (on ATRON, 2
/// is a half turn).
fn quarters_of(world: &RobotWorld, m: usize, joint: u8, quarters: i64) -> Action {
    let config = world.configuration().expect("a configuration");
    let plugins = dynarole_robots::plugins();
    let angle = plugins
        .get(config.kind().name())
        .expect("its plugin")
        .joint_angle;
    let at = world.view().joint(m, joint).expect("a joint");
    let to = at + quarters * angle.quarter;
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

/// All the turns of a group in one synchronous group, with skew `skew`.
fn in_lockstep(turns: usize, skew: f64) -> Timings {
    Timings {
        lockstep: vec![Some(0); turns],
        skew,
    }
}

/// The limit of a group: the largest of its turns' (the search's).
fn limit_of(group: &[(&Motion, usize)]) -> f64 {
    group.iter().map(|(m, _)| m.limit).fold(0.0, f64::max)
}

/// Visits every point of a grid of `steps` intervals per turn whose fractions differ
/// pairwise by at most `width` intervals, with that spread (in intervals): one synchronous
/// group's band, sampled without walking the whole box.
fn for_each_in_band(turns: usize, steps: u32, width: u32, visit: &mut dyn FnMut(&[f64], u32)) {
    let mut fractions = vec![0.0; turns];
    for first in 0..=steps {
        // The others within `width` of the first: every point of the band with this first.
        let (lo, hi) = (first.saturating_sub(width), (first + width).min(steps));
        let mut digits = vec![lo; turns];
        digits[0] = first;
        loop {
            let spread = digits.iter().max().unwrap_or(&0) - digits.iter().min().unwrap_or(&0);
            if spread <= width {
                for (f, d) in fractions.iter_mut().zip(&digits) {
                    *f = f64::from(*d) / f64::from(steps);
                }
                visit(&fractions, spread);
            }
            let Some(j) = (1..turns).find(|&j| digits[j] < hi) else {
                break;
            };
            digits[j] += 1;
            digits[1..j].fill(lo);
        }
    }
}

/// What a dense grid of a synchronous group's band says of every two points some turn
/// moves apart (those `Pairs::All` covers).
struct Banded {
    /// The smallest distance at a grid point inside the band: a timing the band allows, so
    /// the search's closest is at most this.
    inside: f64,
    /// A lower bound of the distance over the whole band, so the search's closest (found
    /// inside the band) is at least this: the grid widened by one interval (every timing of
    /// the band rounds to one of its points), each point's distance lowered by how far half
    /// an interval of every turn can move the two points.
    lower: f64,
}

/// The band of skew `skew` (every turn of the linkage in one synchronous group) on a grid of
/// `steps` intervals per turn.
fn banded_minimum(
    linkage: &Linkage,
    points: &[(usize, [f64; 3])],
    steps: u32,
    skew: f64,
) -> Banded {
    let pairs: Vec<(usize, usize, usize)> = (0..points.len())
        .flat_map(|i| (i + 1..points.len()).map(move |k| (i, k)))
        .filter(|&(i, k)| !linkage.rigid(i, k))
        .map(|(i, k)| (i, k, linkage.shared(i, k)))
        .collect();
    // Half an interval of turn `t` moves a point at most `half * angle * r`, `r` its
    // distance from the turn's pivot (where the turner's point puts it); `r` itself grows by
    // what the point moves, which `growth` covers. The turns two points share move both
    // rigidly and are left out.
    let half = 0.5 / f64::from(steps);
    let angle = |t: usize| linkage.sides[t].angle_deg.abs().to_radians();
    let growth = 1.0 / (1.0 - half * (0..linkage.sides.len()).map(angle).sum::<f64>());
    let strict = (skew * f64::from(steps) + 1e-9).floor() as u32;
    let mut banded = Banded {
        inside: f64::INFINITY,
        lower: f64::INFINITY,
    };
    for_each_in_band(linkage.sides.len(), steps, strict + 1, &mut |f, spread| {
        let moved: Vec<[f64; 3]> = (points.iter().enumerate())
            .map(|(m, (_, p))| linkage.position(m, *p, f))
            .collect();
        let pivots: Vec<[f64; 3]> = (linkage.sides.iter())
            .map(|s| linkage.position(s.turner[0], s.pivot, f))
            .collect();
        let drift = |m: usize, skip: usize| -> f64 {
            (linkage.chains[m][skip..].iter())
                .map(|&t| half * angle(t) * distance(moved[m], pivots[t]))
                .sum()
        };
        for &(i, k, skip) in &pairs {
            let d = distance(moved[i], moved[k]);
            banded.lower = banded
                .lower
                .min(d - growth * (drift(i, skip) + drift(k, skip)));
            if spread <= strict {
                banded.inside = banded.inside.min(d);
            }
        }
    });
    banded
}

/// The search of `group` in one synchronous group, with a wide and a narrow skew, over every
/// pair of points (`Pairs::All`), checked against a band grid of `steps` intervals: for
/// each skew, whether it was clear and whether the band kept out an approach some timing
/// outside it has (so that the band, not the box, is what was compared).
fn band_agrees_with_grid(
    start: &RobotWorld,
    group: &[(&Motion, usize)],
    steps: u32,
) -> Vec<(bool, bool)> {
    let (_, linkage) = linkage_of(group, start).expect("a tree at these joints");
    let limit = limit_of(group);
    let modules: Vec<String> = group.iter().map(|(_, m)| start.view().name(*m)).collect();
    // The closest a coarse grid of the whole box finds: timings that every timing allows.
    let every = banded_minimum(&linkage, &points_of(start), 24, 1.0).inside;
    let verdict = |skew: f64| {
        let case = format!("{modules:?}, skew {skew}");
        let grid = banded_minimum(&linkage, &points_of(start), steps, skew);
        let found = turns_at(group, start, &in_lockstep(group.len(), skew), Pairs::All);
        let clear = match found.expect("a linkage") {
            Together::Clear => {
                assert!(
                    grid.inside >= limit,
                    "{case}: the grid meets {}",
                    grid.inside
                );
                true
            }
            Together::Closest(x) => {
                assert!(
                    grid.lower < limit,
                    "{case}: {} found where the band clears {}",
                    x.distance,
                    grid.lower
                );
                assert!(
                    x.distance <= grid.inside + REFINEMENT,
                    "{case}: {} beyond the grid's {}",
                    x.distance,
                    grid.inside
                );
                assert!(
                    x.distance >= grid.lower - 1e-9,
                    "{case}: {} below the band's bound {}: a timing outside it",
                    x.distance,
                    grid.lower
                );
                false
            }
            Together::Unproven(x) => panic!("{case}: unproven at {}", x.distance),
        };
        (clear, every < grid.lower - 0.01)
    };
    [0.18, 0.05].map(verdict).to_vec()
}

/// The turns of `quarters` quarters up of every module of `start` that moves some sweep
/// point (a turn moving none, a leaf's, leaves nothing to compare).
fn motions_by(start: &RobotWorld, quarters: i64) -> Vec<Option<Motion>> {
    let n = start.view().len();
    let motion = |m: usize| {
        let name = start.view().name(m);
        (start.model())
            .motion(&name, &quarters_of(start, m, 0, quarters))
            .filter(|x| !x.moving.is_empty())
    };
    (0..n).map(motion).collect()
}

/// Every two turns on the snake and the car (every two modules, both a quarter or both a
/// half turn up) and a few three, all in one synchronous group with a wide and a narrow
/// skew, over every pair of points (`Pairs::All`): the search agrees with a dense grid of
/// the band (`band_agrees_with_grid`). Clear only where no grid point inside the band is
/// below the limit, never a conflict where the grid's bound clears the band, and a found
/// approach no farther than the grid's closest inside the band and no closer than the
/// band's bound (a timing outside the band must not be reported). Unproven fails: these
/// groups are small.
#[test]
fn the_lockstep_band_agrees_with_a_dense_grid_inside_it() {
    let (mut clear, mut closest, mut kept_out) = (0, 0, 0);
    let mut tally = |(was_clear, was_kept_out): (bool, bool)| {
        if was_clear {
            clear += 1;
        } else {
            closest += 1;
        }
        kept_out += usize::from(was_kept_out);
    };
    for text in [SNAKE, CAR] {
        let start = world(text);
        let n = start.view().len();
        for quarters in [1, 2] {
            let motions = motions_by(&start, quarters);
            for (a, b) in (0..n).flat_map(|a| (a + 1..n).map(move |b| (a, b))) {
                let (Some(ma), Some(mb)) = (&motions[a], &motions[b]) else {
                    continue;
                };
                let group = [(ma, a), (mb, b)];
                band_agrees_with_grid(&start, &group, 120)
                    .into_iter()
                    .for_each(&mut tally);
            }
        }
    }
    // Three where the band matters: on the snake, half turns along its middle (every timing
    // brings two modules together, the band keeps them apart or nearly); on the car, the
    // driver and both axles a quarter.
    for (text, quarters, names) in [
        (SNAKE, 2, ["M2", "M3", "M4"]),
        (SNAKE, 2, ["M3", "M4", "M6"]),
        (CAR, 1, ["M0", "M1", "M6"]),
    ] {
        let start = world(text);
        let motions = motions_by(&start, quarters);
        let index = |name: &str| start.view().index(name).expect("a module");
        let members = names.map(index);
        let motion = |m: usize| motions[m].as_ref().expect("a turn that moves");
        let group: Vec<(&Motion, usize)> = members.iter().map(|&m| (motion(m), m)).collect();
        band_agrees_with_grid(&start, &group, 80)
            .into_iter()
            .for_each(&mut tally);
    }
    assert!(
        clear >= 10 && closest >= 10,
        "{clear} clear, {closest} closest"
    );
    assert!(
        kept_out >= 5,
        "the band kept out only {kept_out} approaches"
    );
}

/// On the snake, M3 turning its joint a half turn up and M4 a half turn down, in lock-step:
/// M3's turn alone brings M0 onto M6 (the world refuses it; M4's alone it accepts), so over
/// every timing the pair meets, but moving together within the skew they stay clear (the
/// grid of the band agrees, by its lower bound, so that the search's Clear is right).
#[test]
fn a_synchronous_pair_can_be_clear_where_one_turn_alone_collides() {
    let start = world(SNAKE);
    let index = |name: &str| start.view().index(name).expect("a module");
    let (m0, m3, m4, m6) = (index("M0"), index("M3"), index("M4"), index("M6"));
    let half = |increasing| Action::Turn {
        joint: 0,
        from: None,
        to: 216,
        increasing,
    };
    let (up, down) = (half(true), half(false));
    let alone = |name: &str, action: &Action| start.model().clone_model().apply(name, action);
    assert!(
        matches!(alone("M3", &up), Err(OpError::SweepCollision { moving, still, .. })
            if (moving.as_str(), still.as_str()) == ("M0", "M6")),
        "M3's turn alone brings M0 onto M6"
    );
    assert!(alone("M4", &down).is_ok(), "M4's turn alone is clear");
    let motion = |name: &str, action: &Action| start.model().motion(name, action).expect("a turn");
    let (a, b) = (motion("M3", &up), motion("M4", &down));
    let group = [(&a, m3), (&b, m4)];

    let banded = turns_at(&group, &start, &in_lockstep(2, 0.18), Pairs::All);
    assert_eq!(banded, Some(Together::Clear));
    let (_, linkage) = linkage_of(&group, &start).expect("a tree");
    let grid = banded_minimum(&linkage, &points_of(&start), 400, 0.18);
    assert!(grid.lower >= a.limit, "the band's bound {}", grid.lower);

    let Some(Together::Closest(found)) = turns_at(&group, &start, &Timings::every(), Pairs::All)
    else {
        panic!("over every timing M3's turn alone is a timing, which meets");
    };
    assert_eq!(found.modules, (m0, m6));
    // Both turns move them apart (M0 is on M3's moving side, M6 on M4's): the timing that
    // meets is M3's turn with M4's not begun.
    assert_eq!(found.turns, vec![0, 1]);
    assert!(found.distance <= REFINEMENT, "{}", found.distance);
}

/// With a skew of a whole turn the band is the whole box: on a few pairs of turns on the
/// snake and the car, clear and not, the verdict over every pair of points is exactly the
/// one over every timing (the same distance, modules and turns).
#[test]
fn the_band_with_full_skew_is_every_timing() {
    let (mut clear, mut closest) = (0, 0);
    for (text, quarters, names) in [
        (SNAKE, 1, ["M3", "M4"]),
        (SNAKE, 2, ["M3", "M4"]),
        (SNAKE, 1, ["M0", "M6"]),
        (CAR, 1, ["M0", "M6"]),
        (CAR, 2, ["M1", "M6"]),
    ] {
        let start = world(text);
        let motions = motions_by(&start, quarters);
        let index = |name: &str| start.view().index(name).expect("a module");
        let [a, b] = names.map(index);
        let turn = |m: usize| motions[m].as_ref().expect("a turn that moves");
        let group = [(turn(a), a), (turn(b), b)];
        let every = turns_at(&group, &start, &Timings::every(), Pairs::All);
        let whole = turns_at(&group, &start, &in_lockstep(2, 1.0), Pairs::All);
        assert_eq!(whole, every, "{names:?}, {quarters} quarters");
        match every {
            Some(Together::Clear) => clear += 1,
            Some(Together::Closest(_)) => closest += 1,
            other => panic!("{names:?}, {quarters} quarters: {other:?}"),
        }
    }
    assert!(
        clear >= 2 && closest >= 2,
        "{clear} clear, {closest} closest"
    );
}
