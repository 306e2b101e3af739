//! The simulation state that the HAL callbacks and the event loop share: time, the event
//! queue, the world, every module's platform data, counters, violations and the trace.
//! Operations live in `ops.rs`, the infrared network in `network.rs`.
//!
//! Layering (no import circle): what the state holds is below it (`event.rs`, `packet.rs`,
//! `links.rs`, `queue.rs`, `describe.rs`, `report.rs`, `recorded.rs`, `trace.rs`); what acts on it is above
//! (`ops.rs`, `network.rs`, `ffi.rs`, `record.rs`, `wake.rs`, the engine).

use crate::describe::{Describer, DESCRIPTION_BYTES};
use crate::event::Event;
use crate::links::Links;
use crate::packet::{Air, Packet, QUEUES};
use crate::queue::{Key, Queue};
use crate::report::{Counters, Refusal, Violation, STATE_COLUMN};
use crate::scenario::{Durations, Preset, Scenario, Stepping, StuckPart};
use crate::sequence::Sequence;
use crate::trace::{Outputs, Trace};
use dynarole_recording::TraceEvent;
use dynarole_replay::RobotWorld;
use dynarole_world::{Configuration, Port, View};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Controller period of every module (docs/simulator.md).
pub const STEP_US: u64 = 5_000;
/// Bytes of non-volatile storage per module (the ATmega128's EEPROM).
const NV_BYTES: usize = 4096;
/// What `dr_hal_id` answers for a module without an ID (or with one that does not fit the
/// runtime's 16 bits): the last 16-bit value, so that no label `M0` to `M65534` names it and
/// an unlabelled module never takes module 0's role (it did when this was 0).
pub const NO_ID: u16 = 0xFFFF;
/// The platform data of one module. Sized with care (no heap until the module writes its
/// storage; what few modules need is kept aside: `State::waiting`, `State::air`): the
/// simulator's memory grows with the modules (`tests/memory.rs`). Its name is the world's
/// (`View::name`).
#[derive(Clone, Debug)]
pub struct Module {
    pub id: u16,
    pub powered: bool,
    pub failed: bool,
    pub leds: u8,
    /// Receive channels that are dead (permanent link failure): bit c for connector c.
    pub dead: u8,
    pub power_on_at: u64,
    /// Power cycles so far (at most two per `power` entry of the scenario, plus one).
    pub generation: u32,
    /// Order of the last power-on among all power-ons (orders steps at one instant).
    pub rank: u64,
    /// The instant of the step in the queue that is this module's next (stale ones are
    /// skipped); `None` while it waits for a packet (tickless) or is off.
    pub next_step: Option<u64>,
    pub finished_at: Option<u64>,
    /// When each send queue (channel, or hemisphere when half duplex) is free again.
    pub busy_until: [u64; QUEUES],
    /// The storage up to the last byte ever written (at most NV_BYTES): bytes beyond it have
    /// never been written and read as 0xFF.
    pub nv: Vec<u8>,
    pub stats: ModuleStats,
}

impl Module {
    /// Whether a step queued for `time` in power-on `generation` is still this module's
    /// next (not cancelled by a power cycle, nor replaced by another wake-up).
    fn step_live(&self, generation: u32, time: u64) -> bool {
        self.powered && self.generation == generation && self.next_step == Some(time)
    }
}

#[derive(Clone, Debug, Default)]
pub struct ModuleStats {
    pub sent: u64,
    pub received: u64,
    pub dropped: u64,
    pub operations: u64,
    pub resets: u64,
    pub power_cycles: u64,
}

/// Physical state of one statement.
#[derive(Clone, Debug, Default)]
pub struct Phys {
    pub started: Option<u64>,
    pub done: Option<u64>,
    pub running: Option<u64>,
    pub failed: bool,
}

/// One physical execution of a statement's operation.
#[derive(Clone, Debug)]
pub struct Attempt {
    pub statement: usize,
    pub module: usize,
    /// The scenario's fault that makes it fail without effect, decided as it begins.
    pub fault: Option<Injected>,
}

/// Why an attempt fails without effect (`ops/faults.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Injected {
    /// `faults.operation_failure` drew a failure.
    Transient,
    /// Its part is `State::stuck[k]`.
    Stuck(usize),
}

/// Two running turns found to bring modules within the limit at an instant still to come:
/// reported then if both are still running.
pub struct Clash {
    /// The attempts of the turns that bring the modules together (the earliest started
    /// first) and their statements.
    pub attempts: Vec<u64>,
    pub statements: Vec<usize>,
    /// The two modules that come closer than the limit.
    pub modules: (usize, usize),
    pub limit: f64,
}

pub struct State {
    pub seq: Arc<Sequence>,
    pub scenario: Scenario,
    pub preset: Preset,
    /// The operations' durations: the scenario's `[timing]` resolved for the robot
    /// (`Timing::durations`).
    pub durations: Durations,
    pub now: u64,
    queue: Queue,
    pub(crate) next_seq: u64,
    /// Power-ons so far (each module's `rank`).
    next_rank: u64,
    /// The key of the event being dispatched.
    current: Key,
    /// Tickless: modules that wait for their operation's status to leave RUNNING
    /// (`DR_WAKE_OP`), so that a completion or failure wakes them.
    pub op_waiters: BTreeSet<usize>,
    /// The configuration; change it only through `apply` (the link cache depends on it).
    pub world: RobotWorld,
    /// Per module, where its broadcasts go (`network.rs`), while the world is unchanged.
    pub links: Links,
    pub modules: Vec<Module>,
    /// By module, the statements it started since the last time all were finished (what
    /// op_status reports on); only modules that run operations have an entry.
    pub waiting: BTreeMap<usize, Vec<usize>>,
    /// Half duplex (`Preset::half_duplex_sides`), by module: its recent transmissions and receptions
    /// (`network.rs`); empty otherwise.
    pub air: Vec<Vec<Air>>,
    /// The longest air time of any packet sent so far (µs): how long `air` records matter.
    pub longest_air_us: u64,
    pub phys: Vec<Phys>,
    pub attempts: BTreeMap<u64, Attempt>,
    pub next_id: u64,
    /// Turns in progress: attempt -> (turning module, which modules move).
    pub turns: BTreeMap<u64, (usize, Vec<bool>)>,
    /// Turns in progress that move something: attempt -> (start, end) in µs.
    pub spans: BTreeMap<u64, (u64, u64)>,
    /// Clashes found between running turns, each due at its instant (`Event::Clash`).
    pub clashes: Vec<Clash>,
    /// The clash the last search of the running turns found, the only one in force.
    pub pending_clash: Option<u32>,
    /// Clashes reported, by their attempts and modules: one overlap is one violation.
    pub clashes_reported: BTreeSet<(Vec<u64>, (usize, usize))>,
    pub rng_loss: ChaCha8Rng,
    rng_hal: ChaCha8Rng,
    pub rng_faults: ChaCha8Rng,
    /// Only drawn from when `timing.variation` is set, so exact runs are unchanged by it.
    pub rng_timing: ChaCha8Rng,
    /// Only drawn from for an operation whose kind may fail (`faults.operation_failure`), so
    /// runs without such faults are unchanged by it.
    pub rng_operations: ChaCha8Rng,
    /// The scenario's stuck parts, resolved.
    pub stuck: Vec<StuckPart>,
    /// By module, when it dies (µs; the earliest of its `[[dead]]` entries).
    pub death_at: BTreeMap<usize, u64>,
    /// Modules that died: never powered, stepped or reached again.
    pub died: BTreeSet<usize>,
    pub counters: Counters,
    pub violations: Vec<Violation>,
    pub refusals: Vec<Refusal>,
    /// The trace lines, kept and/or written as they come (`trace.rs`).
    pub trace: Option<Trace>,
    /// Whether the trace is also kept as data for a recording (`recorded`).
    pub record: bool,
    /// Where the time of each event goes for a progress line (`Outputs::clock`).
    clock: Option<Arc<AtomicU64>>,
    /// Reads the modules' protocol state for the trace (set by the engine while it runs, and
    /// only when there is a trace).
    pub describer: Option<Describer>,
    pub first_finished: Option<u64>,
    /// The last frame each module broadcast, when the run records them (the fault-free run
    /// that stands for a second robot, `Scenario::foreign`).
    pub last_frames: Option<Vec<Option<Vec<u8>>>>,
    /// What the second robot's modules broadcast last (from that run), by module.
    pub foreign_frames: Vec<Option<Vec<u8>>>,
    /// The trace as data for the viewer's recording (when `record`, `record.rs`).
    pub recorded: crate::recorded::Recorded,
    /// Modules that have declared the end (`finished_at` set), so that `all_finished`, asked
    /// after every event, does not walk every module.
    finished: usize,
    /// Modules stopped by their failure policy, until their next init (`stops.rs`).
    pub stopped: BTreeMap<usize, crate::report::Stop>,
}

/// A uniform draw in [0, 1).
pub fn uniform(rng: &mut ChaCha8Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

fn stream(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

impl State {
    pub fn new(
        seq: Arc<Sequence>,
        (world, preset, durations): (RobotWorld, Preset, Durations),
        scenario: Scenario,
        seed: u64,
        trace: bool,
    ) -> State {
        let view = world.view();
        let mut setup = stream(seed, 0);
        let connectors = view.connectors();
        let modules = (0..view.len())
            .map(|m| Module {
                id: view
                    .id(m)
                    .and_then(|i| u16::try_from(i).ok())
                    .unwrap_or(NO_ID),
                powered: false,
                failed: false,
                leds: 0,
                dead: (0..connectors)
                    .filter(|_| uniform(&mut setup) < scenario.network.dead_link_p)
                    .fold(0, |bits, c| bits | 1 << c),
                power_on_at: 0,
                generation: 0,
                rank: 0,
                next_step: None,
                finished_at: None,
                busy_until: [0; QUEUES],
                nv: Vec::new(),
                stats: ModuleStats::default(),
            })
            .collect();
        let phys = vec![Phys::default(); seq.len()];
        let stuck = scenario.stuck_parts(&seq.robot, |name| view.index(name));
        let mut death_at = BTreeMap::new();
        for d in &scenario.dead {
            if let Some(m) = view.index(&d.module) {
                let at = d.at_ms.saturating_mul(1000);
                let due = death_at.entry(m).or_insert(at);
                *due = (*due).min(at);
            }
        }
        let links = Links::new(view.len(), connectors);
        let air = if preset.half_duplex_sides {
            vec![Vec::new(); view.len()]
        } else {
            Vec::new()
        };
        let mut state = State {
            seq,
            scenario,
            preset,
            durations,
            now: 0,
            queue: Queue::new(),
            next_seq: 0,
            next_rank: 0,
            current: Key::plain(0, 0, 0),
            op_waiters: BTreeSet::new(),
            world,
            links,
            modules,
            waiting: BTreeMap::new(),
            air,
            longest_air_us: 0,
            phys,
            attempts: BTreeMap::new(),
            next_id: 1,
            turns: BTreeMap::new(),
            spans: BTreeMap::new(),
            clashes: Vec::new(),
            pending_clash: None,
            clashes_reported: BTreeSet::new(),
            rng_loss: stream(seed, 1),
            rng_hal: stream(seed, 2),
            rng_faults: stream(seed, 3),
            rng_timing: stream(seed, 4),
            rng_operations: stream(seed, 5),
            stuck,
            death_at,
            died: BTreeSet::new(),
            counters: Counters::default(),
            violations: Vec::new(),
            refusals: Vec::new(),
            trace: Trace::new(trace, None),
            record: trace,
            clock: None,
            describer: None,
            first_finished: None,
            last_frames: None,
            foreign_frames: Vec::new(),
            recorded: crate::recorded::Recorded::default(),
            finished: 0,
            stopped: BTreeMap::new(),
        };
        state.schedule_start(&mut setup);
        state
    }

    /// What the run writes besides its report: the trace file (added to the trace kept in
    /// memory, if any), the recording and its limit, the clock for progress.
    pub fn set_outputs(&mut self, outputs: Outputs) {
        if outputs.trace.is_some() {
            let keep = self.trace.as_ref().is_some_and(Trace::keeps);
            self.trace = Trace::new(keep, outputs.trace);
        }
        if outputs.record && !self.record {
            self.record = true;
            self.recorded = crate::recorded::Recorded::with_limits(
                outputs.record_limit,
                outputs.record_packets,
            );
        }
        self.clock = outputs.clock;
    }

    /// Power-on of every module, then the scenario's faults, as events.
    fn schedule_start(&mut self, setup: &mut ChaCha8Rng) {
        for m in 0..self.modules.len() {
            // No draw for a preset that powers everything at 0, so that its runs' streams are
            // what they were.
            let spread = self.preset.power_on_spread_us;
            let at = if spread == 0 {
                0
            } else {
                setup.next_u64() % spread
            };
            self.schedule(at, Event::PowerOn { module: m });
        }
        let view = self.world.view();
        let index = |name: &str| view.index(name).unwrap_or(usize::MAX);
        let mut faults = Vec::new();
        for r in &self.scenario.reset {
            faults.push((
                r.at_ms * 1000,
                Event::Reset {
                    module: index(&r.module),
                },
            ));
        }
        for p in &self.scenario.power {
            let module = index(&p.module);
            faults.push((p.off_ms * 1000, Event::PowerOff { module }));
            faults.push((p.on_ms * 1000, Event::PowerOn { module }));
        }
        if let Some(r) = &self.scenario.random_resets {
            for m in 0..self.modules.len() {
                faults.push((
                    reset_interval(r.interval_ms, m),
                    Event::ResetCheck { module: m },
                ));
            }
        }
        for (entry, f) in self.scenario.foreign.iter().enumerate() {
            faults.push((f.from_ms * 1000, Event::Foreign { entry }));
        }
        // A death is a power-off that `power_off` finds due (`ops/faults.rs`).
        let timeout_us = self.scenario.timeout_ms * 1000;
        for (&module, &at) in self.death_at.iter().filter(|d| *d.1 <= timeout_us) {
            faults.push((at, Event::PowerOff { module }));
        }
        for (at, event) in faults {
            self.schedule(at, event);
        }
    }

    /// `foreign[entry]`'s packet now: the receiving port, the other robot's frame and its
    /// identity (robot, execution); the next one is scheduled. `None` when the other robot's
    /// module sent nothing.
    pub fn foreign_packet(&mut self, entry: usize) -> Option<(Port, Vec<u8>, u16, u32)> {
        let f = self.scenario.foreign.get(entry)?.clone();
        let next = self.now + f.interval_ms * 1000;
        if next < f.to_ms * 1000 {
            self.schedule(next, Event::Foreign { entry });
        }
        let module = self.view().index(&f.module)?;
        let frame = self.foreign_frames.get(module)?.clone()?;
        self.counters.foreign += 1;
        let port = Port {
            module,
            connector: f.connector,
        };
        if self.tracing() {
            let detail = format!(
                "robot {} -> {}.C{} ({} bytes)",
                f.robot,
                f.module,
                f.connector,
                frame.len()
            );
            self.log(Some(module), TraceEvent::Foreign, detail);
        }
        Some((port, frame, f.robot, f.execution_beside(self.seq.execution)))
    }

    pub fn n_modules(&self) -> usize {
        self.modules.len()
    }

    pub fn view(&self) -> View<'_> {
        self.world.view()
    }

    /// The world's configuration in the data-file format (a robot without one: `None`),
    /// moved out (not copied) at the end of a run.
    pub fn into_configuration(self) -> Option<Configuration> {
        self.world.into_configuration()
    }

    pub fn schedule(&mut self, time: u64, event: Event) {
        let key = Key::plain(time, self.now, self.next_seq);
        self.next_seq += 1;
        self.push(key, event);
    }

    /// Into the queue; stale steps go first when the queue would otherwise grow.
    pub(crate) fn push(&mut self, key: Key, event: Event) {
        if self.queue.heap_full() {
            let modules = &self.modules;
            self.queue.drop_stale(|key, event| match *event {
                Event::Step { module, generation } => modules
                    .get(module as usize)
                    .is_none_or(|x| !x.step_live(generation, key.time())),
                _ => false,
            });
        }
        self.queue.push(key, event);
    }

    /// The next event, and the clock moved to it; `None` when nothing is left before `until`.
    pub fn pop(&mut self, until: u64) -> Option<Event> {
        let (key, event) = self.queue.pop(until)?;
        self.now = key.time();
        self.current = key;
        if let Some(clock) = &self.clock {
            clock.store(self.now, Ordering::Relaxed);
        }
        self.counters.events += 1;
        Some(event)
    }

    /// The key of the event being dispatched.
    pub(crate) fn current(&self) -> Key {
        self.current
    }

    /// A stale step was popped (not due any more): it is not counted as an event.
    pub fn uncount(&mut self) {
        self.counters.events = self.counters.events.saturating_sub(1);
    }

    /// Whether modules are stepped only when they need it (`Scenario::stepping`).
    pub fn tickless(&self) -> bool {
        self.scenario.stepping == Stepping::Tickless
    }

    /// Whether faults (loss, blocks, resets) are still on.
    pub fn faults_on(&self) -> bool {
        self.now < self.scenario.faults_end_ms() * 1000
    }

    /// Whether a trace is kept or recorded (callers skip formatting details when not).
    pub fn tracing(&self) -> bool {
        self.trace.is_some() || self.record
    }

    /// Writes the rest of the trace file and closes it: the first error writing it, if any.
    pub fn flush_trace(&mut self) -> std::io::Result<()> {
        self.trace.as_mut().map_or(Ok(()), Trace::flush)
    }

    /// One trace line: time, module, event, the module's protocol state (`-` when there is
    /// none), detail. Events are the vocabulary's (`TraceEvent`), never a word made up here.
    pub fn log(&mut self, module: Option<usize>, event: TraceEvent, detail: impl AsRef<str>) {
        if !self.tracing() {
            return;
        }
        let name = match module {
            Some(m) if m < self.modules.len() => self.world.view().name(m),
            _ => "-".to_string(),
        };
        let mut buffer = [0u8; DESCRIPTION_BYTES];
        let len = match (module, &self.describer) {
            (Some(m), Some(d)) => d.describe(m, &mut buffer),
            _ => {
                buffer[0] = b'-';
                1
            }
        };
        let state = std::str::from_utf8(buffer.get(..len).unwrap_or_default()).unwrap_or("?");
        if let Some(trace) = &mut self.trace {
            let _ = write!(
                trace.line,
                "{:>8}.{:03} {:<6} {:<10} {:<width$} {}",
                self.now / 1000,
                self.now % 1000,
                name,
                event.name(),
                state,
                detail.as_ref(),
                width = STATE_COLUMN
            );
            trace.end_line();
        }
        if self.record {
            self.recorded
                .row(self.now, module, event, state, detail.as_ref());
        }
    }

    pub fn statement_label(&self, s: usize) -> String {
        format!("#{s} {}", self.seq.text(s))
    }

    /// The statement's label when there is a trace to write it to (else nothing: no
    /// formatting on the simulation path of an untraced run).
    pub fn trace_label(&self, s: usize) -> String {
        if self.tracing() {
            self.statement_label(s)
        } else {
            String::new()
        }
    }

    // ----- module life -----

    /// Powers a module on (first time or after a power-off): the engine then runs its init.
    pub fn power_on(&mut self, m: usize) -> bool {
        let now = self.now;
        if self.died.contains(&m) {
            return false;
        }
        let Some(module) = self.modules.get_mut(m) else {
            return false;
        };
        if module.powered {
            return false;
        }
        module.powered = true;
        module.power_on_at = now;
        module.generation = module.generation.wrapping_add(1);
        module.rank = self.next_rank;
        self.next_rank += 1;
        self.log(Some(m), TraceEvent::PowerOn, "");
        self.put_step(m, now);
        true
    }

    /// Powers a module off: silent and inert; its operation in progress stops. Its death,
    /// when it is due, is a power-off for good.
    pub fn power_off(&mut self, m: usize) {
        if self.die_if_due(m) {
            return;
        }
        let Some(module) = self.modules.get_mut(m) else {
            return;
        };
        if !module.powered {
            return;
        }
        module.powered = false;
        module.generation = module.generation.wrapping_add(1);
        module.next_step = None;
        module.stats.power_cycles += 1;
        self.counters.power_cycles += 1;
        self.log(Some(m), TraceEvent::PowerOff, "");
        self.op_waiters.remove(&m);
        self.interrupt_operations(m);
    }

    /// A reset is due: true when the module is on (the engine then re-runs its init).
    pub fn reset(&mut self, m: usize) -> bool {
        if !self.modules.get(m).is_some_and(|x| x.powered) {
            return false;
        }
        self.modules[m].stats.resets += 1;
        self.counters.resets += 1;
        self.log(Some(m), TraceEvent::Reset, "");
        true
    }

    /// A periodic random-reset check; true when the module resets now.
    pub fn reset_check(&mut self, m: usize) -> bool {
        let Some(r) = self.scenario.random_resets.clone() else {
            return false;
        };
        if !self.faults_on() {
            return false;
        }
        let next = self.now + reset_interval(r.interval_ms, m);
        self.schedule(next, Event::ResetCheck { module: m });
        uniform(&mut self.rng_faults) < r.probability && self.reset(m)
    }

    /// Whether a step of `m` in `generation` at the current time is still due (not
    /// cancelled by a power cycle, nor replaced by another wake-up); a due step is consumed.
    pub fn step_due(&mut self, m: usize, generation: u32) -> bool {
        let now = self.now;
        let Some(x) = self.modules.get_mut(m) else {
            return false;
        };
        let due = x.step_live(generation, now);
        if due {
            x.next_step = None;
        }
        due
    }

    /// The key of module `m`'s step at `time`, one of its 5 ms instants: the first one, at
    /// power-on, counts as scheduled then; every later one at the instant before it.
    pub(crate) fn step_key(&self, m: usize, time: u64) -> Key {
        let module = &self.modules[m];
        let scheduled = if time == module.power_on_at {
            time
        } else {
            time.saturating_sub(STEP_US)
        };
        Key::step(time, scheduled, module.rank)
    }

    /// Puts module `m`'s step at `time` (one of its 5 ms instants) in the queue, as its next.
    pub(crate) fn put_step(&mut self, m: usize, time: u64) {
        let key = self.step_key(m, time);
        let event = Event::Step {
            // Fits: a run has at most `links::MAX_MODULES` modules.
            module: m as u32,
            generation: self.modules[m].generation,
        };
        self.modules[m].next_step = Some(time);
        if self.tickless() {
            self.push(key, event);
        } else {
            self.queue.push_periodic(key, event);
        }
    }

    /// The fixed stepping: the next periodic step of `m`, after STEP_US.
    pub fn schedule_step(&mut self, m: usize) {
        self.put_step(m, self.now + STEP_US);
    }

    /// After a step: the module says whether it knows the sequence is over (S3 is checked).
    pub fn note_finished(&mut self, m: usize, finished: bool) {
        let known = self.modules.get(m).map(|x| x.finished_at.is_some());
        if !finished || known != Some(false) {
            return;
        }
        self.modules[m].finished_at = Some(self.now);
        self.finished += 1;
        self.first_finished.get_or_insert(self.now);
        self.log(Some(m), TraceEvent::Finished, "declares the end");
        self.check_end(m);
    }

    pub fn all_finished(&self) -> bool {
        self.finished == self.modules.len()
    }

    // ----- HAL answers -----

    pub fn now_ms(&self, m: usize) -> u32 {
        self.clock_at(m, self.now)
    }

    pub fn random(&mut self) -> u16 {
        (self.rng_hal.next_u64() >> 48) as u16
    }

    pub fn id(&self, m: usize) -> u16 {
        self.modules[m].id
    }

    pub fn connected(&self, m: usize, connector: u8) -> u8 {
        let port = Port {
            module: m,
            connector,
        };
        u8::from(self.view().latched_to(port).is_some())
    }

    pub fn neighbour_id(&self, m: usize, connector: u8) -> i16 {
        let view = self.view();
        view.latched_to(Port {
            module: m,
            connector,
        })
        .and_then(|p| view.id(p.module))
        .and_then(|id| i16::try_from(id).ok())
        .unwrap_or(-1)
    }

    pub fn joint(&self, m: usize, joint: u8) -> i16 {
        self.view()
            .joint(m, joint)
            .and_then(|j| i16::try_from(j).ok())
            .unwrap_or(0)
    }

    pub fn leds(&mut self, m: usize, value: u8) {
        self.modules[m].leds = value;
    }

    pub fn nv_read(&self, m: usize, addr: u16, out: &mut [u8]) {
        let nv = &self.modules[m].nv;
        for (k, byte) in out.iter_mut().enumerate() {
            *byte = nv.get(usize::from(addr) + k).copied().unwrap_or(0xFF);
        }
    }

    pub fn nv_write(&mut self, m: usize, addr: u16, data: &[u8]) {
        let nv = &mut self.modules[m].nv;
        let end = (usize::from(addr) + data.len()).min(NV_BYTES);
        if nv.len() < end {
            nv.resize(end, 0xFF);
        }
        for (k, byte) in data.iter().enumerate() {
            if let Some(slot) = nv.get_mut(usize::from(addr) + k) {
                *slot = *byte;
            }
        }
    }
}

/// USSR's reset checks: module k every `interval + k/7` seconds (faults notes, d).
fn reset_interval(interval_ms: u64, m: usize) -> u64 {
    interval_ms * 1000 + (m as u64) * 1_000_000 / 7
}

// Sized deliberately: every queued event is a key and an event, and every module a `Module`
// (`tests/memory.rs` holds the whole run to its budget).
const _: () = assert!(std::mem::size_of::<Event>() == 16);
const _: () = assert!(std::mem::size_of::<Key>() == 24);
const _: () = assert!(std::mem::size_of::<Packet>() == 56);
const _: () = assert!(std::mem::size_of::<Air>() == 24);
