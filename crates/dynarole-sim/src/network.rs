//! The network (docs/simulator.md): who can send to whom, the finite bit rate with a send
//! queue per channel (per hemisphere when half duplex), and what can happen to a packet on
//! the way: a link broken by a turn, a blocked link, a collision, loss, a dead link.

use crate::event::Event;
use crate::packet::{Air, Arrivals, Packet, Target, QUEUES};
use crate::queue::Key;
use crate::state::{uniform, State};
use dynarole_recording::TraceEvent;
use dynarole_world::Port;
use std::rc::Rc;

/// 19200 baud, modelled as 1920 bytes per second.
const BYTES_PER_SECOND: u64 = 1920;
/// Send buffer per channel (bytes).
const SEND_BUFFER: u64 = 128;
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
    /// The trace event of a packet that did not arrive; a delivered one has none (it is no
    /// trace line).
    fn event(self) -> Option<TraceEvent> {
        match self {
            Fate::Delivered => None,
            Fate::Lost => Some(TraceEvent::Lost),
            Fate::Dead => Some(TraceEvent::DeadLink),
            Fate::Collision => Some(TraceEvent::Collision),
            Fate::Blocked => Some(TraceEvent::Blocked),
            Fate::Moving => Some(TraceEvent::Broken),
            Fate::Off => Some(TraceEvent::Off),
        }
    }

    /// The recording's word for the fate (`PacketArc::fate`): `delivered`, or the drop's
    /// event.
    fn name(self) -> &'static str {
        self.event().map_or("delivered", TraceEvent::name)
    }
}

fn airtime_us(len: usize) -> u64 {
    (len as u64 * 1_000_000).div_ceil(BYTES_PER_SECOND)
}

/// The packets of one broadcast (or one `dr_hal_send`) before they go into the queue.
#[derive(Default)]
struct Sends {
    list: [Send; QUEUES],
    len: usize,
}

#[derive(Clone, Copy)]
struct Send {
    connector: u8,
    to: Port,
    /// Start and end on the air.
    air: (u64, u64),
}

impl Default for Send {
    fn default() -> Send {
        let to = Port {
            module: 0,
            connector: 0,
        };
        Send {
            connector: 0,
            to,
            air: (0, 0),
        }
    }
}

impl Sends {
    fn push(&mut self, connector: u8, to: Port, air: (u64, u64)) {
        if let Some(slot) = self.list.get_mut(self.len) {
            *slot = Send { connector, to, air };
            self.len += 1;
        }
    }

    fn list(&self) -> &[Send] {
        self.list.get(..self.len).unwrap_or_default()
    }
}

impl Arrivals {
    /// No packet yet: the ids and sequence numbers of a broadcast's packets start at
    /// `first_id` and `first_seq`; module `from` sent them at `sent_at`.
    fn first(first_id: u64, first_seq: u64, sent_at: u64, from: usize, bytes: Rc<[u8]>) -> Self {
        Arrivals {
            first_id,
            first_seq,
            sent_at,
            air: (0, 0),
            bytes,
            // Fits: a run has at most MAX_MODULES modules.
            from_module: from as u32,
            next: 0,
            len: 0,
            targets: [Target::default(); QUEUES],
        }
    }

    /// `sends` (the k-th has rank k) grouped by air time, in the order of each group's first.
    fn groups(&self, sends: &Sends, mut each: impl FnMut(Arrivals)) {
        let mut grouped = 0u8;
        for (k, send) in (0u8..).zip(sends.list()) {
            if grouped & (1 << k) != 0 {
                continue;
            }
            let mut group = Arrivals {
                air: send.air,
                ..self.clone()
            };
            for (j, other) in (0u8..).zip(sends.list()).skip(usize::from(k)) {
                if other.air == send.air {
                    grouped |= 1 << j;
                    group.add(j, other);
                }
            }
            each(group);
        }
    }

    fn add(&mut self, rank: u8, send: &Send) {
        if let Some(slot) = self.targets.get_mut(usize::from(self.len)) {
            *slot = Target {
                // Fits: a run has at most MAX_MODULES modules.
                to_module: send.to.module as u32,
                to_connector: send.to.connector,
                from_connector: send.connector,
                rank,
            };
            self.len += 1;
        }
    }

    fn current(&self) -> Target {
        self.targets
            .get(usize::from(self.next))
            .copied()
            .unwrap_or_default()
    }

    /// The queue key of the next packet: as `State::schedule` gave it when it was sent.
    fn key(&self) -> Key {
        let seq = self.first_seq + u64::from(self.current().rank);
        Key::plain(self.air.1, self.sent_at, seq)
    }

    /// The next packet.
    fn packet(&self) -> Packet {
        let t = self.current();
        let from = Port {
            module: self.from_module as usize,
            connector: t.from_connector,
        };
        let to = Port {
            module: t.to_module as usize,
            connector: t.to_connector,
        };
        let id = self.first_id + u64::from(t.rank);
        Packet::new(id, from, to, self.air, Rc::clone(&self.bytes))
    }
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
        let targets = match self.links.get(m) {
            Some(targets) => targets,
            None => {
                let targets = self.link_targets(m);
                self.links.set(m, &targets);
                targets
            }
        };
        // The air time reserved on each send queue (one reservation per queue and broadcast).
        let mut slots: [Option<Option<(u64, u64)>>; QUEUES] = [None; QUEUES];
        let mut sends = Sends::default();
        for (connector, to) in (0u8..).zip(targets) {
            let Some(to) = to else {
                continue;
            };
            let queue = self.send_queue(connector);
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
            let Some(air) = slot else {
                self.counters.overflow += 1;
                continue;
            };
            sends.push(connector, to, air);
        }
        self.transmit(m, &sends, bytes);
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
            Some(air) => {
                let mut sends = Sends::default();
                sends.push(channel, to, air);
                self.transmit(m, &sends, bytes);
            }
            None => self.counters.overflow += 1,
        }
    }

    /// Where module `m`'s broadcasts go: the receiving connector, by sending connector.
    /// Cached in `links` until the world changes.
    fn link_targets(&self, m: usize) -> [Option<Port>; QUEUES] {
        let view = self.view();
        let mut out = [None; QUEUES];
        for (connector, target) in (0..view.connectors()).zip(out.iter_mut()) {
            *target = view.link_target(Port {
                module: m,
                connector,
            });
        }
        out
    }

    /// Full duplex: one queue per channel; half duplex: one transceiver per side.
    fn send_queue(&self, connector: u8) -> usize {
        if self.preset.half_duplex_sides {
            self.view().side(connector)
        } else {
            usize::from(connector)
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
        if self.preset.half_duplex_sides {
            let air = Air::new((start, end), 0, queue.min(1));
            // Its own transmissions are forgotten too (not only when it hears a packet), so
            // that a module that mostly talks keeps a short log.
            self.prune_air(m);
            if let Some(log) = self.air.get_mut(m) {
                log.push(air);
            }
        }
        Some((start, end))
    }

    /// Module `m`'s packets, in the order sent: each takes the next packet id and the next
    /// sequence number, exactly as if scheduled one by one, but the packets with the same air
    /// time go into the queue as one event (`Arrivals`).
    fn transmit(&mut self, m: usize, sends: &Sends, bytes: &[u8]) {
        if sends.len == 0 {
            return;
        }
        let count = sends.len as u64;
        let first = Arrivals::first(self.next_id, self.next_seq, self.now, m, Rc::from(bytes));
        self.next_id += count;
        self.next_seq += count;
        self.counters.packets_sent += count;
        self.modules[m].stats.sent += count;
        self.note_air(sends, first.first_id);
        first.groups(sends, |arrivals| {
            self.push(arrivals.key(), Event::Arrival(Box::new(arrivals)));
        });
    }

    /// The air time of packets just sent (the packet ids from `first_id`): the longest so far,
    /// and, half duplex, the receivers' collision records.
    fn note_air(&mut self, sends: &Sends, first_id: u64) {
        for (k, send) in (0u64..).zip(sends.list()) {
            self.longest_air_us = self.longest_air_us.max(send.air.1 - send.air.0);
            if self.preset.half_duplex_sides {
                let side = self.view().side(send.to.connector);
                let air = Air::new(send.air, first_id + k, side);
                if let Some(log) = self.air.get_mut(send.to.module) {
                    log.push(air);
                }
            }
        }
    }

    /// The next packet of `arrivals` (the event being dispatched); the others go back into the
    /// queue, at the next one's key.
    pub fn next_arrival(&mut self, mut arrivals: Box<Arrivals>) -> Packet {
        let packet = arrivals.packet();
        arrivals.next += 1;
        if arrivals.next < arrivals.len {
            let key = arrivals.key();
            self.push(key, Event::Arrival(arrivals));
        }
        packet
    }

    /// Decides a packet's fate as it arrives; true when the receiver gets it.
    pub fn arrive(&mut self, packet: &Packet) -> bool {
        let fate = self.fate(packet);
        self.prune_air(packet.to().module);
        self.record_packet(packet, fate.name());
        if fate == Fate::Delivered {
            self.counters.delivered += 1;
            self.modules[packet.to().module].stats.received += 1;
            return true;
        }
        self.counters.count_drop(fate);
        self.modules[packet.to().module].stats.dropped += 1;
        let Some(event) = fate.event() else {
            return false;
        };
        if self.tracing() {
            let view = self.view();
            let detail = format!(
                "{} <- {} ({} bytes)",
                view.port_name(packet.to()),
                view.port_name(packet.from()),
                packet.bytes.len()
            );
            self.log(Some(packet.to().module), event, detail);
        }
        false
    }

    fn fate(&mut self, p: &Packet) -> Fate {
        if !self.modules[p.to().module].powered {
            return Fate::Off;
        }
        if self.turn_breaks(p.from().module, p.to().module) {
            return Fate::Moving;
        }
        let faults = self.faults_on();
        if faults && (self.blocked(p.from()) || self.blocked(p.to())) {
            return Fate::Blocked;
        }
        if self.preset.half_duplex_sides && self.collides(p) {
            return Fate::Collision;
        }
        if !faults {
            return Fate::Delivered;
        }
        let dead = self.modules[p.to().module]
            .dead
            .checked_shr(u32::from(p.to().connector))
            .is_some_and(|bits| bits & 1 == 1);
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
                && self.view().index(&b.module) == Some(port.module)
                && (b.from_ms..b.to_ms).contains(&now_ms)
        })
    }

    /// Half duplex: the receiver's hemisphere UART heard another packet, or was sending,
    /// while this one was on the air.
    fn collides(&self, p: &Packet) -> bool {
        let h = self.view().side(p.to().connector);
        self.air.get(p.to().module).is_some_and(|log| {
            log.iter().any(|a| {
                a.hemisphere() == h && a.packet() != p.id && a.start < p.end && a.end > p.start
            })
        })
    }

    /// Forgets module m's records that no collision check can need: a packet arriving from
    /// now on is either on the air already (it started at most `longest_air_us` ago) or
    /// sent later (it starts now or after), so a record that ended before both matters to
    /// no packet.
    fn prune_air(&mut self, m: usize) {
        let horizon = self.now.saturating_sub(self.longest_air_us);
        if let Some(log) = self.air.get_mut(m) {
            log.retain(|a| a.end >= horizon);
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
