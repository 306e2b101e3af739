//! A motion's moving side on one state and what two motions decide about each other: the
//! pair rule that `parallel/footprint.rs` explains, and the exact closest approach of two
//! motions done at the same time. Shared by the independence check and `parallelise`, below
//! both.

use crate::bitset::BitSet;
use crate::robot_world::RobotWorld;
use crate::simultaneous::{turns_together, Together};
use dynarole_core::check::ResolvedStatement;
use dynarole_core::RobotApi;
use dynarole_world::Motion;
use std::cell::Cell;

/// A motion on one state, with the modules it moves and its own module (by index). Only a
/// motion with legs has one: one that moves in place (a latch) makes or breaks connections,
/// which only running both orders decides.
pub(crate) struct MovingSide {
    motion: Motion,
    pub(crate) modules: BitSet,
    pub(crate) pivot: usize,
}

impl MovingSide {
    pub(crate) fn of(
        robot: &RobotApi,
        statement: &ResolvedStatement,
        module: Option<&str>,
        world: &RobotWorld,
    ) -> Option<MovingSide> {
        let module = module?;
        let motion = world.motion(robot, statement, module)?;
        if !motion.moves() {
            return None;
        }
        let view = world.view();
        let mut modules = BitSet::new(view.len());
        for (name, _) in &motion.moving {
            modules.insert(view.index(name)?);
        }
        let pivot = view.index(module)?;
        Some(MovingSide {
            motion,
            modules,
            pivot,
        })
    }

    /// The motion on the state the side was found on.
    pub(crate) fn motion(&self) -> &Motion {
        &self.motion
    }

    /// Whether the two turns are one linkage: their sides share a module, or one moves the
    /// other's module (a turn that moves no module, a free end's joint, leaves every position
    /// where it was, so carrying its module along changes nothing it does). Such a pair is
    /// decided over its own joint-space box: for it alone, not with other turns of a group.
    pub(crate) fn linked(&self, other: &MovingSide) -> bool {
        let carries = |x: &MovingSide, y: &MovingSide| {
            x.modules.contains(y.pivot) && !y.motion.moving.is_empty()
        };
        self.modules.intersects(&other.modules) || carries(self, other) || carries(other, self)
    }

    /// Two turns done from `world`, each accepted on it alone (checked here for both),
    /// proven independent from their motions: both orders are accepted and end in the same
    /// configuration, and done at the same time they stay the limit apart. `false` when
    /// that is not proven (the full check decides).
    pub(crate) fn proven_independent(&self, other: &MovingSide, world: &RobotWorld) -> bool {
        // `decide` assumes the earlier turn is accepted on `world` and checks the later one's
        // sweep; asked both ways round, both sweeps are checked.
        let (first, second) = (Cell::new(None), Cell::new(None));
        self.decide(other, world, (0, &first)) == Some(false)
            && other.decide(self, world, (0, &second)) == Some(false)
    }

    /// `self` is `a` (statement `i`), `b` the later turn, both on `world` (the state before
    /// `a`): `Some(ordered)`, or `None` for the full check.
    pub(crate) fn decide(
        &self,
        b: &MovingSide,
        world: &RobotWorld,
        (i, clear): (usize, &Cell<Option<usize>>),
    ) -> Option<bool> {
        // Sides that share a module, or one turn carrying the other's module, are turns of one
        // linkage: on a tree the two orders end alike (the shape depends on the joint angles
        // only), the modules only one of them moves apart are where it alone puts them in
        // either order (`a` is accepted on `world`, `b` is checked below), and the others are
        // decided over the pair's whole joint-space box; where they make no tree, the full
        // check.
        let positions = world.model().rigid_module_centres()?;
        if self.linked(b) {
            let pair = [(&self.motion, self.pivot), (&b.motion, b.pivot)];
            match turns_together(&pair, world)? {
                Together::Clear => {}
                Together::Closest(_) | Together::Unproven(_) => return Some(true),
            }
        } else if closest_approach(&self.motion, &b.motion).is_some() {
            return Some(true);
        }

        // Clear on the state after `a` (checked for the pair `i + 1`): only `a`'s modules moved.
        let incremental = clear.get() == Some(i + 1);
        let collides = b.sweep_collides(&positions, incremental.then_some(&self.modules));
        if !collides {
            clear.set(Some(i));
        }
        Some(collides)
    }

    /// Whether this turn alone, on the state whose module centres are `positions`, sweeps a
    /// module it moves within the limit of one it does not (of those in `only`, when given).
    fn sweep_collides(&self, positions: &[[f64; 3]], only: Option<&BitSet>) -> bool {
        let still: Vec<[f64; 3]> = (0..positions.len())
            .filter(|k| !self.modules.contains(*k))
            .filter(|k| only.is_none_or(|set| set.contains(*k)))
            .map(|k| positions[k])
            .collect();
        let moving: Vec<[f64; 3]> = self.motion.moving.iter().map(|(_, p)| *p).collect();
        let approach = self.motion.sweep_approach(&moving, &still);
        approach.is_some_and(|distance| distance < self.motion.limit)
    }

    /// Whether this turn alone sweeps clear of every module on `world` (`None` when the robot
    /// does not move whole modules): all a group whose turns were found clear together asks
    /// of each turn, once, for its pairs (`independence.rs`).
    pub(crate) fn sweep_clear(&self, world: &RobotWorld) -> Option<bool> {
        let positions = world.model().rigid_module_centres()?;
        Some(!self.sweep_collides(&positions, None))
    }
}

/// Halvings of a piece of a path before a closest approach too near the limit to be decided
/// is reported as a conflict: the piece is then shorter than 2^-40 of the path.
const MAX_HALVINGS: u32 = 40;

/// Times one pair of points is searched again for a closer approach below the one found.
const MAX_DESCENTS: usize = 64;

/// The closest approach below the limit that the two turns can bring two of their moving
/// points to, for some relative timing; `None` when they are proven to stay apart.
///
/// Exact, not sampled. For one point of each side, the distance between the moving point of
/// `a` at one moment and the whole path of the point of `b` is known in closed form
/// ([`Motion::distance_to_path`]); a piece of `a`'s path whose middle is at distance `d`
/// from `b`'s path keeps every point within half the piece's length of that middle, so the
/// whole piece stays at least `d - length / 2` away. Pieces that cannot be decided that way
/// are halved; a pair of points whose paths' exact bounding boxes are already apart by the
/// limit is not looked at.
pub(crate) fn closest_approach(a: &Motion, b: &Motion) -> Option<f64> {
    // Once a conflict is found, the bar drops to it, so what is reported is the closest
    // approach of all pairs (to the precision of the halvings), not the first one found.
    let mut bar = a.limit.max(b.limit);
    let mut closest = None;
    let boxes_b: Vec<_> = b.moving.iter().map(|(_, p)| b.path_box(*p)).collect();
    for (_, pa) in &a.moving {
        let box_a = a.path_box(*pa);
        for ((_, pb), box_b) in b.moving.iter().zip(&boxes_b) {
            for _ in 0..MAX_DESCENTS {
                if box_distance(&box_a, box_b) >= bar {
                    break;
                }
                match path_approach(a, *pa, b, *pb, bar) {
                    Some(d) if d < bar => {
                        closest = Some(d);
                        bar = d;
                    }
                    _ => break,
                }
            }
        }
    }
    closest
}

/// Branch and bound over the path of `pa` (fractions of `a`'s turn) against the whole path of
/// `pb`: the distance found below `limit`, or the lower bound of a piece that could not be
/// decided after [`MAX_HALVINGS`] halvings; `None` when every piece stays at least `limit` away.
fn path_approach(a: &Motion, pa: [f64; 3], b: &Motion, pb: [f64; 3], limit: f64) -> Option<f64> {
    let length = a.path_length(pa);
    // Pieces still to decide: (start, end, halvings). A stack: at most one piece per level
    // waits, so it never holds more than MAX_HALVINGS + 1 pieces.
    let mut pieces = vec![(0.0_f64, 1.0_f64, 0_u32)];
    while let Some((start, end, halvings)) = pieces.pop() {
        let middle = (start + end) / 2.0;
        let d = b.distance_to_path(pb, a.position_at(pa, middle));
        if d < limit {
            return Some(d);
        }
        let bound = d - length * (end - start) / 2.0;
        if bound >= limit {
            continue;
        }
        if halvings == MAX_HALVINGS {
            return Some(bound.min(limit - f64::EPSILON));
        }
        pieces.push((middle, end, halvings + 1));
        pieces.push((start, middle, halvings + 1));
    }
    None
}

/// The distance between two boxes (low, high); 0 when they overlap.
fn box_distance(a: &([f64; 3], [f64; 3]), b: &([f64; 3], [f64; 3])) -> f64 {
    let gap = |k: usize| (b.0[k] - a.1[k]).max(a.0[k] - b.1[k]).max(0.0);
    (gap(0).powi(2) + gap(1).powi(2) + gap(2).powi(2)).sqrt()
}
