//! Packets in flight, the air log of a module's hemisphere, and one broadcast's packets
//! (`Arrivals`, delivered by `network.rs`): data the state, the event queue and the network
//! share, below all of them.

use dynarole_world::Port;
use std::rc::Rc;

/// A packet on its way from one connector to another. Compact (ports as a u32 module index
/// and a connector, the bytes shared by every copy of one broadcast): at the start of a large
/// run every module's first broadcast is in flight at once.
#[derive(Clone, Debug)]
pub struct Packet {
    pub id: u64,
    pub start: u64,
    pub end: u64,
    pub bytes: Rc<[u8]>,
    from: (u32, u8),
    to: (u32, u8),
}

impl Packet {
    pub fn new(id: u64, from: Port, to: Port, (start, end): (u64, u64), bytes: Rc<[u8]>) -> Packet {
        // Module indices fit: a run has at most `links::MAX_MODULES` modules.
        let compact = |p: Port| (p.module as u32, p.connector);
        Packet {
            id,
            start,
            end,
            bytes,
            from: compact(from),
            to: compact(to),
        }
    }

    pub fn from(&self) -> Port {
        Port {
            module: self.from.0 as usize,
            connector: self.from.1,
        }
    }

    pub fn to(&self) -> Port {
        Port {
            module: self.to.0 as usize,
            connector: self.to.1,
        }
    }
}

/// One transmission or reception on a module's hemisphere, remembered for collision checks
/// (24 bytes: a half-duplex module remembers a dozen at a time).
#[derive(Clone, Copy, Debug)]
pub struct Air {
    pub start: u64,
    pub end: u64,
    /// The packet's id (0 for the module's own transmission; ids stay far below 2^63), with
    /// the hemisphere in the top bit.
    tag: u64,
}

impl Air {
    const HEMISPHERE: u64 = 1 << 63;

    pub fn new((start, end): (u64, u64), packet: u64, hemisphere: usize) -> Air {
        let top = if hemisphere == 0 { 0 } else { Air::HEMISPHERE };
        Air {
            start,
            end,
            tag: (packet & !Air::HEMISPHERE) | top,
        }
    }

    pub fn packet(&self) -> u64 {
        self.tag & !Air::HEMISPHERE
    }

    pub fn hemisphere(&self) -> usize {
        usize::from(self.tag & Air::HEMISPHERE != 0)
    }
}

/// Send queues per module, at most (one per connector).
pub const QUEUES: usize = 8;

/// The packets of one broadcast that share their time on the air, as one event of the queue
/// (a broadcast reaches every neighbour at once: at the start of a large run every module's
/// first broadcast is in flight together, and one event per packet would hold four or more
/// queue entries per module). Delivered one per event (`State::next_arrival`), each at the
/// key it would have had alone: the packets of one broadcast take consecutive sequence
/// numbers and ids (the k-th sent: first + k) and share the instant they were scheduled at
/// and their end, so no other event comes between them.
#[derive(Clone, Debug)]
pub struct Arrivals {
    pub(crate) first_id: u64,
    pub(crate) first_seq: u64,
    pub(crate) sent_at: u64,
    pub(crate) air: (u64, u64),
    pub(crate) bytes: Rc<[u8]>,
    pub(crate) from_module: u32,
    /// The next packet to deliver, and how many there are.
    pub(crate) next: u8,
    pub(crate) len: u8,
    pub(crate) targets: [Target; QUEUES],
}

/// One packet of `Arrivals`: where it goes, the sender's connector, and its rank among the
/// packets of its broadcast.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Target {
    pub(crate) to_module: u32,
    pub(crate) to_connector: u8,
    pub(crate) from_connector: u8,
    pub(crate) rank: u8,
}
