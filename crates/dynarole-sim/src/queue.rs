//! The event queue: events in `Key` order, kept in three structures whose heads `pop`
//! compares, so the order is exactly that of a single priority queue. A FIFO holds the fixed
//! stepping's periodic steps (scheduled in key order); a timing wheel of 1 ms slots holds
//! what happens within the next quarter of a second (packet arrivals, wake-ups, steps out of
//! order), touched in time order, so that memory is read mostly in sequence; a binary heap
//! holds the rest (operations' ends, faults, and anything for the slot being served).

use crate::event::Event;
use std::cmp::{Ordering, Reverse};
use std::collections::{BinaryHeap, VecDeque};

/// Width of one slot of the wheel (µs).
const SLOT_US: u64 = 1_000;
/// Slots of the wheel: its horizon is SLOTS * SLOT_US ahead of the slot being served.
const SLOTS: usize = 256;
/// Heaps smaller than this are never searched for stale events (not worth the time).
const COMPACT_FROM: usize = 4096;

/// Where an event stands in the queue. Events at one time are ordered by when they were
/// scheduled, then plain events before steps, then plain events by scheduling order
/// (`tie`: a sequence number) and steps by their module's power-on order (`tie`: its rank).
/// A step's key depends only on its module and instant (it counts as scheduled at its
/// module's previous 5 ms instant, when the fixed stepping schedules it), never on when it
/// was actually put in the queue: so a tickless run, which schedules its steps at other
/// moments, dispatches every event in the same order as the fixed stepping.
///
/// Fields compare in order (derived `Ord`); `order` packs "is a step" into its top bit above
/// the tie (sequence numbers and ranks stay far below 2^63), so a key takes 24 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Key {
    time: u64,
    scheduled: u64,
    order: u64,
}

/// The top bit of `Key::order`: set for steps.
const STEP: u64 = 1 << 63;

impl Key {
    /// A plain event at `time`, scheduled at `scheduled`, the `seq`-th scheduled.
    pub fn plain(time: u64, scheduled: u64, seq: u64) -> Key {
        Key {
            time,
            scheduled,
            order: seq & !STEP,
        }
    }

    /// A step at `time` that counts as scheduled at `scheduled`, of the module powered on
    /// `rank`-th.
    pub fn step(time: u64, scheduled: u64, rank: u64) -> Key {
        Key {
            time,
            scheduled,
            order: STEP | rank,
        }
    }

    pub fn time(&self) -> u64 {
        self.time
    }
}

/// An event and its place in the queue.
#[derive(Debug)]
struct Scheduled {
    key: Key,
    event: Event,
}

impl PartialEq for Scheduled {
    fn eq(&self, other: &Self) -> bool {
        self.key == other.key
    }
}
impl Eq for Scheduled {}
impl PartialOrd for Scheduled {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Scheduled {
    fn cmp(&self, other: &Self) -> Ordering {
        self.key.cmp(&other.key)
    }
}

/// Events of the next SLOTS slots, one unsorted vector per slot; the slot being served is
/// sorted once, when it is reached (`ready`, last element first).
struct Wheel {
    slots: Vec<Vec<Scheduled>>,
    /// The absolute slot (time / SLOT_US) being served: every event in `slots` is in a later
    /// one, and below `served + SLOTS`.
    served: u64,
    /// The served slot's events, sorted in decreasing key order.
    ready: Vec<Scheduled>,
    /// Events in `slots` (not counting `ready`).
    waiting: usize,
}

impl Wheel {
    fn new() -> Wheel {
        Wheel {
            slots: (0..SLOTS).map(|_| Vec::new()).collect(),
            served: 0,
            ready: Vec::new(),
            waiting: 0,
        }
    }

    /// Takes `item` when its slot is after the served one and within the horizon.
    fn push(&mut self, item: Scheduled) -> Result<(), Scheduled> {
        let slot = item.key.time / SLOT_US;
        if slot <= self.served || slot >= self.served + SLOTS as u64 {
            return Err(item);
        }
        self.slots[(slot % SLOTS as u64) as usize].push(item);
        self.waiting += 1;
        Ok(())
    }

    /// The smallest key, moving on to the next non-empty slot when the served one is done.
    fn head(&mut self) -> Option<Key> {
        if self.ready.is_empty() && self.waiting > 0 {
            let mut slot = self.served + 1;
            while self.slots[(slot % SLOTS as u64) as usize].is_empty() {
                slot += 1;
            }
            let index = (slot % SLOTS as u64) as usize;
            // Taken, not swapped: a slot keeps no capacity once served, so the wheel's memory
            // follows the events waiting, not the largest burst each slot ever held.
            self.ready = std::mem::take(&mut self.slots[index]);
            self.waiting -= self.ready.len();
            self.ready.sort_unstable_by_key(|s| Reverse(s.key));
            self.served = slot;
        }
        self.ready.last().map(|s| s.key)
    }

    fn pop(&mut self) -> Option<Scheduled> {
        self.ready.pop()
    }
}

/// Where an event came from (see `Queue::pop`).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Source {
    Heap,
    Fifo,
    Wheel,
}

pub struct Queue {
    heap: BinaryHeap<Reverse<Scheduled>>,
    fifo: VecDeque<Scheduled>,
    wheel: Wheel,
}

impl Queue {
    pub fn new() -> Queue {
        Queue {
            heap: BinaryHeap::new(),
            fifo: VecDeque::new(),
            wheel: Wheel::new(),
        }
    }

    /// Whether the next push into the heap would make it allocate more (and it is large
    /// enough for that to matter): the moment to drop stale events (`drop_stale`).
    pub fn heap_full(&self) -> bool {
        self.heap.len() == self.heap.capacity() && self.heap.len() >= COMPACT_FROM
    }

    /// Drops from the heap the events `stale` says would be skipped when popped (steps that
    /// a later wake-up replaced): the order of the others does not change, and the heap's
    /// memory follows the events that count. When that frees less than half, the heap grows
    /// as it would have, so that the next drop comes only after as many pushes again.
    pub fn drop_stale(&mut self, stale: impl Fn(&Key, &Event) -> bool) {
        self.heap.retain(|Reverse(s)| !stale(&s.key, &s.event));
        if self.heap.len() * 2 > self.heap.capacity() {
            self.heap.reserve(self.heap.capacity());
        }
    }

    /// Any event.
    pub fn push(&mut self, key: Key, event: Event) {
        if let Err(item) = self.wheel.push(Scheduled { key, event }) {
            self.heap.push(Reverse(item));
        }
    }

    /// A periodic step: into the FIFO when it keeps it sorted (nearly always), else `push`.
    pub fn push_periodic(&mut self, key: Key, event: Event) {
        if self.fifo.back().is_some_and(|last| last.key > key) {
            self.push(key, event);
            return;
        }
        self.fifo.push_back(Scheduled { key, event });
    }

    /// The event with the smallest key, unless its time is after `until`.
    pub fn pop(&mut self, until: u64) -> Option<(Key, Event)> {
        let candidates = [
            (self.heap.peek().map(|Reverse(e)| e.key), Source::Heap),
            (self.fifo.front().map(|e| e.key), Source::Fifo),
            (self.wheel.head(), Source::Wheel),
        ];
        let (key, source) = candidates
            .into_iter()
            .filter_map(|(key, source)| Some((key?, source)))
            .min_by_key(|(key, _)| *key)?;
        if key.time > until {
            return None;
        }
        let item = match source {
            Source::Heap => self.heap.pop().map(|Reverse(e)| e),
            Source::Fifo => self.fifo.pop_front(),
            Source::Wheel => self.wheel.pop(),
        }?;
        Some((item.key, item.event))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Random pushes (near, far, into the slot being served, periodic) interleaved with pops
    /// come out exactly in key order, as from one sorted list.
    #[test]
    fn pops_in_key_order_whatever_the_structure_holding_an_event() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut queue = Queue::new();
        let mut reference: BinaryHeap<Reverse<Key>> = BinaryHeap::new();
        let mut now = 0u64;
        let mut seq = 0u64;
        let mut periodic = 0u64;
        for round in 0..20_000u64 {
            for _ in 0..rng.next_u64() % 3 {
                let ahead = match rng.next_u64() % 4 {
                    0 => rng.next_u64() % 1_000,
                    1 => rng.next_u64() % 20_000,
                    2 => rng.next_u64() % 400_000,
                    _ => rng.next_u64() % 5_000_000,
                };
                let key = Key::plain(now + ahead, now, seq);
                seq += 1;
                queue.push(key, Event::PowerOn { module: 0 });
                reference.push(Reverse(key));
            }
            if round % 5 == 0 {
                periodic = periodic.max(now) + 5_000;
                let key = Key::step(periodic, periodic - 5_000, round);
                queue.push_periodic(key, Event::PowerOn { module: 1 });
                reference.push(Reverse(key));
            }
            if rng.next_u64() % 2 == 0 {
                let got = queue.pop(u64::MAX).map(|(k, _)| k);
                let want = reference.pop().map(|Reverse(k)| k);
                assert_eq!(got, want, "round {round}");
                if let Some(k) = got {
                    now = k.time();
                }
            }
        }
        while let Some(Reverse(want)) = reference.pop() {
            assert_eq!(queue.pop(u64::MAX).map(|(k, _)| k), Some(want));
        }
        assert!(queue.pop(u64::MAX).is_none());
    }
}
