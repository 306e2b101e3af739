//! The events of the simulation's queue (below the queue and the state that schedule them).

use crate::packet::Arrivals;

#[derive(Clone, Debug)]
pub enum Event {
    PowerOn {
        module: usize,
    },
    PowerOff {
        module: usize,
    },
    /// A step of `module` (an index below `links::MAX_MODULES`) in its power-on
    /// `generation` (u32 fields: the event, and every event, takes 16 bytes).
    Step {
        module: u32,
        generation: u32,
    },
    OpDone {
        attempt: u64,
    },
    /// Packets of one broadcast (`packet::Arrivals`), one per event.
    Arrival(Box<Arrivals>),
    Reset {
        module: usize,
    },
    ResetCheck {
        module: usize,
    },
    /// Two running turns bring modules within the limit now: `State::clashes[entry]`.
    Clash {
        entry: u32,
    },
    /// The next packet of the scenario's `foreign[entry]`.
    Foreign {
        entry: usize,
    },
}
