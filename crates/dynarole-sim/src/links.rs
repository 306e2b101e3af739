//! Where each module's broadcasts go while the world is unchanged (`State::links`, filled and
//! read by `network.rs`), and the most modules a run can have so that every port packs.

use crate::packet::QUEUES;
use dynarole_world::Port;

/// Where each module's broadcasts go, by sending connector, while the world is unchanged:
/// one u32 per connector of every module in one vector (4 bytes per connector, no
/// allocation per module), filled for a module at its first broadcast after a change.
pub struct Links {
    /// Connectors per module.
    connectors: usize,
    /// Module m's entries are `slots[m * connectors..][..connectors]`: `UNKNOWN` (not looked
    /// up since the last change), `NONE`, or the receiving port as `module * QUEUES +
    /// connector`.
    slots: Vec<u32>,
}

const UNKNOWN: u32 = u32::MAX;
const NONE: u32 = u32::MAX - 1;

/// Most modules a run can have: every port must pack into a `Links` slot.
pub const MAX_MODULES: usize = (NONE as usize) / QUEUES;

impl Links {
    pub fn new(modules: usize, connectors: u8) -> Links {
        let connectors = usize::from(connectors);
        Links {
            connectors,
            slots: vec![UNKNOWN; modules * connectors],
        }
    }

    /// Forgets every target (the world changed).
    pub fn clear(&mut self) {
        self.slots.fill(UNKNOWN);
    }

    /// Module m's targets by sending connector, if looked up since the last change.
    pub(crate) fn get(&self, m: usize) -> Option<[Option<Port>; QUEUES]> {
        let slots = self
            .slots
            .get(m * self.connectors..(m + 1) * self.connectors)?;
        if slots.first().is_none_or(|s| *s == UNKNOWN) {
            return None;
        }
        let mut out = [None; QUEUES];
        for (target, slot) in out.iter_mut().zip(slots) {
            *target = (*slot != NONE).then_some(Port {
                module: *slot as usize / QUEUES,
                connector: (*slot as usize % QUEUES) as u8,
            });
        }
        Some(out)
    }

    pub(crate) fn set(&mut self, m: usize, targets: &[Option<Port>; QUEUES]) {
        let range = m * self.connectors..(m + 1) * self.connectors;
        if let Some(slots) = self.slots.get_mut(range) {
            for (slot, target) in slots.iter_mut().zip(targets) {
                *slot = target.map_or(NONE, |p| {
                    u32::try_from(p.module * QUEUES + usize::from(p.connector)).unwrap_or(NONE)
                });
            }
        }
    }
}
