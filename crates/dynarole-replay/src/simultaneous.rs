//! Two joint turns done at the same time on a tree of modules, over every relative timing:
//! the frame in which the robot moves as one turn carrying the other (or as two turns on
//! either side of a still part), and a branch and bound over the joint-space box of the pair
//! (both turns' fractions, every combination) that proves every two modules stay the limit
//! apart, or finds how close they come.
//!
//! Why a frame is enough: turning one side of a joint by an angle, or the other side by minus
//! that angle, differ by a rigid motion of the whole robot, so distances between modules are
//! the same either way. On a tree, two joints cut the robot into three rigid groups; among the
//! four ways of choosing sides, one leaves a group still and either moves the other two
//! independently or moves one of them with the other (the inner turn's axis carried by the
//! outer turn). Which modules a turn moves is the world model's answer (`RobotModel::motion`).

use crate::robot_world::RobotWorld;
use dynarole_world::{Leg, Motion};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The most boxes one pair of modules is split into before its approach is reported as not
/// proven (conservatively, as a conflict): bounds the time the check takes.
const MAX_BOXES_PER_PAIR: usize = 1 << 16;

/// How far below a conflict already found a closer one is still looked for (lattice units or
/// the robot's unit): messages print three decimals.
const REFINEMENT: f64 = 1e-4;

/// What two turns done together bring their modules to, over every relative timing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Together {
    /// Every two modules stay at least the limit apart.
    Clear,
    /// Two modules come this close (below the limit) for some timing.
    Closest(f64),
    /// Not proven within [`MAX_BOXES_PER_PAIR`] boxes: the lower bound reached.
    Unproven(f64),
}

/// Every point the robot's sweeps are checked with, with its module's index
/// (`RobotModel::sweep_points`): whole modules' centres, or blocks.
type Points = [(usize, [f64; 3])];

/// One turn as the frame search sees it: its rotation, the points it moves (by index, on one
/// side of its joint) and the points of its own module.
#[derive(Clone)]
struct Side {
    pivot: [f64; 3],
    axis: [f64; 3],
    angle_deg: f64,
    moves: Vec<bool>,
    turner: Vec<usize>,
}

impl Side {
    /// The turn of `motion` by module `turner`, when it is one rotation whose moving points
    /// are among the robot's `points`.
    fn of(motion: &Motion, turner: usize, world: &RobotWorld, points: &Points) -> Option<Side> {
        let [Leg::Rotate {
            pivot,
            axis,
            angle_deg,
        }] = motion.legs.as_slice()
        else {
            return None;
        };
        let view = world.view();
        let mut moves = vec![false; points.len()];
        for (name, at) in &motion.moving {
            let m = view.index(name)?;
            let k = points
                .iter()
                .position(|(module, p)| *module == m && p == at)?;
            moves[k] = true;
        }
        let own = points.iter().enumerate().filter(|(_, (m, _))| *m == turner);
        Some(Side {
            pivot: *pivot,
            axis: *axis,
            angle_deg: *angle_deg,
            moves,
            turner: own.map(|(k, _)| k).collect(),
        })
    }

    /// Whether it moves any of the points `set`.
    fn moves_any(&self, set: &[usize]) -> bool {
        set.iter().any(|&k| self.moves[k])
    }

    /// Whether it moves all of the points `set` (another turn's module: its axis with it).
    fn moves_all(&self, set: &[usize]) -> bool {
        set.iter().all(|&k| self.moves[k])
    }

    /// The other side of the joint turned the other way: the same motion up to a rigid
    /// motion of the whole robot.
    fn flipped(&self) -> Side {
        Side {
            angle_deg: -self.angle_deg,
            moves: self.moves.iter().map(|m| !m).collect(),
            ..self.clone()
        }
    }

    fn leg(&self) -> Leg {
        Leg::Rotate {
            pivot: self.pivot,
            axis: self.axis,
            angle_deg: self.angle_deg,
        }
    }

    /// The largest rate (per unit of the turn's fraction) at which a point at distance
    /// `reach` from the pivot moves: its radius times the angle.
    fn rate(&self, reach: f64) -> f64 {
        reach * self.angle_deg.abs().to_radians()
    }
}

/// How the robot moves under the two turns, in the frame where some modules stay still.
enum Frame {
    /// Each turn moves its own modules; neither moves the other's axis.
    Apart(Side, Side),
    /// `outer` moves its modules, among them `inner`'s module and all `inner` moves.
    Carrying { outer: Side, inner: Side },
}

impl Frame {
    /// The first frame, over the four choices of sides, in which the turns compose without
    /// ambiguity, and whether its first fraction is `b`'s (`b` carries `a`); `None` when there
    /// is none (not a tree at these joints).
    fn of(a: &Side, b: &Side) -> Option<(Frame, bool)> {
        for (a, b) in [
            (a.clone(), b.clone()),
            (a.clone(), b.flipped()),
            (a.flipped(), b.clone()),
            (a.flipped(), b.flipped()),
        ] {
            let disjoint = a.moves.iter().zip(&b.moves).all(|(x, y)| !(x & y));
            let within = |inner: &Side, outer: &Side| {
                inner.moves.iter().zip(&outer.moves).all(|(i, o)| !i | o)
            };
            if disjoint && !a.moves_any(&b.turner) && !b.moves_any(&a.turner) {
                return Some((Frame::Apart(a, b), false));
            }
            if a.moves_all(&b.turner) && !b.moves_any(&a.turner) && within(&b, &a) {
                return Some((Frame::Carrying { outer: a, inner: b }, false));
            }
            if b.moves_all(&a.turner) && !a.moves_any(&b.turner) && within(&a, &b) {
                return Some((Frame::Carrying { outer: b, inner: a }, true));
            }
        }
        None
    }

    /// Where point `m` (starting at `p`) is when the turns are at fractions `(fa, fb)`:
    /// `fa` of the first side given to [`Frame::Apart`] or of `outer`.
    fn position(&self, m: usize, p: [f64; 3], (fa, fb): (f64, f64)) -> [f64; 3] {
        match self {
            Frame::Apart(a, b) if a.moves[m] => a.leg().position_at(p, fa),
            Frame::Apart(_, b) if b.moves[m] => b.leg().position_at(p, fb),
            Frame::Apart(..) => p,
            Frame::Carrying { outer, inner } if inner.moves[m] => {
                outer.leg().position_at(inner.leg().position_at(p, fb), fa)
            }
            Frame::Carrying { outer, .. } if outer.moves[m] => outer.leg().position_at(p, fa),
            Frame::Carrying { .. } => p,
        }
    }

    /// Bounds on how fast point `m` (starting at `p`) moves per unit of each fraction.
    fn rates(&self, m: usize, p: [f64; 3]) -> (f64, f64) {
        match self {
            Frame::Apart(a, _) if a.moves[m] => (a.rate(distance(p, a.pivot)), 0.0),
            Frame::Apart(_, b) if b.moves[m] => (0.0, b.rate(distance(p, b.pivot))),
            Frame::Carrying { outer, inner } if inner.moves[m] => {
                // The inner turn keeps the module within its distance of the inner pivot,
                // which the outer turn carries at its own distance from the outer pivot.
                let reach = distance(p, inner.pivot) + distance(inner.pivot, outer.pivot);
                (outer.rate(reach), inner.rate(distance(p, inner.pivot)))
            }
            Frame::Carrying { outer, .. } if outer.moves[m] => {
                (outer.rate(distance(p, outer.pivot)), 0.0)
            }
            _ => (0.0, 0.0),
        }
    }

    /// Which rigid group point `m` is in: two points of one group never move apart.
    fn group(&self, m: usize) -> u8 {
        let (first, second) = match self {
            Frame::Apart(a, b) => (a.moves[m], b.moves[m]),
            Frame::Carrying { outer, inner } => (outer.moves[m], inner.moves[m]),
        };
        u8::from(first) + 2 * u8::from(second)
    }
}

/// The approach of every two points of the robot under turns `a` (by module `turner_a`) and
/// `b` done together, over every relative timing; `None` when the robot gives no sweep
/// points, a motion is not one rotation of some of them, or no frame composes them.
pub(crate) fn turns_together(
    (a, turner_a): (&Motion, usize),
    (b, turner_b): (&Motion, usize),
    world: &RobotWorld,
) -> Option<Together> {
    let points = world.model().sweep_points()?;
    let sa = Side::of(a, turner_a, world, &points)?;
    let sb = Side::of(b, turner_b, world, &points)?;
    let (frame, _) = Frame::of(&sa, &sb)?;
    let limit = a.limit.max(b.limit);
    let mut bar = limit;
    let mut closest = None;
    let mut unproven = None;
    for (i, k) in moving_pairs(&frame, points.len()) {
        let pair = Pair {
            frame: &frame,
            points: ((i, points[i].1), (k, points[k].1)),
        };
        match pair.approach(bar) {
            Approach::Clear => {}
            Approach::Below(d) => {
                closest = Some(d);
                bar = d;
            }
            Approach::Unproven(bound) => {
                unproven = Some(unproven.map_or(bound, |u: f64| u.min(bound)));
            }
        }
    }
    Some(match (closest, unproven) {
        (Some(d), _) => Together::Closest(d),
        (None, Some(bound)) => Together::Unproven(bound),
        (None, None) => Together::Clear,
    })
}

/// Two modules closer than the limit while two turns run at once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// When it first happens, as a fraction of the stretch of time searched.
    pub at: f64,
    /// The two modules (indices), lower first.
    pub modules: (usize, usize),
    /// How far apart they are then.
    pub distance: f64,
}

/// What two turns running at once do over a stretch of time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Along {
    /// Every two modules stay at least the limit apart.
    Clear,
    /// The first moment two modules are closer than the limit.
    Contact(Contact),
    /// Not turns this search composes (not one rotation of whole modules each, no frame).
    Unknown,
}

/// The least width of a piece of the stretch the search of the first contact splits (its
/// time resolution, as a fraction of the stretch).
const CONTACT_RESOLUTION: f64 = 1e-6;

/// Turns `a` (by module `turner_a`) and `b` running at once over a stretch of time along
/// which their fractions go linearly from `from` to `to` (`(a's, b's)`): the first moment two
/// modules come closer than the limit. Exact to [`CONTACT_RESOLUTION`] of the stretch: a
/// piece whose middle has two modules `d` apart keeps them at least `d` minus their rate
/// times half its width apart, and pieces are searched earliest first.
pub fn first_contact(
    (a, turner_a): (&Motion, usize),
    (b, turner_b): (&Motion, usize),
    (from, to): ((f64, f64), (f64, f64)),
    world: &RobotWorld,
) -> Along {
    let Some(points) = world.model().sweep_points() else {
        return Along::Unknown;
    };
    let sides = Side::of(a, turner_a, world, &points).zip(Side::of(b, turner_b, world, &points));
    let Some((frame, swapped)) = sides.and_then(|(sa, sb)| Frame::of(&sa, &sb)) else {
        return Along::Unknown;
    };
    let order = |(x, y): (f64, f64)| if swapped { (y, x) } else { (x, y) };
    let (from, to) = (order(from), order(to));
    let at = |u: f64| (from.0 + (to.0 - from.0) * u, from.1 + (to.1 - from.1) * u);
    let limit = a.limit.max(b.limit);
    let mut first: Option<Contact> = None;
    for (i, k) in moving_pairs(&frame, points.len()) {
        let (p, q) = (points[i].1, points[k].1);
        let (ra, rb) = add(frame.rates(i, p), frame.rates(k, q));
        let rate = ra * (to.0 - from.0).abs() + rb * (to.1 - from.1).abs();
        let apart = |u: f64| distance(frame.position(i, p, at(u)), frame.position(k, q, at(u)));
        let before = first.map_or(1.0, |c| c.at);
        if let Some((u, d)) = earliest_below(&apart, rate, limit, before) {
            first = Some(Contact {
                at: u,
                modules: (points[i].0, points[k].0),
                distance: d,
            });
        }
    }
    first.map_or(Along::Clear, Along::Contact)
}

/// The earliest `u` in `[0, before]` at which `apart(u)` (changing at most `rate` per unit of
/// `u`) is below `limit`, to [`CONTACT_RESOLUTION`], with the distance there.
fn earliest_below(
    apart: &dyn Fn(f64) -> f64,
    rate: f64,
    limit: f64,
    before: f64,
) -> Option<(f64, f64)> {
    let mut pieces = vec![(0.0_f64, before)];
    let mut found = None;
    for _ in 0..MAX_BOXES_PER_PAIR {
        // Last pushed is the earlier half: the stack searches earliest first.
        let Some((u0, u1)) = pieces.pop() else {
            return found;
        };
        let middle = (u0 + u1) / 2.0;
        let d = apart(middle);
        if d < limit && u1 - u0 <= CONTACT_RESOLUTION {
            return Some((middle, d));
        }
        if d < limit {
            found = Some((middle, d));
        }
        if d - rate * (u1 - u0) / 2.0 >= limit {
            continue;
        }
        if u1 - u0 > CONTACT_RESOLUTION {
            pieces.push((middle, u1));
            pieces.push((u0, middle));
        }
    }
    found
}

/// Every two points of different groups, lower index first, without visiting the pairs of
/// the still group (group 0) with itself: the cost is the moving modules times all of them.
fn moving_pairs(frame: &Frame, n: usize) -> Vec<(usize, usize)> {
    let moving: Vec<usize> = (0..n).filter(|&m| frame.group(m) != 0).collect();
    let mut pairs = Vec::new();
    for &i in &moving {
        for k in 0..n {
            let counted = frame.group(k) != 0 && k < i;
            if frame.group(k) != frame.group(i) && !counted {
                pairs.push((i.min(k), i.max(k)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// Two modules (index and start position) under a frame.
struct Pair<'f> {
    frame: &'f Frame,
    points: ((usize, [f64; 3]), (usize, [f64; 3])),
}

enum Approach {
    Clear,
    Below(f64),
    Unproven(f64),
}

impl Pair<'_> {
    /// Branch and bound over the box of both fractions: a box whose centre is `d` apart
    /// keeps every point of it at least `d` minus the rates times the half-widths apart.
    /// Boxes are taken lowest bound first (so the search ends as soon as no box can beat
    /// the bar) and split across their wider dimension, weighted by the rates.
    fn approach(&self, bar: f64) -> Approach {
        let mut boxes = BinaryHeap::new();
        boxes.push(self.piece((0.0, 1.0, 0.0, 1.0)));
        let mut best: Option<f64> = None;
        let mut bar = bar;
        for _ in 0..MAX_BOXES_PER_PAIR {
            let Some(piece) = boxes.pop() else {
                break;
            };
            // Proving clearance is exact; refining a conflict already found stops at the
            // precision messages print.
            let slack = if best.is_some() { REFINEMENT } else { 0.0 };
            if piece.bound >= bar - slack {
                return best.map_or(Approach::Clear, Approach::Below);
            }
            if piece.centre_distance < bar {
                best = Some(piece.centre_distance);
                bar = piece.centre_distance;
            }
            for half in self.halves(piece.area) {
                boxes.push(self.piece(half));
            }
        }
        match (best, boxes.peek()) {
            (Some(d), _) => Approach::Below(d),
            (None, Some(lowest)) if lowest.bound < bar => Approach::Unproven(lowest.bound.max(0.0)),
            (None, _) => Approach::Clear,
        }
    }

    /// A box of fractions `(a0, a1, b0, b1)` with its centre's distance and its lower bound.
    fn piece(&self, area: (f64, f64, f64, f64)) -> Piece {
        let ((i, p), (k, q)) = self.points;
        let (ra, rb) = add(self.frame.rates(i, p), self.frame.rates(k, q));
        let (a0, a1, b0, b1) = area;
        let centre = ((a0 + a1) / 2.0, (b0 + b1) / 2.0);
        let d = distance(
            self.frame.position(i, p, centre),
            self.frame.position(k, q, centre),
        );
        Piece {
            bound: d - ((a1 - a0) * ra + (b1 - b0) * rb) / 2.0,
            centre_distance: d,
            area,
        }
    }

    /// The two halves of a box, split across its wider dimension weighted by the rates.
    fn halves(&self, (a0, a1, b0, b1): (f64, f64, f64, f64)) -> [(f64, f64, f64, f64); 2] {
        let ((i, p), (k, q)) = self.points;
        let (ra, rb) = add(self.frame.rates(i, p), self.frame.rates(k, q));
        let (ma, mb) = ((a0 + a1) / 2.0, (b0 + b1) / 2.0);
        if (a1 - a0) * ra >= (b1 - b0) * rb {
            [(a0, ma, b0, b1), (ma, a1, b0, b1)]
        } else {
            [(a0, a1, b0, mb), (a0, a1, mb, b1)]
        }
    }
}

/// A box of the search, ordered so that the heap gives the lowest bound first.
struct Piece {
    bound: f64,
    centre_distance: f64,
    area: (f64, f64, f64, f64),
}

impl PartialEq for Piece {
    fn eq(&self, other: &Piece) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Piece {}

impl PartialOrd for Piece {
    fn partial_cmp(&self, other: &Piece) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Piece {
    fn cmp(&self, other: &Piece) -> Ordering {
        // Reversed: `BinaryHeap` is a max-heap. Ties by area keep the order total.
        other
            .bound
            .total_cmp(&self.bound)
            .then_with(|| other.area.0.total_cmp(&self.area.0))
            .then_with(|| other.area.2.total_cmp(&self.area.2))
    }
}

fn add(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 + b.0, a.1 + b.1)
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynarole_world::Action;

    const CAR: &str = include_str!("../../../robots/atron/examples/car.json");
    const CHAIN10: &str = include_str!("../../../robots/atron/examples/rotation-chain-10.json");
    const SNAKE: &str = include_str!("../../../robots/atron/examples/snake.json");
    const MTRAN_SNAKE: &str = include_str!("../../../robots/mtran/examples/mtran-snake4.json");

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

    fn same(a: &[f64], b: &[f64]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    /// The frame's corners are the world's own ends, up to rigid motion: one turn done (either
    /// one), and both. Checked on every pair of quarter turns the world accepts in both
    /// orders on three ATRON shapes and an M-TRAN snake (its blocks, both joints of each
    /// module), so that the frame search is the world's kinematics.
    #[test]
    fn the_frames_corners_are_where_the_world_puts_the_modules() {
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

    /// For turns `a` and `b` the world accepts alone and one after the other: the frame's
    /// corners have every two points as far apart as the world's ends. False when the world
    /// refuses one.
    fn corners_agree(
        start: &RobotWorld,
        (i, ta): (usize, &Action),
        (k, tb): (usize, &Action),
    ) -> bool {
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
        let sa = Side::of(&ma, i, start, &points).expect("a side");
        let sb = Side::of(&mb, k, start, &points).expect("a side");
        let (frame, swapped) = Frame::of(&sa, &sb).expect("a tree at these joints");
        let at = |f: (f64, f64)| {
            let moved: Vec<(usize, [f64; 3])> = (points.iter().enumerate())
                .map(|(m, (module, p))| (*module, frame.position(m, *p, f)))
                .collect();
            distances(&moved)
        };
        let (first, second) = if swapped { (b, a) } else { (a, b) };
        assert!(same(&at((1.0, 1.0)), &both), "{names:?}: both turns");
        assert!(
            same(&at((1.0, 0.0)), &first),
            "{names:?}: the first turn alone"
        );
        assert!(
            same(&at((0.0, 1.0)), &second),
            "{names:?}: the second turn alone"
        );
        true
    }

    /// The smallest distance over a dense grid of the box, for every two modules.
    fn sampled_minimum(frame: &Frame, points: &[(usize, [f64; 3])], steps: u32) -> f64 {
        let mut best = f64::INFINITY;
        for s in 0..=steps {
            for t in 0..=steps {
                let f = (
                    f64::from(s) / f64::from(steps),
                    f64::from(t) / f64::from(steps),
                );
                let moved: Vec<[f64; 3]> = (points.iter().enumerate())
                    .map(|(m, (_, p))| frame.position(m, *p, f))
                    .collect();
                for (i, k) in
                    (0..points.len()).flat_map(|i| (i + 1..points.len()).map(move |k| (i, k)))
                {
                    if frame.group(i) != frame.group(k) {
                        best = best.min(distance(moved[i], moved[k]));
                    }
                }
            }
        }
        best
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
        let Some(Together::Closest(found)) = turns_together((&a, m0), (&b, m6), &car) else {
            panic!("the car's turns collide part-way");
        };
        let points = points_of(&car);
        let (frame, _) = Frame::of(
            &Side::of(&a, m0, &car, &points).expect("a side"),
            &Side::of(&b, m6, &car, &points).expect("a side"),
        )
        .expect("a frame");
        let sampled = sampled_minimum(&frame, &points, 300);
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
            turns_together((&a, m2), (&b, m4), &chain),
            Some(Together::Clear)
        );
        let points = points_of(&chain);
        let (frame, _) = Frame::of(
            &Side::of(&a, m2, &chain, &points).expect("a side"),
            &Side::of(&b, m4, &chain, &points).expect("a side"),
        )
        .expect("a frame");
        assert!(sampled_minimum(&frame, &points, 100) >= a.limit);
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
                let Some(found) = turns_together((&ma, i), (&mb, k), &start) else {
                    continue;
                };
                let sides = (
                    Side::of(&ma, i, &start, &points).expect("a side"),
                    Side::of(&mb, k, &start, &points).expect("a side"),
                );
                let (frame, _) = Frame::of(&sides.0, &sides.1).expect("a frame");
                let sampled = sampled_minimum(&frame, &points, 60);
                match found {
                    Together::Clear => assert!(sampled >= ma.limit, "{names:?}: {sampled}"),
                    Together::Closest(d) => {
                        assert!(d <= sampled + 1e-9, "{names:?}: {d} {sampled}")
                    }
                    Together::Unproven(_) => {}
                }
                compared += 1;
            }
        }
        assert!(compared >= 6, "only {compared} pairs compared");
    }
}
