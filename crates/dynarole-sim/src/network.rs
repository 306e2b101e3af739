//! The infrared network (atron.md a.8): who can send to whom, the finite bit rate with a send
//! queue per channel (per hemisphere when half duplex), and what can happen to a packet on
//! the way: a link broken by a turn, a blocked link, a collision, loss, a dead link.

use crate::scenario::Preset;
use crate::state::{uniform, Event, Packet, State};
use dynarole_world::Port;

/// 19200 baud, modelled as 1920 bytes per second.
const BYTES_PER_SECOND: u64 = 1920;
/// Send buffer per channel (bytes).
const SEND_BUFFER: u64 = 128;
/// Send queues per module, at most (one per connector; ATRON and M-TRAN have 8 and 6).
const QUEUES: usize = 8;
/// How long transmissions are remembered for collision checks (µs): longer than any
/// packet's air time (a packet has at most 255 bytes: 133 ms), so forgetting older ones
/// changes no check (a packet arriving now started at most that long ago).
const AIR_MEMORY_US: u64 = 200_000;
const _: () = assert!(AIR_MEMORY_US > 255 * 1_000_000 / BYTES_PER_SECOND + 1);

/// What happened to a packet at the receiving connector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fate {
    Delivered,
    /// Lost to the background loss probability.
    Lost,
    /// Lost on a dead link.
    Dead,
    /// Half duplex: overlapped another packet or the receiver's own transmission.
    Collision,
    /// The link is blocked by the scenario.
    Blocked,
    /// A turn in progress moves one end away from the other.
    Moving,
    /// The receiver is powered off.
    Off,
}

impl Fate {
    fn name(self) -> &'static str {
        match self {
            Fate::Delivered => "delivered",
            Fate::Lost => "lost",
            Fate::Dead => "dead-link",
            Fate::Collision => "collision",
            Fate::Blocked => "blocked",
            Fate::Moving => "broken",
            Fate::Off => "off",
        }
    }
}

fn airtime_us(len: usize) -> u64 {
    (len as u64 * 1_000_000).div_ceil(BYTES_PER_SECOND)
}

impl State {
    /// `dr_hal_broadcast`: one transmission per channel the module can send on.
    pub fn broadcast(&mut self, m: usize, bytes: &[u8]) {
        if !self.modules[m].powered {
            return;
        }
        self.counters.broadcasts += 1;
        if let Some(frames) = self.last_frames.as_mut() {
            if let Some(slot) = frames.get_mut(m) {
                *slot = Some(bytes.to_vec());
            }
        }
        let targets = match self.links.get_mut(m).and_then(Option::take) {
            Some(targets) => targets,
            None => self.link_targets(m),
        };
        // The air time reserved on each send queue (one reservation per queue and broadcast).
        let mut slots: [Option<Option<(u64, u64)>>; QUEUES] = [None; QUEUES];
        for &(from, to) in &targets {
            let queue = self.send_queue(from.connector);
            let slot = match slots.get(queue).copied().flatten() {
                Some(slot) => slot,
                None => {
                    let slot = self.reserve(m, queue, bytes.len());
                    if let Some(s) = slots.get_mut(queue) {
                        *s = Some(slot);
                    }
                    slot
                }
            };
            let Some((start, end)) = slot else {
                self.counters.overflow += 1;
                continue;
            };
            self.send(from, to, start, end, bytes);
        }
        if let Some(cache) = self.links.get_mut(m) {
            *cache = Some(targets);
        }
    }

    /// `dr_hal_send`: one transmission on one channel, if anything listens there.
    pub fn send_on(&mut self, m: usize, channel: u8, bytes: &[u8]) {
        if !self.modules[m].powered {
            return;
        }
        let from = Port {
            module: m,
            connector: channel,
        };
        let Some(to) = self.view().link_target(from) else {
            return;
        };
        let queue = self.send_queue(channel);
        match self.reserve(m, queue, bytes.len()) {
            Some((start, end)) => self.send(from, to, start, end, bytes),
            None => self.counters.overflow += 1,
        }
    }

    /// Where module `m`'s broadcasts go: (sending connector, receiving connector), by
    /// connector. Cached in `links` until the world changes.
    fn link_targets(&self, m: usize) -> Vec<(Port, Port)> {
        let view = self.view();
        (0..view.connectors())
            .map(|c| Port {
                module: m,
                connector: c,
            })
            .filter_map(|from| view.link_target(from).map(|to| (from, to)))
            .collect()
    }

    /// Full duplex: one queue per channel; half duplex: one UART per hemisphere.
    fn send_queue(&self, connector: u8) -> usize {
        match self.preset {
            Preset::Ussr => usize::from(connector),
            Preset::Atron => self.view().hemisphere(connector),
        }
    }

    /// Reserves air time on a send queue; `None` when the send buffer is full.
    fn reserve(&mut self, m: usize, queue: usize, len: usize) -> Option<(u64, u64)> {
        let now = self.now;
        let busy = self.modules[m]
            .busy_until
            .get(queue)
            .copied()
            .unwrap_or(now);
        let start = busy.max(now);
        let backlog = (start - now) * BYTES_PER_SECOND / 1_000_000;
        if backlog + len as u64 > SEND_BUFFER {
            return None;
        }
        let end = start + airtime_us(len);
        if let Some(slot) = self.modules[m].busy_until.get_mut(queue) {
            *slot = end;
        }
        if self.preset == Preset::Atron {
            self.modules[m].air[queue.min(1)].push((start, end, 0));
        }
        Some((start, end))
    }

    fn send(&mut self, from: Port, to: Port, start: u64, end: u64, bytes: &[u8]) {
        let id = self.next_id;
        self.next_id += 1;
        self.counters.packets_sent += 1;
        self.modules[from.module].stats.sent += 1;
        if self.preset == Preset::Atron {
            let h = self.view().hemisphere(to.connector);
            self.modules[to.module].air[h].push((start, end, id));
        }
        let packet = Packet {
            id,
            from,
            to,
            start,
            end,
            bytes: bytes.to_vec(),
        };
        self.schedule(end, Event::Arrival(Box::new(packet)));
    }

    /// Decides a packet's fate as it arrives; true when the receiver gets it.
    pub fn arrive(&mut self, packet: &Packet) -> bool {
        let fate = self.fate(packet);
        self.prune_air(packet.to.module);
        self.record_packet(packet, fate.name());
        if fate == Fate::Delivered {
            self.counters.delivered += 1;
            self.modules[packet.to.module].stats.received += 1;
            return true;
        }
        self.counters.count_drop(fate);
        self.modules[packet.to.module].stats.dropped += 1;
        if self.tracing() {
            let view = self.view();
            let detail = format!(
                "{} <- {} ({} bytes)",
                view.port_name(packet.to),
                view.port_name(packet.from),
                packet.bytes.len()
            );
            self.log(Some(packet.to.module), fate.name(), detail);
        }
        false
    }

    fn fate(&mut self, p: &Packet) -> Fate {
        if !self.modules[p.to.module].powered {
            return Fate::Off;
        }
        if self.turn_breaks(p.from.module, p.to.module) {
            return Fate::Moving;
        }
        let faults = self.faults_on();
        if faults && (self.blocked(p.from) || self.blocked(p.to)) {
            return Fate::Blocked;
        }
        if self.preset == Preset::Atron && self.collides(p) {
            return Fate::Collision;
        }
        if !faults {
            return Fate::Delivered;
        }
        let dead = self.modules[p.to.module]
            .dead
            .get(usize::from(p.to.connector))
            .copied()
            .unwrap_or(false);
        let loss = if dead {
            self.scenario.network.dead_loss
        } else {
            self.scenario.network.loss
        };
        match (uniform(&mut self.rng_loss) < loss, dead) {
            (false, _) => Fate::Delivered,
            (true, true) => Fate::Dead,
            (true, false) => Fate::Lost,
        }
    }

    /// During a turn, the turning module's links and every link between a moving and a still
    /// module are broken.
    fn turn_breaks(&self, a: usize, b: usize) -> bool {
        self.turns.values().any(|(turning, moving)| {
            *turning == a || *turning == b || moving.get(a) != moving.get(b)
        })
    }

    fn blocked(&self, port: Port) -> bool {
        let now_ms = self.now / 1000;
        self.scenario.block.iter().any(|b| {
            b.connector == port.connector
                && self.modules[port.module].name == b.module
                && (b.from_ms..b.to_ms).contains(&now_ms)
        })
    }

    /// Half duplex: the receiver's hemisphere UART heard another packet, or was sending,
    /// while this one was on the air.
    fn collides(&self, p: &Packet) -> bool {
        let h = self.view().hemisphere(p.to.connector);
        self.modules[p.to.module].air[h]
            .iter()
            .any(|(start, end, id)| *id != p.id && *start < p.end && *end > p.start)
    }

    fn prune_air(&mut self, m: usize) {
        let horizon = self.now.saturating_sub(AIR_MEMORY_US);
        for log in &mut self.modules[m].air {
            log.retain(|(_, end, _)| *end >= horizon);
        }
    }
}

impl crate::report::Counters {
    fn count_drop(&mut self, fate: Fate) {
        match fate {
            Fate::Delivered => {}
            Fate::Lost => self.lost += 1,
            Fate::Dead => self.dead += 1,
            Fate::Collision => self.collided += 1,
            Fate::Blocked => self.blocked += 1,
            Fate::Moving => self.broken += 1,
            Fate::Off => self.off += 1,
        }
    }
}
