//! Joint turns of RoFI modules checked along their whole motion, not at samples: a group of
//! turns done at once, over every relative timing (each turn anywhere in its motion while the
//! others are anywhere in theirs) or in lock-step, proven to keep every two shoes of
//! different modules apart, or shown to bring two together (at which fractions), or, past a
//! budget of pieces, reported unproven with its lower bound.
//!
//! The bound: shoes are placed along a spanning tree of the modules (each module's own
//! joints always a tree edge). A turn moves two shoes relative to each other only when its
//! module lies between them on the tree, and then by at most its angle (in radians) times the
//! distance of either shoe from the joint's axis, which is at most the number of tree links
//! (each one unit) from the shoe to the axis. So over a piece of the box of fractions whose
//! half-widths are h, two shoes at distance d at its centre stay at least
//! d − min(Σ |Δθ_i| h_i r_i(a), Σ |Δθ_i| h_i r_i(b)) apart; a second-order bound (`least`),
//! from the exact derivatives at the centre, proves pairs that end touching. Pieces, the one
//! proven least first, are halved along the turn with the largest |Δθ_i| h_i until every
//! pair is proven apart, one is found overlapping at a piece's centre, or the budget is spent.
//! "Apart" is proven to within `SWEEP_TOLERANCE` (shoes that end mated are exactly one unit
//! apart there), and every point evaluated is held to RoFI's own limit. RoFI's own tools check
//! a step at ten samples of the lock-step timing only.

use crate::kinematics::centre_of as centre;
use crate::module::{Connection, Joint, Module, RofiConfiguration};
use crate::tree::{Shoe, Tree};
use crate::validity::{Collision, COLLISION_DISTANCE_SQUARED};
use nalgebra::{Matrix4, Point3, Vector3};
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::fmt;

/// Pieces of the box examined before a group is reported unproven.
pub const SWEEP_BUDGET: usize = 100_000;

/// How much closer than one unit two shoes may be proven to come for a motion to be called
/// clear (0.01 unit: 1 mm on RoFI's 10 cm module). Shoes that end mated, or touch on the way,
/// are exactly one unit apart there, which no bound of finite pieces proves; every point
/// the search evaluates is still held to RoFI's own limit (`COLLISION_DISTANCE_SQUARED`).
pub const SWEEP_TOLERANCE: f64 = 0.01;

/// One joint turned from `from` by `by` degrees (signed: gamma's direction is in the sign).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turn {
    pub module: u32,
    pub joint: Joint,
    pub from: f64,
    pub by: f64,
}

/// How the turns of a group run relative to each other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Timing {
    /// Every relative timing: each turn's fraction independent of the others'.
    Every,
    /// Lock-step: every turn at the same fraction of its motion.
    LockStep,
    /// Lock-step within a skew: the turns' fractions at most this far apart (0 to 1), as a
    /// synchronous group's start allows. Searched as `Every` over the pieces of the box that
    /// hold such timings; a piece holding none is dropped, and a verdict is given only at a
    /// piece's centre that is one.
    Band(f64),
}

/// What the motion of a group does.
#[derive(Clone, Debug, PartialEq)]
pub enum SweepVerdict {
    /// No two shoes of different modules come closer than one unit less `SWEEP_TOLERANCE`
    /// anywhere, nor closer than RoFI's limit at any point evaluated.
    Clear,
    /// Two shoes overlap with the turns at these fractions of their motions.
    Collides {
        fractions: Vec<f64>,
        collision: Collision,
    },
    /// A loop of connections does not stay closed with the turns at these fractions.
    OpensLoop {
        fractions: Vec<f64>,
        connection: Connection,
    },
    /// The budget ran out: the closest the check could prove the two shoes stay.
    Unproven {
        lower_bound: f64,
        shoes: (Shoe, Shoe),
    },
}

/// Why a group of turns cannot be checked.
#[derive(Clone, Debug, PartialEq)]
pub enum SweepError {
    UnknownModule(u32),
    /// The joint is not at the turn's start angle.
    NotAtStart {
        turn: Turn,
        now: f64,
    },
    /// Alpha or beta would leave ±90 degrees.
    OutOfRange(Turn),
    /// Two turns of one joint in one group.
    SameJoint(Turn),
    /// The configuration is not connected.
    NotConnected,
}

impl fmt::Display for SweepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SweepError::UnknownModule(id) => write!(f, "no module {id}"),
            SweepError::NotAtStart { turn, now } => write!(
                f,
                "module {}: {} is at {now} degrees, not at the turn's start {}",
                turn.module,
                turn.joint.name(),
                turn.from
            ),
            SweepError::OutOfRange(turn) => write!(
                f,
                "module {}: {} would turn to {} degrees, outside -90..90",
                turn.module,
                turn.joint.name(),
                turn.from + turn.by
            ),
            SweepError::SameJoint(turn) => write!(
                f,
                "module {}: {} is turned twice in one group",
                turn.module,
                turn.joint.name()
            ),
            SweepError::NotConnected => write!(f, "the configuration is not connected"),
        }
    }
}

/// Checks the motion of `turns` done together from `config` (valid at the start) with the
/// given timing.
pub fn sweep(
    config: &RofiConfiguration,
    turns: &[Turn],
    timing: Timing,
) -> Result<SweepVerdict, SweepError> {
    sweep_within(config, turns, timing, SWEEP_BUDGET)
}

/// [`sweep`] with another budget of pieces (a smaller one answers "unproven" sooner).
pub fn sweep_within(
    config: &RofiConfiguration,
    turns: &[Turn],
    timing: Timing,
    budget: usize,
) -> Result<SweepVerdict, SweepError> {
    check_turns(config, turns)?;
    let tree = Tree::of(config).map_err(|_| SweepError::NotConnected)?;
    let search = Search::new(&tree, turns, timing);
    Ok(search.run(budget))
}

fn check_turns(config: &RofiConfiguration, turns: &[Turn]) -> Result<(), SweepError> {
    for (i, turn) in turns.iter().enumerate() {
        let module = config
            .module(turn.module)
            .ok_or(SweepError::UnknownModule(turn.module))?;
        let now = module.joint(turn.joint);
        let same = match turn.joint {
            Joint::Gamma => crate::module::circular(now - turn.from).abs() < 1e-9,
            _ => (now - turn.from).abs() < 1e-9,
        };
        if !same {
            return Err(SweepError::NotAtStart { turn: *turn, now });
        }
        let end = turn.from + turn.by;
        if turn.joint != Joint::Gamma && end.abs() > crate::module::SHOE_JOINT_LIMIT_DEG {
            return Err(SweepError::OutOfRange(*turn));
        }
        let earlier = &turns[..i];
        if earlier
            .iter()
            .any(|t| t.module == turn.module && t.joint == turn.joint)
        {
            return Err(SweepError::SameJoint(*turn));
        }
    }
    Ok(())
}

/// A piece waiting in the search's queue, first the one proven least.
struct Queued {
    piece: Piece,
    made: usize,
}

impl Queued {
    fn new(piece: Piece, made: usize) -> Queued {
        Queued { piece, made }
    }
}

impl Ord for Queued {
    fn cmp(&self, other: &Self) -> Ordering {
        // The heap pops its greatest: the smallest bound, then the earliest made.
        (other.piece.lower.0.total_cmp(&self.piece.lower.0)).then(other.made.cmp(&self.made))
    }
}

impl PartialOrd for Queued {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Queued {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Queued {}

/// The turns as the search needs them: which module's link each one crosses and how far
/// every shoe is from its axis.
struct Search<'t> {
    tree: &'t Tree,
    turns: Vec<Turn>,
    /// The far shoe of each turn's module link (its subtree is one side of the turn).
    far: Vec<usize>,
    /// Per turn, every shoe's tree links to the turn's axis.
    reach: Vec<Vec<usize>>,
    timing: Timing,
}

/// A piece of the box: its centre and half-widths, and the pairs not yet proven apart on it.
struct Piece {
    centre: Vec<f64>,
    half: Vec<f64>,
    pairs: Vec<(usize, usize)>,
    /// What its parent proved of it: every pair stays at least this far apart on it (the
    /// closest pair named), which is what is reported if the budget runs out.
    lower: (f64, (usize, usize)),
}

impl<'t> Search<'t> {
    fn new(tree: &'t Tree, turns: &[Turn], timing: Timing) -> Self {
        let mut far = Vec::new();
        let mut reach = Vec::new();
        for turn in turns {
            let m = tree.index.get(&turn.module).copied().unwrap_or(0);
            let (a, b) = (m * 2, m * 2 + 1);
            far.push(if tree.parent[b] == Some(a) { b } else { a });
            let from_a = tree.hops_from(a);
            let from_b = tree.hops_from(b);
            let hops: Vec<usize> = match turn.joint {
                Joint::Alpha => from_a,
                Joint::Beta => from_b,
                Joint::Gamma => from_a.iter().zip(&from_b).map(|(x, y)| *x.min(y)).collect(),
            };
            reach.push(hops);
        }
        Search {
            tree,
            turns: turns.to_vec(),
            far,
            reach,
            timing,
        }
    }

    fn dimensions(&self) -> usize {
        match self.timing {
            Timing::Every | Timing::Band(_) => self.turns.len(),
            Timing::LockStep => usize::from(!self.turns.is_empty()),
        }
    }

    /// Each turn's fraction at a point of the box.
    fn fractions(&self, point: &[f64]) -> Vec<f64> {
        match self.timing {
            Timing::Every | Timing::Band(_) => point.to_vec(),
            Timing::LockStep => vec![point.first().copied().unwrap_or(0.0); self.turns.len()],
        }
    }

    /// The modules with the turns at `fractions`.
    fn modules_at(&self, fractions: &[f64]) -> Vec<Module> {
        let mut modules = self.tree.modules.clone();
        for (turn, t) in self.turns.iter().zip(fractions) {
            let m = self.tree.index.get(&turn.module).copied().unwrap_or(0);
            let angle = turn.from + t * turn.by;
            match turn.joint {
                Joint::Alpha => modules[m].alpha = angle,
                Joint::Beta => modules[m].beta = angle,
                Joint::Gamma => modules[m].gamma = angle,
            }
        }
        modules
    }

    /// The pairs of shoes of different modules that some turn moves relative to each other.
    fn moving_pairs(&self) -> Vec<(usize, usize)> {
        let n = self.tree.parent.len();
        let mut pairs = Vec::new();
        for a in 0..n {
            for b in (a + 1)..n {
                if a / 2 != b / 2 && self.crossing(a, b).next().is_some() {
                    pairs.push((a, b));
                }
            }
        }
        pairs
    }

    /// The turns whose module link lies between shoes `a` and `b` on the tree.
    fn crossing(&self, a: usize, b: usize) -> impl Iterator<Item = usize> + '_ {
        (0..self.turns.len())
            .filter(move |&i| self.tree.within(a, self.far[i]) != self.tree.within(b, self.far[i]))
    }

    /// How far `a` and `b` can move relative to each other over a piece of half-widths `half`
    /// (per turn): through `a`'s distances to the axes, through `b`'s, and the larger.
    fn reaches(&self, (a, b): (usize, usize), half: &[f64]) -> (f64, f64) {
        let (mut via_a, mut via_b) = (0.0, 0.0);
        for i in self.crossing(a, b) {
            let swing = self.turns[i].by.to_radians().abs() * half[i];
            via_a += swing * self.reach[i][a] as f64;
            via_b += swing * self.reach[i][b] as f64;
        }
        (f64::min(via_a, via_b), f64::max(via_a, via_b))
    }

    /// The least distance of `a` and `b` over a piece of half-widths `half` whose centre has
    /// `poses`: the better of the first-order bound (d less how far they can move) and the
    /// second-order one (d less the exact first-order change, less what the turns' second
    /// derivatives allow: two turns' mixed derivative of a point is at most twice their rates
    /// times its distance from the later axis, hence (Σ rates) times the larger reach).
    fn least(&self, (a, b): (usize, usize), half: &[f64], poses: &[Matrix4<f64>]) -> f64 {
        let (pa, pb) = (centre(&poses[a]), centre(&poses[b]));
        let d = (pa - pb).norm();
        let (first, largest) = self.reaches((a, b), half);
        let rates: f64 = (self.crossing(a, b))
            .map(|i| self.turns[i].by.to_radians().abs() * half[i])
            .sum();
        let direction = (pa - pb) / d.max(f64::MIN_POSITIVE);
        let linear: f64 = (self.crossing(a, b))
            .map(|i| (direction.dot(&self.velocity(i, (a, b), poses)) * half[i]).abs())
            .sum();
        f64::max(d - first, d - linear - rates * largest)
    }

    /// d(p_a − p_b)/d(fraction of turn `i`) with the turns at the poses' fractions: the shoe
    /// on the turn's far side rotates about the joint's axis at the turn's rate.
    fn velocity(&self, i: usize, (a, b): (usize, usize), poses: &[Matrix4<f64>]) -> Vector3<f64> {
        let far = self.far[i];
        let near = far ^ 1;
        let (axis, through, sign) = self.axis(i, poses, (near, far));
        let rate = sign * self.turns[i].by.to_radians();
        let spin = |x: usize| axis.cross(&(centre(&poses[x]) - through)) * rate;
        if self.tree.within(a, far) {
            spin(a)
        } else {
            -spin(b)
        }
    }

    /// Turn `i`'s axis (unit, world frame), a point on it, and the sense in which its far side
    /// turns when the angle grows: alpha about shoe A's X axis, beta about shoe B's (each
    /// joint's angle enters the frame of the side it is on negated), gamma about the line
    /// from the near shoe to the far one.
    fn axis(
        &self,
        i: usize,
        poses: &[Matrix4<f64>],
        (near, far): (usize, usize),
    ) -> (Vector3<f64>, Point3<f64>, f64) {
        let x_axis = |shoe: usize| {
            let p = &poses[shoe];
            Vector3::new(p[(0, 0)], p[(1, 0)], p[(2, 0)])
        };
        let far_is_b = far % 2 == 1;
        let (a_shoe, b_shoe) = if far_is_b { (near, far) } else { (far, near) };
        match self.turns[i].joint {
            Joint::Alpha => {
                let sign = if far_is_b { 1.0 } else { -1.0 };
                (x_axis(a_shoe), centre(&poses[a_shoe]), sign)
            }
            Joint::Beta => {
                let sign = if far_is_b { -1.0 } else { 1.0 };
                (x_axis(b_shoe), centre(&poses[b_shoe]), sign)
            }
            Joint::Gamma => {
                let from = centre(&poses[near]);
                let along = (centre(&poses[far]) - from).normalize();
                (along, from, 1.0)
            }
        }
    }

    fn run(&self, budget: usize) -> SweepVerdict {
        let dims = self.dimensions();
        let pairs = self.moving_pairs();
        if dims == 0 || pairs.is_empty() {
            return SweepVerdict::Clear;
        }
        let first = pairs[0];
        let root = Piece {
            centre: vec![0.5; dims],
            half: vec![0.5; dims],
            pairs,
            lower: (0.0, first),
        };
        // The piece proven least first (ties: the earliest made): a real overlap is found at
        // a coarse level, and shoes that only touch are refined last.
        let mut queue = BinaryHeap::from([Queued::new(root, 0)]);
        let limit = 1.0 - SWEEP_TOLERANCE;
        let mut made = 1;
        let mut examined = 0;
        while let Some(Queued { piece, .. }) = queue.pop() {
            examined += 1;
            if examined > budget {
                queue.push(Queued::new(piece, made));
                return self.unproven(&queue);
            }
            let fractions = self.fractions(&piece.centre);
            let modules = self.modules_at(&fractions);
            let poses = self.tree.poses(&modules);
            // Outside a band, a centre proves nothing wrong: its piece is only refined.
            let a_timing = self.holds(&piece.centre, &piece.centre);
            if let (true, Some((connection, _))) = (a_timing, self.tree.open_loop(&poses)) {
                return SweepVerdict::OpensLoop {
                    fractions,
                    connection,
                };
            }
            let half = self.fractions(&piece.half);
            let mut pending = Vec::new();
            let mut lower = (f64::INFINITY, first);
            for &(a, b) in &piece.pairs {
                let d = (centre(&poses[a]) - centre(&poses[b])).norm();
                if a_timing && d * d < COLLISION_DISTANCE_SQUARED {
                    let shoes = (self.tree.shoe_of(a), self.tree.shoe_of(b));
                    let collision = Collision { shoes, distance: d };
                    return SweepVerdict::Collides {
                        fractions,
                        collision,
                    };
                }
                let proven = self.least((a, b), &half, &poses);
                if proven < limit {
                    pending.push((a, b));
                    if proven < lower.0 {
                        lower = (proven.max(0.0), (a, b));
                    }
                }
            }
            if !pending.is_empty() {
                for half in self.halves(&piece, pending, lower) {
                    let (low, high) = bounds(&half);
                    if self.holds(&low, &high) {
                        queue.push(Queued::new(half, made));
                        made += 1;
                    }
                }
            }
        }
        SweepVerdict::Clear
    }

    /// Whether the box from `low` to `high` holds a timing of the search: always, but for a
    /// band, whose timings have fractions at most its width apart.
    fn holds(&self, low: &[f64], high: &[f64]) -> bool {
        let Timing::Band(width) = self.timing else {
            return true;
        };
        let highest_low = low.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let lowest_high = high.iter().copied().fold(f64::INFINITY, f64::min);
        highest_low - lowest_high <= width
    }

    /// The verdict when the budget is spent: the least that the pieces left are proven to
    /// keep, each by the piece it was halved from.
    fn unproven(&self, left: &BinaryHeap<Queued>) -> SweepVerdict {
        let least = (left.iter().map(|q| q.piece.lower))
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .unwrap_or((0.0, (0, 0)));
        let (lower_bound, (a, b)) = least;
        let shoes = (self.tree.shoe_of(a), self.tree.shoe_of(b));
        SweepVerdict::Unproven { lower_bound, shoes }
    }

    /// The piece halved along the dimension that swings most.
    fn halves(
        &self,
        piece: &Piece,
        pairs: Vec<(usize, usize)>,
        lower: (f64, (usize, usize)),
    ) -> [Piece; 2] {
        let swing = |k: usize| match self.timing {
            Timing::Every | Timing::Band(_) => self.turns[k].by.abs() * piece.half[k],
            Timing::LockStep => piece.half[k],
        };
        let k = (0..piece.half.len())
            .max_by(|&x, &y| swing(x).total_cmp(&swing(y)))
            .unwrap_or(0);
        let mut half = piece.half.clone();
        half[k] /= 2.0;
        let mut low = piece.centre.clone();
        low[k] -= half[k];
        let mut high = piece.centre.clone();
        high[k] += half[k];
        [
            Piece {
                centre: low,
                half: half.clone(),
                pairs: pairs.clone(),
                lower,
            },
            Piece {
                centre: high,
                half,
                pairs,
                lower,
            },
        ]
    }
}

/// A piece's corners: each dimension's low and high end.
fn bounds(piece: &Piece) -> (Vec<f64>, Vec<f64>) {
    let each = |sign: f64| {
        (piece.centre.iter().zip(&piece.half))
            .map(|(c, h)| c + sign * h)
            .collect()
    };
    (each(-1.0), each(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::module::{Connector, Dock, Orientation, Side};

    /// Chains of three modules at every dock pair and several twists and angles.
    fn chains() -> Vec<RofiConfiguration> {
        let mut out = Vec::new();
        for (k, d1) in Dock::ALL.into_iter().enumerate() {
            for (j, d2) in Dock::ALL.into_iter().enumerate() {
                let o = Orientation::ALL[(k + j) % 4];
                let angle = |x: usize| (x as f64 * 37.0) % 180.0 - 90.0;
                let modules = [
                    Module::new(1, angle(k), angle(j + 1), angle(k + j) * 2.0),
                    Module::new(2, angle(j + 2), angle(k + 3), angle(j) * 2.0),
                    Module::new(3, angle(k + 5), angle(j + 4), 30.0),
                ];
                // Modules 2 and 3 entered by either shoe: the tree crosses them both ways.
                for (entry2, entry3) in [(Side::A, Side::A), (Side::B, Side::B)] {
                    let edges = [
                        Connection {
                            from: (1, Connector::new(Side::B, d1)),
                            orientation: o,
                            to: (2, Connector::new(entry2, d2)),
                        },
                        Connection {
                            from: (3, Connector::new(entry3, d1)),
                            orientation: Orientation::ALL[j % 4],
                            to: (2, Connector::new(entry2.other(), d2)),
                        },
                    ];
                    if let Ok(c) = RofiConfiguration::from_parts(&modules, &edges) {
                        out.push(c);
                    }
                }
            }
        }
        out
    }

    #[test]
    fn the_velocity_of_a_pair_is_the_derivative_of_their_offset() {
        let mut checked = 0;
        for config in chains() {
            let turns: Vec<Turn> = (config.modules())
                .flat_map(|m| Joint::ALL.map(|joint| (m, joint)))
                .map(|(m, joint)| Turn {
                    module: m.id,
                    joint,
                    from: m.joint(joint),
                    by: if joint == Joint::Gamma {
                        50.0
                    } else {
                        -m.joint(joint) * 0.5
                    },
                })
                .collect();
            let tree = Tree::of(&config).expect("a chain");
            let search = Search::new(&tree, &turns, Timing::Every);
            let point = vec![0.4; turns.len()];
            let poses_at = |t: &[f64]| tree.poses(&search.modules_at(t));
            let poses = poses_at(&point);
            for (a, b) in search.moving_pairs() {
                for i in search.crossing(a, b) {
                    let step = 1e-6;
                    let mut up = point.clone();
                    up[i] += step;
                    let mut down = point.clone();
                    down[i] -= step;
                    let offset = |p: &[Matrix4<f64>]| centre(&p[a]) - centre(&p[b]);
                    let numeric =
                        (offset(&poses_at(&up)) - offset(&poses_at(&down))) / (2.0 * step);
                    let exact = search.velocity(i, (a, b), &poses);
                    assert!(
                        (numeric - exact).norm() < 1e-5,
                        "turn {:?}, shoes {a} {b}: {numeric} against {exact}",
                        turns[i]
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 100, "{checked}");
    }
}
