//! Pairs of turns decided from their motions, without running them on copies of the world:
//! the same verdict as running both orders (the property test compares the two graphs).
//!
//! Two turns `a` (statement `i`) and `b` (a later one), on the state `W` before `a`:
//! - moving sides that share a module: ordered (the full check says "both turns move ...");
//! - on a robot whose turns move whole modules (`RobotModel::rigid_module_centres`: ATRON),
//!   disjoint sides, neither pivot moved by the other turn (or the one moved
//!   turns no module, as at a free end of a chain): the two orders give
//!   the same configuration (each module is turned by at most one of them, about an axis the
//!   other does not move). If the two turns done at the same time can come closer than the
//!   limit, ordered (the full check's last test). Otherwise every moving module of one turn
//!   stays the limit away from every position the other's moving modules take, so `a` after
//!   `b` sweeps past the same still modules as `a` in the input, plus `b`'s moved ones, which
//!   are clear; likewise `b` after `a`. What is left is whether `b` itself is clear on `W`:
//!   ordered when it is not, free when it is.
//!
//! `b`'s sweep on `W` is checked against every still module, or, when it was found clear on
//! the state after `a` (the previous pair of the same later statement), only against the
//! modules `a` moved: the others are where they were then, and so is `b`'s moving side.

use super::layout::BitSet;
use crate::independence::closest_approach;
use crate::robot_world::RobotWorld;
use dynarole_core::check::ResolvedStatement;
use dynarole_core::RobotApi;
use dynarole_world::geometry::sweep_closest_approach;
use dynarole_world::TurnMotion;
use std::cell::{Cell, RefCell};
use std::rc::Rc;

/// What is known of one later statement `b` while its earlier statements are visited, from
/// the nearest back: the latest input index on whose state its turn's sweep was found clear,
/// and its moving side on the state before the statement visited last.
#[derive(Default)]
pub(super) struct Later {
    clear: Cell<Option<usize>>,
    side: RefCell<Option<(usize, Rc<MovingSide>)>>,
}

impl Later {
    /// The pair (`a` = statement `i`, with its moving side, and the later turn `b` done by
    /// `module`) on `world`, the state before `a`: `Some(ordered)`, or `None` for the full
    /// check. `b`'s moving side is the one found on the state after `a` when `a` is a turn of
    /// another module (turns change no latch, and a turn of another module changes neither
    /// `b`'s joint nor, unless the sides meet, its modules); else it is computed on `world`.
    pub(super) fn decide(
        &self,
        request: &super::Request,
        (a, i): (&MovingSide, usize),
        (b, module): (&ResolvedStatement, Option<&str>),
        world: &RobotWorld,
    ) -> Option<bool> {
        let cached = self.side.borrow().clone();
        let (side_b, fresh) = match cached {
            Some((k, side)) if k == i + 1 && side.pivot != a.pivot => (side, false),
            _ => match MovingSide::of(&request.program.robot, b, module, world) {
                Some(side) => (Rc::new(side), true),
                // `b` is refused on `world` (a wrong angle, a locked joint): ordered.
                None => return Some(true),
            },
        };
        let verdict = a.decide(&side_b, world, (i, &self.clear));
        // A side carried over is only right for `world` when `a` moved none of it, nor its
        // module; otherwise the next pair computes it again.
        let valid =
            fresh || !(a.modules.intersects(&side_b.modules) || a.modules.contains(side_b.pivot));
        *self.side.borrow_mut() = valid.then_some((i, side_b));
        verdict
    }
}

/// A turn's motion on one state, with the modules it moves and its own module (by index).
pub(crate) struct MovingSide {
    motion: TurnMotion,
    modules: BitSet,
    pivot: usize,
}

impl MovingSide {
    pub(crate) fn of(
        robot: &RobotApi,
        statement: &ResolvedStatement,
        module: Option<&str>,
        world: &RobotWorld,
    ) -> Option<MovingSide> {
        let module = module?;
        let motion = world.turn_motion(robot, statement, module)?;
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
    fn decide(
        &self,
        b: &MovingSide,
        world: &RobotWorld,
        (i, clear): (usize, &Cell<Option<usize>>),
    ) -> Option<bool> {
        if self.modules.intersects(&b.modules) {
            return Some(true);
        }

        let positions = world.model().rigid_module_centres()?;
        // A turn that moves no module (a free end's joint) leaves every position where it
        // was, so carrying its module along changes nothing it does; else moving the other's
        // module changes the other's motion, and the full check decides.
        let carries = |x: &MovingSide, y: &MovingSide| {
            x.modules.contains(y.pivot) && !y.motion.moving.is_empty()
        };
        if carries(self, b) || carries(b, self) {
            return None;
        }
        if closest_approach(&self.motion, &b.motion).is_some() {
            return Some(true);
        }

        // Clear on the state after `a` (checked for the pair `i + 1`): only `a`'s modules moved.
        let incremental = clear.get() == Some(i + 1);
        let still: Vec<[f64; 3]> = (0..positions.len())
            .filter(|k| !b.modules.contains(*k))
            .filter(|k| !incremental || self.modules.contains(*k))
            .map(|k| positions[k])
            .collect();
        let moving: Vec<[f64; 3]> = b.motion.moving.iter().map(|(_, p)| *p).collect();
        let approach = sweep_closest_approach(
            b.motion.pivot,
            b.motion.axis,
            b.motion.angle_deg,
            &moving,
            &still,
        );
        let collides = approach.is_some_and(|a| a.distance < b.motion.limit);
        if !collides {
            clear.set(Some(i));
        }
        Some(collides)
    }
}
