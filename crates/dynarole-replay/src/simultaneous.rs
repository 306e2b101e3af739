//! Joint turns done at the same time on a tree of modules, over every relative timing: the
//! linkage the turns make (which turns move each module, the outer ones carrying the inner
//! ones' axes), and a branch and bound over the joint-space box of the group (every turn's
//! fraction, every combination) that proves every two modules stay the limit apart, or finds
//! how close they come.
//!
//! Why one still module is enough: turning one side of a joint by an angle, or the other side
//! by minus that angle, differ by a rigid motion of the whole robot, so distances between
//! modules are the same either way. Holding one module still picks, for every turn, the side
//! without it; on a tree the sides picked are then nested or apart, and a module's position is
//! its start position turned by the turns that move it, innermost first, each about its axis
//! where it starts (the product of the turns, the outer ones carrying the inner ones' axes).
//! Which modules a turn moves is the world model's answer (`RobotModel::motion`).
//!
//! Why the bound is sound: at the middle of a box, a point turned by one turn through at most
//! `φ` from the middle's angle moves at most the chord `2 r sin(φ/2)`, `r` its distance from
//! that turn's axis there; the turns inside it move it at most their own chords, which the
//! outer turn, a rigid motion, does not lengthen. So every point of a box is within the sum of
//! the chords of where the middle puts it, and two modules the box's middle puts `d` apart
//! stay at least `d` minus both sums apart.

use crate::robot_world::RobotWorld;
use dynarole_world::{GroupVerdict, Leg, Motion};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The most boxes one pair of modules is split into before its approach is reported as not
/// proven (conservatively, as a conflict): bounds the time one pair takes.
const MAX_BOXES_PER_PAIR: usize = 1 << 16;

/// The most boxes all pairs of one group are split into together: bounds the time a group
/// takes whatever its size (a pair searched after the budget is spent is not proven).
const MAX_BOXES_PER_GROUP: usize = 1 << 21;

/// How far below a conflict already found a closer one is still looked for (lattice units or
/// the robot's unit): messages print three decimals.
const REFINEMENT: f64 = 1e-4;

/// What turns done together bring their modules to, over every relative timing.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Together {
    /// Every two modules stay at least the limit apart.
    Clear,
    /// Two modules come this close (below the limit) for some timing.
    Closest(Approach),
    /// Not proven within the boxes allowed: the lower bound reached, for the pair of modules
    /// (and the turns that move them apart) left unproven.
    Unproven(Approach),
}

/// How close two modules come, and the turns (the group's indices) that move them relative
/// to each other: those the timing that brings them there is a timing of.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Approach {
    pub distance: f64,
    pub modules: (usize, usize),
    pub turns: Vec<usize>,
    /// The robot's own rule that refuses the group, in words that finish "done at the same
    /// time, ..." (`GroupVerdict::Refused`), in place of the distance.
    pub rule: Option<String>,
}

/// Every point the robot's sweeps are checked with, with its module's index
/// (`RobotModel::sweep_points`): whole modules' centres, or blocks.
type Points = [(usize, [f64; 3])];

/// The robot's sweep points with, for each module, the indices of its points.
struct Indexed {
    points: Vec<(usize, [f64; 3])>,
    by_module: Vec<Vec<usize>>,
}

impl Indexed {
    fn new(points: Vec<(usize, [f64; 3])>) -> Indexed {
        let modules = points.iter().map(|(m, _)| m + 1).max().unwrap_or(0);
        let mut by_module = vec![Vec::new(); modules];
        for (k, (m, _)) in points.iter().enumerate() {
            by_module[*m].push(k);
        }
        Indexed { points, by_module }
    }

    fn of_module(&self, m: usize) -> impl Iterator<Item = usize> + '_ {
        self.by_module.get(m).into_iter().flatten().copied()
    }
}

/// The narrowest band of lock-step timings searched (fractions apart): turns of one module
/// start at the same instant, a band of no width.
const LEAST_BAND: f64 = 0.01;

/// Which relative timings of a group's turns are searched: every one (`&`), or with some
/// turns in lock-step (a synchronous group: started at one instant, moved at one pace, so
/// that their fractions never differ by more than the skew the runtime allows).
#[derive(Clone, Debug, PartialEq, Default)]
pub(crate) struct Timings {
    /// For each turn of the group, the synchronous group it belongs to, if any. Shorter than
    /// the group: the turns past its end are free.
    pub lockstep: Vec<Option<usize>>,
    /// How far apart the fractions of two turns of one synchronous group may be (0 to 1).
    pub skew: f64,
}

impl Timings {
    /// Every relative timing.
    pub fn every() -> Timings {
        Timings::default()
    }

    fn set_of(&self, turn: usize) -> Option<usize> {
        self.lockstep.get(turn).copied().flatten()
    }

    /// Whether the box `area` of the turns `dims` holds a timing allowed: for each
    /// synchronous group, its turns' ranges leave room for fractions within the skew. (The
    /// allowed timings of some of the turns are those of the same form: the others can
    /// always follow.)
    fn meets(&self, area: &[(f64, f64)], dims: &[usize]) -> bool {
        self.spread(dims, |j| area[j]) <= self.band()
    }

    /// Whether the point `at` (turn `dims[j]` at `at[j]`) is a timing allowed.
    fn holds(&self, at: &[f64], dims: &[usize]) -> bool {
        self.spread(dims, |j| (at[j], at[j])) <= self.band()
    }

    /// The skew searched: at least [`LEAST_BAND`], a sound widening (more timings), since a
    /// band of no width holds almost no box's middle, where conflicts are found.
    fn band(&self) -> f64 {
        self.skew.max(LEAST_BAND)
    }

    /// The largest, over the synchronous groups, of the least spread of their turns'
    /// fractions that ranges `range(j)` of turns `dims[j]` allow.
    fn spread(&self, dims: &[usize], range: impl Fn(usize) -> (f64, f64)) -> f64 {
        // (set, highest low, lowest high) of each synchronous group met.
        let mut sets: Vec<(usize, f64, f64)> = Vec::new();
        for (j, &t) in dims.iter().enumerate() {
            let Some(set) = self.set_of(t) else { continue };
            let (lo, hi) = range(j);
            match sets.iter_mut().find(|(s, _, _)| *s == set) {
                Some(entry) => {
                    entry.1 = entry.1.max(lo);
                    entry.2 = entry.2.min(hi);
                }
                None => sets.push((set, lo, hi)),
            }
        }
        sets.iter().map(|(_, lo, hi)| lo - hi).fold(0.0, f64::max)
    }
}

/// The robot's sweep points and the linkage of a group's turns on them.
type Linked = (Vec<(usize, [f64; 3])>, Linkage);

/// One turn as the linkage sees it: its rotation, the points it moves (by index, on one side
/// of its joint) and the points of its own module.
#[derive(Clone)]
struct Side {
    pivot: [f64; 3],
    /// The axis, of unit length.
    axis: [f64; 3],
    angle_deg: f64,
    moves: Vec<bool>,
    turner: Vec<usize>,
}

impl Side {
    /// The turn of `motion` by module `turner`, when it is one rotation whose moving points
    /// are among the robot's `points`.
    fn of(motion: &Motion, turner: usize, world: &RobotWorld, points: &Indexed) -> Option<Side> {
        let [Leg::Rotate {
            pivot,
            axis,
            angle_deg,
        }] = motion.legs.as_slice()
        else {
            return None;
        };
        let length = norm(*axis);
        if length == 0.0 || !length.is_finite() {
            return None;
        }
        let view = world.view();
        let mut moves = vec![false; points.points.len()];
        for (name, at) in &motion.moving {
            let m = view.index(name)?;
            let k = points.of_module(m).find(|&k| points.points[k].1 == *at)?;
            moves[k] = true;
        }
        Some(Side {
            pivot: *pivot,
            axis: axis.map(|c| c / length),
            angle_deg: *angle_deg,
            moves,
            turner: points.of_module(turner).collect(),
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

    /// Whether every point it moves, `outer` moves too.
    fn within(&self, outer: &Side) -> bool {
        self.moves.iter().zip(&outer.moves).all(|(i, o)| !i | o)
    }

    /// Whether it moves no point `other` moves.
    fn apart_from(&self, other: &Side) -> bool {
        self.moves.iter().zip(&other.moves).all(|(x, y)| !(x & y))
    }

    /// Whether it carries `inner`: moves its module and all it moves, and is not moved by it.
    fn carries(&self, inner: &Side) -> bool {
        self.moves_all(&inner.turner) && !inner.moves_any(&self.turner) && inner.within(self)
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

    /// The longest chord a point at `p` travels when the turn goes at most `half` of its
    /// fraction either way: `2 r sin(φ/2)`, `r` the point's distance from the axis and `φ`
    /// the angle (at most a half turn, beyond which the chord no longer grows).
    fn chord(&self, p: [f64; 3], half: f64) -> f64 {
        let r: [f64; 3] = std::array::from_fn(|k| p[k] - self.pivot[k]);
        let along = dot(r, self.axis);
        let radius = (dot(r, r) - along * along).max(0.0).sqrt();
        let swing = (self.angle_deg.abs().to_radians() * half).min(std::f64::consts::PI);
        2.0 * radius * (swing / 2.0).sin()
    }
}

/// The turns of a group composed on a tree, in the frame where one module stays still: for
/// each point, the turns that move it, outermost (the one carrying the others) first.
struct Linkage {
    sides: Vec<Side>,
    chains: Vec<Vec<usize>>,
}

impl Linkage {
    /// The first choice of a still point (one per rigid body the turns cut the robot into)
    /// with which every two turns are apart or one carries the other; `None` when there is
    /// none (not a tree at these joints).
    fn of(sides: &[Side], points: usize) -> Option<Linkage> {
        for root in body_representatives(sides, points) {
            let oriented: Vec<Side> = sides
                .iter()
                .map(|s| {
                    if s.moves[root] {
                        s.flipped()
                    } else {
                        s.clone()
                    }
                })
                .collect();
            let Some(depths) = nesting(&oriented) else {
                continue;
            };
            let chains = (0..points)
                .map(|m| {
                    let mut chain: Vec<usize> = (0..oriented.len())
                        .filter(|&t| oriented[t].moves[m])
                        .collect();
                    chain.sort_by_key(|&t| (depths[t], t));
                    chain
                })
                .collect();
            return Some(Linkage {
                sides: oriented,
                chains,
            });
        }
        None
    }

    /// Where point `m` (starting at `p`) is when each turn `t` is at fraction `fractions[t]`
    /// (the search needs only `reach` and `Whole`; the tests compare this with the world).
    #[cfg(test)]
    fn position(&self, m: usize, p: [f64; 3], fractions: &[f64]) -> [f64; 3] {
        self.chains[m]
            .iter()
            .rev()
            .fold(p, |q, &t| self.sides[t].leg().position_at(q, fractions[t]))
    }

    /// Point `m` (starting at `p`) moved by its turns after the first `skip` (those it shares
    /// with the point it is measured against, which move both rigidly), at the box's middle
    /// `centre` with half-widths `half`; with the sum of the chords that bound how far any
    /// point of the box puts it from there, adding each turn's chord to `weights[t]`.
    fn reach(
        &self,
        (m, p): (usize, [f64; 3]),
        skip: usize,
        (centre, half): (&[f64], &[f64]),
        weights: &mut [f64],
    ) -> ([f64; 3], f64) {
        let mut q = p;
        let mut total = 0.0;
        for &t in self.chains[m][skip..].iter().rev() {
            let side = &self.sides[t];
            let chord = side.chord(q, half[t]);
            total += chord;
            weights[t] += chord;
            q = side.leg().position_at(q, centre[t]);
        }
        (q, total)
    }

    /// Points `i` and `k` (starting at `p` and `q`; they share their first `skip` turns) at
    /// the middle of a box: their distance there and the lower bound over the box, each
    /// turn's chords added to `weights`.
    fn apart(
        &self,
        (p, q): ([f64; 3], [f64; 3]),
        (i, k, skip): (usize, usize, usize),
        box_: (&[f64], &[f64]),
        weights: &mut [f64],
    ) -> (f64, f64) {
        let (p, rp) = self.reach((i, p), skip, box_, weights);
        let (q, rq) = self.reach((k, q), skip, box_, weights);
        let d = distance(p, q);
        (d, d - rp - rq)
    }

    /// Whether two points move apart: not moved by the same turns.
    #[cfg(test)]
    fn rigid(&self, i: usize, k: usize) -> bool {
        self.chains[i] == self.chains[k]
    }

    /// Each point's rigid body (the points moved by the same turns), numbered in order of
    /// first point.
    fn bodies(&self) -> Vec<usize> {
        let mut seen: Vec<&Vec<usize>> = Vec::new();
        (self.chains.iter())
            .map(
                |chain| match seen.iter().position(|c| same_turns(c, chain)) {
                    Some(b) => b,
                    None => {
                        seen.push(chain);
                        seen.len() - 1
                    }
                },
            )
            .collect()
    }

    /// How many outer turns points `i` and `k` share.
    fn shared(&self, i: usize, k: usize) -> usize {
        let (a, b) = (&self.chains[i], &self.chains[k]);
        a.iter().zip(b).take_while(|(x, y)| x == y).count()
    }

    /// The turns that move points `i` and `k` relative to each other, in the group's order.
    fn between(&self, i: usize, k: usize) -> Vec<usize> {
        let skip = self.shared(i, k);
        let mut turns: Vec<usize> = self.chains[i][skip..]
            .iter()
            .chain(&self.chains[k][skip..])
            .copied()
            .collect();
        turns.sort_unstable();
        turns.dedup();
        turns
    }
}

/// Every point where the middle of one box puts it, and the chords that bound how far the box
/// moves it, from each level of its chain in: the first test of every pair, which clears most
/// of them, at the cost of one pass over the points instead of one per pair. Turns shared by
/// two points move both rigidly, so the distance of the whole positions is theirs.
struct Whole {
    positions: Vec<[f64; 3]>,
    /// `reach_from[m][l]`: the chords of point `m`'s turns from chain level `l` in.
    reach_from: Vec<Vec<f64>>,
}

impl Whole {
    fn of(linkage: &Linkage, points: &Points, (centre, half): (&[f64], &[f64])) -> Whole {
        let mut positions = Vec::with_capacity(points.len());
        let mut reach_from = Vec::with_capacity(points.len());
        for (m, (_, p)) in points.iter().enumerate() {
            let chain = &linkage.chains[m];
            let mut suffix = vec![0.0; chain.len() + 1];
            let mut q = *p;
            for (level, &t) in chain.iter().enumerate().rev() {
                let side = &linkage.sides[t];
                suffix[level] = suffix[level + 1] + side.chord(q, half[t]);
                q = side.leg().position_at(q, centre[t]);
            }
            positions.push(q);
            reach_from.push(suffix);
        }
        Whole {
            positions,
            reach_from,
        }
    }

    /// The lower bound over the whole box of the distance of points `i` and `k`, which share
    /// their first `skip` turns.
    fn bound(&self, i: usize, k: usize, skip: usize) -> f64 {
        distance(self.positions[i], self.positions[k])
            - self.reach_from[i][skip]
            - self.reach_from[k][skip]
    }
}

/// One point of each rigid body the turns cut the robot into (points moved by the same
/// turns), in point order: the candidates for the still point.
fn body_representatives(sides: &[Side], points: usize) -> Vec<usize> {
    let mut seen: Vec<Vec<bool>> = Vec::new();
    let mut out = Vec::new();
    for m in 0..points {
        let signature: Vec<bool> = sides.iter().map(|s| s.moves[m]).collect();
        if !seen.iter().any(|other| other.iter().eq(&signature)) {
            seen.push(signature);
            out.push(m);
        }
    }
    out
}

/// Each turn's depth (how many turns carry it) when every two are apart or one carries the
/// other; `None` otherwise. A turn that moves no point is apart from every other.
fn nesting(sides: &[Side]) -> Option<Vec<usize>> {
    let mut depths = vec![0; sides.len()];
    for (x, a) in sides.iter().enumerate() {
        for (y, b) in sides.iter().enumerate().skip(x + 1) {
            let idle = |s: &Side| !s.moves.iter().any(|&m| m);
            let apart = a.apart_from(b) && !a.moves_any(&b.turner) && !b.moves_any(&a.turner);
            if idle(a) || idle(b) || apart {
                continue;
            }
            if a.carries(b) {
                depths[y] += 1;
            } else if b.carries(a) {
                depths[x] += 1;
            } else {
                return None;
            }
        }
    }
    Some(depths)
}

/// The turns of a group (each motion with its module's index), the robot's sweep points and
/// their linkage; `None` when the robot gives no sweep points, a motion is not one rotation
/// of some of them, or the turns are not on a tree.
fn linkage_of(turns: &[(&Motion, usize)], world: &RobotWorld) -> Option<Linked> {
    let points = Indexed::new(world.model().sweep_points()?);
    let sides = turns
        .iter()
        .map(|(motion, turner)| Side::of(motion, *turner, world, &points))
        .collect::<Option<Vec<Side>>>()?;
    let linkage = Linkage::of(&sides, points.points.len())?;
    Some((points.points, linkage))
}

/// The approach of every two points of the robot under `turns` (each motion with its
/// module's index) done together, over every relative timing; `None` when the linkage
/// cannot be made (`linkage_of`).
pub(crate) fn turns_together(turns: &[(&Motion, usize)], world: &RobotWorld) -> Option<Together> {
    turns_at(turns, world, &Timings::every(), Pairs::MovedByTwo)
}

/// The robot's own check of the group, where the timings are one it takes: every relative
/// timing, or every turn in one synchronous group (turns in and out of one are searched here).
fn robot_check(
    turns: &[(&Motion, usize)],
    world: &RobotWorld,
    timings: &Timings,
) -> Option<GroupVerdict> {
    let sets: Vec<Option<usize>> = (0..turns.len()).map(|t| timings.set_of(t)).collect();
    let skew = match sets.first().copied().flatten() {
        None if sets.iter().all(Option::is_none) => None,
        Some(set) if sets.iter().all(|s| *s == Some(set)) => Some(timings.skew),
        _ => return None,
    };
    world.model().turns_together(turns, skew)
}

/// A robot's own verdict on a group (`RobotModel::turns_together`) as the search's: the
/// approach is put on every turn of the group, the robot not saying which bring it about.
fn robot_verdict(verdict: GroupVerdict, turns: usize) -> Together {
    let approach = |distance, modules| Approach {
        distance,
        modules,
        turns: (0..turns).collect(),
        rule: None,
    };
    match verdict {
        GroupVerdict::Clear => Together::Clear,
        GroupVerdict::Closest { distance, modules } => {
            Together::Closest(approach(distance, modules))
        }
        GroupVerdict::Unproven { distance, modules } => {
            Together::Unproven(approach(distance, modules))
        }
        GroupVerdict::Refused { modules, reason } => Together::Closest(Approach {
            rule: Some(reason),
            ..approach(0.0, modules)
        }),
    }
}

/// Which pairs of points a search covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pairs {
    /// Those at least two turns move relative to each other: the others are each turn's own
    /// sweep, which the world checks when it applies the turn.
    MovedByTwo,
    /// Every pair a turn moves relative to another: the world applies these turns without
    /// their own sweeps (`SweepCheck::WithOthers`), which this search then includes.
    All,
}

/// [`turns_together`] over the relative timings `timings` allows, on the pairs `pairs`
/// says.
pub(crate) fn turns_at(
    turns: &[(&Motion, usize)],
    world: &RobotWorld,
    timings: &Timings,
    pairs: Pairs,
) -> Option<Together> {
    if let Some(verdict) = robot_check(turns, world, timings) {
        return Some(robot_verdict(verdict, turns.len()));
    }
    let (points, linkage) = linkage_of(turns, world)?;
    let limit = turns.iter().map(|(m, _)| m.limit).fold(0.0, f64::max);
    let mut bar = limit;
    let mut budget = MAX_BOXES_PER_GROUP;
    let mut closest: Option<Approach> = None;
    let mut unproven: Option<Approach> = None;
    let whole = Whole::of(
        &linkage,
        &points,
        (&vec![0.5; turns.len()], &vec![0.5; turns.len()]),
    );
    for (i, k, skip) in moving_pairs(&linkage, points.len(), pairs) {
        if whole.bound(i, k, skip) >= bar {
            continue;
        }
        let pair = Pair {
            linkage: &linkage,
            points: ((i, points[i].1), (k, points[k].1)),
            turns: turns.len(),
            timings,
        };
        let approach = |distance: f64| Approach {
            distance,
            modules: (points[i].0, points[k].0),
            turns: linkage.between(i, k),
            rule: None,
        };
        match pair.approach(bar, &mut budget) {
            Search::Clear => {}
            Search::Below(d) => {
                closest = Some(approach(d));
                bar = d;
            }
            Search::Unproven(bound) => {
                if unproven.as_ref().is_none_or(|u| bound < u.distance) {
                    unproven = Some(approach(bound));
                }
            }
        }
    }
    Some(match (closest, unproven) {
        (Some(found), _) => Together::Closest(found),
        (None, Some(bound)) => Together::Unproven(bound),
        (None, None) => Together::Clear,
    })
}

/// Two modules closer than the limit while turns run at once.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// When it first happens, as a fraction of the stretch of time searched.
    pub at: f64,
    /// The two modules (indices), lower first.
    pub modules: (usize, usize),
    /// How far apart they are then.
    pub distance: f64,
    /// The turns (indices into the group searched, in order) that move them relative to
    /// each other.
    pub turns: Vec<usize>,
}

/// What turns running at once do over a stretch of time.
#[derive(Clone, Debug, PartialEq)]
pub enum Along {
    /// Every two modules stay at least the limit apart.
    Clear,
    /// The first moment two modules are closer than the limit.
    Contact(Contact),
    /// Not turns this search composes (not one rotation of whole modules each, not a tree).
    Unknown,
}

/// The least width of a piece of the stretch the search of the first contact splits (its
/// time resolution, as a fraction of the stretch).
const CONTACT_RESOLUTION: f64 = 1e-6;

/// `turns` (each motion with its module's index) running at once over a stretch of time
/// along which each turn's fraction goes linearly from `from[t]` to `to[t]`: the first moment
/// two modules (of the pairs `pairs` says) come closer than the limit. Exact to [`CONTACT_RESOLUTION`] of the stretch: a
/// piece of it is a thin box of the fractions, bounded as the group check bounds its boxes,
/// and pieces are searched earliest first.
pub fn first_contact(
    turns: &[(&Motion, usize)],
    (from, to): (&[f64], &[f64]),
    world: &RobotWorld,
    pairs: Pairs,
) -> Along {
    if from.len() != turns.len() || to.len() != turns.len() {
        return Along::Unknown;
    }
    let Some((points, linkage)) = linkage_of(turns, world) else {
        return Along::Unknown;
    };
    let at = |u: f64| -> Vec<f64> { from.iter().zip(to).map(|(f, t)| f + (t - f) * u).collect() };
    let limit = turns.iter().map(|(m, _)| m.limit).fold(0.0, f64::max);
    let mut first: Option<Contact> = None;
    let centre = at(0.5);
    let half: Vec<f64> = from
        .iter()
        .zip(to)
        .map(|(f, t)| (t - f).abs() / 2.0)
        .collect();
    let whole = Whole::of(&linkage, &points, (&centre, &half));
    for (i, k, skip) in moving_pairs(&linkage, points.len(), pairs) {
        if whole.bound(i, k, skip) >= limit {
            continue;
        }
        let piece = |u0: f64, u1: f64| {
            let centre = at((u0 + u1) / 2.0);
            let half: Vec<f64> = from
                .iter()
                .zip(to)
                .map(|(f, t)| (t - f).abs() * (u1 - u0) / 2.0)
                .collect();
            let mut weights = vec![0.0; turns.len()];
            let box_ = (centre.as_slice(), half.as_slice());
            linkage.apart((points[i].1, points[k].1), (i, k, skip), box_, &mut weights)
        };
        let before = first.as_ref().map_or(1.0, |c| c.at);
        if let Some((u, d)) = earliest_below(&piece, limit, before) {
            first = Some(Contact {
                at: u,
                modules: (points[i].0, points[k].0),
                distance: d,
                turns: linkage.between(i, k),
            });
        }
    }
    first.map_or(Along::Clear, Along::Contact)
}

/// The earliest `u` in `[0, before]` at which two points are below `limit` apart, to
/// [`CONTACT_RESOLUTION`], with the distance there; `piece(u0, u1)` gives their distance at
/// the middle of `[u0, u1]` and a lower bound over all of it.
fn earliest_below(
    piece: &dyn Fn(f64, f64) -> (f64, f64),
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
        let (d, bound) = piece(u0, u1);
        if d < limit && u1 - u0 <= CONTACT_RESOLUTION {
            return Some((middle, d));
        }
        if d < limit {
            found = Some((middle, d));
        }
        if bound >= limit {
            continue;
        }
        if u1 - u0 > CONTACT_RESOLUTION {
            pieces.push((middle, u1));
            pieces.push((u0, middle));
        }
    }
    found
}

/// Every two points that at least two turns (with [`Pairs::All`], one) move relative to each
/// other (lower index first in each, the moving points in order), with how many turns they
/// share; the still body's pairs
/// with itself are never visited, so the cost is the moving points times all of them.
fn moving_pairs(linkage: &Linkage, n: usize, which: Pairs) -> Vec<(usize, usize, usize)> {
    let least = match which {
        Pairs::MovedByTwo => 2,
        Pairs::All => 1,
    };
    let body = linkage.bodies();
    let moving = |m: usize| !linkage.chains[m].is_empty();
    let mut pairs = Vec::new();
    for i in (0..n).filter(|&i| moving(i)) {
        for k in 0..n {
            if body[i] == body[k] || (moving(k) && k < i) {
                continue;
            }
            // Two points only one turn moves apart are where that turn alone puts them, at
            // every timing of the others: its own sweep, which the replay checks. Past the
            // turns two points share, their chains have no turn in common.
            let skip = linkage.shared(i, k);
            let apart = linkage.chains[i].len() + linkage.chains[k].len() - 2 * skip;
            if apart >= least {
                pairs.push((i.min(k), i.max(k), skip));
            }
        }
    }
    pairs
}

/// Two points (index and start position) under a linkage of `turns` turns.
struct Pair<'l> {
    linkage: &'l Linkage,
    points: ((usize, [f64; 3]), (usize, [f64; 3])),
    turns: usize,
    timings: &'l Timings,
}

enum Search {
    Clear,
    Below(f64),
    Unproven(f64),
}

impl Pair<'_> {
    /// Branch and bound over the box of the turns that move the two points apart: boxes are
    /// taken lowest bound first (so the search ends as soon as no box can beat the bar) and
    /// split across the turn whose chord is longest. Each box taken spends one of `budget`.
    fn approach(&self, bar: f64, budget: &mut usize) -> Search {
        let ((i, _), (k, _)) = self.points;
        let dims = self.linkage.between(i, k);
        let mut boxes = BinaryHeap::new();
        boxes.push(self.piece(vec![(0.0, 1.0); dims.len()], &dims));
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
                return best.map_or(Search::Clear, Search::Below);
            }
            // The middle is a timing found only where the timings allow it.
            if piece.centre_distance < bar && self.timings.holds(&piece.middle(), &dims) {
                best = Some(piece.centre_distance);
                bar = piece.centre_distance;
            }
            if *budget == 0 {
                boxes.push(piece);
                break;
            }
            *budget -= 1;
            for half in piece.halves() {
                // A box of timings none of which is allowed is not searched.
                if self.timings.meets(&half, &dims) {
                    boxes.push(self.piece(half, &dims));
                }
            }
        }
        match (best, boxes.peek()) {
            (Some(d), _) => Search::Below(d),
            (None, Some(lowest)) if lowest.bound < bar => Search::Unproven(lowest.bound.max(0.0)),
            (None, _) => Search::Clear,
        }
    }

    /// A box of the fractions of `dims` (`area[j]` is turn `dims[j]`'s range) with its
    /// middle's distance, its lower bound and each turn's chord there.
    fn piece(&self, area: Vec<(f64, f64)>, dims: &[usize]) -> Piece {
        let ((i, p), (k, q)) = self.points;
        let mut centre = vec![0.0; self.turns];
        let mut half = vec![0.0; self.turns];
        for (j, &(lo, hi)) in area.iter().enumerate() {
            centre[dims[j]] = (lo + hi) / 2.0;
            half[dims[j]] = (hi - lo) / 2.0;
        }
        let skip = self.linkage.shared(i, k);
        let mut weights = vec![0.0; self.turns];
        let box_ = (centre.as_slice(), half.as_slice());
        let (d, bound) = self.linkage.apart((p, q), (i, k, skip), box_, &mut weights);
        let widest = (0..dims.len())
            .max_by(|&x, &y| {
                weights[dims[x]]
                    .total_cmp(&weights[dims[y]])
                    .then(y.cmp(&x))
            })
            .unwrap_or(0);
        Piece {
            bound,
            centre_distance: d,
            widest,
            area,
        }
    }
}

/// A box of the search, ordered so that the heap gives the lowest bound first.
struct Piece {
    bound: f64,
    centre_distance: f64,
    /// The dimension to split: the turn with the longest chord.
    widest: usize,
    area: Vec<(f64, f64)>,
}

impl Piece {
    /// The fractions at its middle, one per dimension.
    fn middle(&self) -> Vec<f64> {
        self.area.iter().map(|(lo, hi)| (lo + hi) / 2.0).collect()
    }

    /// The two halves of the box across its widest dimension.
    fn halves(&self) -> [Vec<(f64, f64)>; 2] {
        let (lo, hi) = self.area.get(self.widest).copied().unwrap_or((0.0, 0.0));
        let middle = (lo + hi) / 2.0;
        let (mut low, mut high) = (self.area.clone(), self.area.clone());
        if let (Some(l), Some(h)) = (low.get_mut(self.widest), high.get_mut(self.widest)) {
            *l = (lo, middle);
            *h = (middle, hi);
        }
        [low, high]
    }
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
        // Reversed: `BinaryHeap` is a max-heap. Ties by the boxes' corners keep the order
        // total, so the search is the same on every run.
        other.bound.total_cmp(&self.bound).then_with(|| {
            (other.area.iter().zip(&self.area))
                .map(|(x, y)| x.0.total_cmp(&y.0))
                .find(|o| o.is_ne())
                .unwrap_or(Ordering::Equal)
        })
    }
}

/// Whether two chains hold the same turns, compared element by element: chains are a few
/// turns long, for which a call to compare memory costs more than the comparison.
fn same_turns(a: &[usize], b: &[usize]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x == y)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| a[k] * b[k]).sum()
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm(std::array::from_fn(|k| a[k] - b[k]))
}

#[cfg(test)]
#[path = "../tests/unit/simultaneous.rs"]
mod tests;
