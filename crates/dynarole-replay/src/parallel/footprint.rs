//! Pairs of turns decided from their motions, without running them on copies of the world:
//! the same verdict as running both orders (the property test compares the two graphs).
//!
//! Two turns `a` (statement `i`) and `b` (a later one), on the state `W` before `a`:
//! - moving sides that share a module, or one turn moving the other's module: the full check
//!   (both orders, and the two turns done together over every relative timing);
//! - on a robot whose turns move whole modules (`RobotModel::rigid_module_centres`),
//!   otherwise (disjoint sides, neither pivot moved by the other turn, or the one moved
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
//!
//! The pair rule itself is `MovingSide::decide` (`motion.rs`, shared with the independence
//! check); this file keeps what each later statement carries from one pair to the next.

use crate::motion::MovingSide;
use crate::robot_world::RobotWorld;
use dynarole_core::check::ResolvedStatement;
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
            // Carried over only where `a` moves none of it (a turn changes no latch, so its
            // set of modules is the same; their positions then are too).
            Some((k, side))
                if k == i + 1
                    && side.pivot != a.pivot
                    && !a.modules.intersects(&side.modules)
                    && !a.modules.contains(side.pivot) =>
            {
                (side, false)
            }
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
