//! The event loop of `--firmware avr`: every module is an emulated ATmega128 running its image.
//! The cores run in lockstep quanta of simulated time; after each quantum, what each core did
//! (bytes sent, controller register writes, status pins) is applied to the simulation state in
//! time order, merged with the state's own events (arrivals, operation completions, faults),
//! exactly the calls the host platform makes (`dr_hal_broadcast`, `dr_hal_op_start`, ...).
//! A core sees the world's changes at quantum boundaries, up to one quantum late.

use super::emu::{self, Core, Library};
use super::image::Image;
use crate::describe::Describer;
use crate::engine::Finished;
use crate::event::Event;
use crate::ops::OpCall;
use crate::packet::Packet;
use crate::state::State;
use std::rc::Rc;

/// The ATmega128's clock: cycles per microsecond of simulated time.
const CYCLES_PER_US: u64 = 16;
/// Lockstep quantum (µs).
const QUANTUM_US: u64 = 1_000;

/// Registers and pins of `runtime/avr/dr_avr_board.h`.
mod board {
    pub const REG_STATEMENT: usize = 0x00;
    pub const REG_OP: usize = 0x02;
    pub const REG_INDEX: usize = 0x03;
    pub const REG_ADDRESS: u8 = 0x04;
    pub const REG_GO: u8 = 0x05;
    pub const REG_LEDS: u8 = 0x06;
    pub const REG_STATUS: u8 = 0x10;
    pub const REG_ID: u8 = 0x11;
    pub const REG_CONNECTED: u8 = 0x13;
    pub const REG_NEIGHBOUR: u8 = 0x20;
    pub const REG_JOINT: u8 = 0x30;
    pub const REG_ARGS: usize = 0x40;
    pub const REGS: usize = 0x60;
    pub const CHANNELS: u8 = 8;
    pub const JOINTS: u8 = 8;
    pub const PIN_STEP: u8 = 1 << 2;
    pub const PIN_RECEIVE: u8 = 1 << 3;
    pub const PIN_FINISHED: u8 = 1 << 4;
    pub const PIN_STOPPED: u8 = 1 << 6;
}

/// What the emulator measured on one module.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct ModuleFirmware {
    pub name: String,
    /// Deepest stack use (bytes, painted stack), over every power-on and reset.
    pub stack_bytes: u32,
    /// Cycles the core ran (awake or asleep) and slept.
    pub cycles: u64,
    pub sleep_cycles: u64,
    pub steps: u64,
    pub step_cycles: u64,
    pub step_cycles_max: u64,
    pub receives: u64,
    pub receive_cycles: u64,
    pub receive_cycles_max: u64,
    /// Frames the board's receive arbiter dropped (its queue was full).
    pub arbiter_drops: u64,
}

/// The image's footprint and every module's measurements.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct FirmwareReport {
    pub text: u64,
    pub data: u64,
    pub bss: u64,
    pub modules: Vec<ModuleFirmware>,
}

/// A frame leaving a module's USART.
struct Outgoing {
    mask: u8,
    bytes: Vec<u8>,
}

struct Board {
    core: Core,
    /// (time in µs, cycle) of the last power-on: maps the core's cycles to simulated time.
    on: Option<(u64, u64)>,
    /// The controller's registers as the firmware wrote them.
    regs: [u8; board::REGS],
    outgoing: Option<Outgoing>,
    pins: u8,
    since_step: u64,
    since_receive: u64,
    address: u8,
    /// Log entries after this time (µs) are void: the core was reset or stopped meanwhile.
    void_after: Option<u64>,
    /// The state description being received (`EV_TEXT` entries), for the trace.
    text: Vec<u8>,
    stats: ModuleFirmware,
}

/// One log entry, placed in simulated time.
struct Output {
    time: u64,
    module: usize,
    event: emu::Event,
}

impl Board {
    fn time_of(&self, cycle: u64) -> u64 {
        let (us, base) = self.on.unwrap_or((0, 0));
        us + cycle.saturating_sub(base) / CYCLES_PER_US
    }

    /// Power-on or reset at `now`: the MCU restarts; the stack measure restarts too.
    fn restart(&mut self, now: u64, power_on: bool) {
        self.note_stack();
        self.core.reset();
        if power_on {
            self.on = Some((now, self.core.cycle()));
        }
        self.outgoing = None;
        self.pins = 0;
        self.text.clear();
        self.void_after = Some(now);
    }

    fn power_off(&mut self, now: u64) {
        self.note_stack();
        self.note_cycles();
        self.on = None;
        self.outgoing = None;
        self.void_after = Some(now);
    }

    fn note_stack(&mut self) {
        self.stats.stack_bytes = self.stats.stack_bytes.max(self.core.stack_high_water());
    }

    fn note_cycles(&mut self) {
        if let Some((_, base)) = self.on {
            self.stats.cycles += self.core.cycle().saturating_sub(base);
        }
    }

    /// The sensor registers, from the world as it is now.
    fn refresh(&mut self, state: &State, m: usize) {
        let id = state.id(m).to_le_bytes();
        self.core.set_reg(board::REG_STATUS, state.op_status(m));
        self.core.set_reg(board::REG_ID, id[0]);
        self.core.set_reg(board::REG_ID + 1, id[1]);
        let mut connected = 0u8;
        for c in 0..board::CHANNELS {
            connected |= state.connected(m, c) << c;
            let n = state.neighbour_id(m, c).to_le_bytes();
            self.core.set_reg(board::REG_NEIGHBOUR + 2 * c, n[0]);
            self.core.set_reg(board::REG_NEIGHBOUR + 2 * c + 1, n[1]);
        }
        self.core.set_reg(board::REG_CONNECTED, connected);
        for j in 0..board::JOINTS {
            let v = state.joint(m, j).to_le_bytes();
            self.core.set_reg(board::REG_JOINT + 2 * j, v[0]);
            self.core.set_reg(board::REG_JOINT + 2 * j + 1, v[1]);
        }
    }
}

/// Runs the modules' firmware until every module has declared the end, or the timeout.
pub fn run(
    lib: &Rc<Library>,
    image: &Image,
    max_args: usize,
    mut state: State,
) -> Result<(Finished, FirmwareReport), String> {
    let n = state.n_modules();
    let timeout = state.scenario.timeout_ms * 1000;
    let mut boards = (0..n)
        .map(|m| {
            Ok(Board {
                core: Core::open(lib, &image.elf)?,
                on: None,
                regs: [0; board::REGS],
                outgoing: None,
                pins: 0,
                since_step: 0,
                since_receive: 0,
                address: 0xFF,
                void_after: None,
                text: Vec::new(),
                stats: ModuleFirmware {
                    name: state.view().name(m),
                    ..ModuleFirmware::default()
                },
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    if state.tracing() {
        state.describer = Some(Describer::texts(n));
    }
    let mut log = Vec::new();
    let mut outputs = Vec::new();
    let mut until = 0u64;
    while !state.all_finished() && until < timeout {
        until = (until + QUANTUM_US).min(timeout);
        outputs.clear();
        for (m, b) in boards.iter_mut().enumerate() {
            let Some((us, base)) = b.on else { continue };
            b.refresh(&state, m);
            b.void_after = None;
            if !b.core.run(base + (until - us) * CYCLES_PER_US) {
                return Err(format!(
                    "the firmware of module {} stopped (the emulated MCU crashed or slept with interrupts off)",
                    b.stats.name
                ));
            }
            log.clear();
            b.core.take(&mut log);
            if b.core.overflowed() {
                return Err(format!(
                    "the emulator's log of module {} overflowed",
                    b.stats.name
                ));
            }
            outputs.extend(log.iter().map(|&event| Output {
                time: b.time_of(event.cycle),
                module: m,
                event,
            }));
        }
        // Stable: a module's entries stay in their order.
        outputs.sort_by_key(|o| (o.time, o.module));
        for o in &outputs {
            while let Some(event) = state.pop(o.time.saturating_sub(1)) {
                dispatch(&mut state, &mut boards, event);
            }
            let b = &mut boards[o.module];
            if b.void_after.is_some_and(|t| o.time > t) || b.on.is_none() {
                continue;
            }
            state.now = state.now.max(o.time);
            apply(&mut state, b, o, max_args);
            if state.all_finished() {
                break;
            }
        }
        while !state.all_finished() {
            let Some(event) = state.pop(until) else { break };
            dispatch(&mut state, &mut boards, event);
        }
        state.now = state.now.max(until);
    }
    Ok(finish(state, boards, image, timeout))
}

fn finish(
    mut state: State,
    boards: Vec<Board>,
    image: &Image,
    timeout: u64,
) -> (Finished, FirmwareReport) {
    let addresses = boards.iter().map(|b| b.address).collect();
    let modules = boards
        .into_iter()
        .map(|mut b| {
            b.note_stack();
            b.note_cycles();
            b.stats.sleep_cycles = b.core.sleep_cycles();
            b.stats
        })
        .collect();
    if !state.all_finished() {
        state.now = timeout;
        state.log(None, dynarole_recording::TraceEvent::Timeout, "");
    }
    let report = FirmwareReport {
        text: image.text,
        data: image.data,
        bss: image.bss,
        modules,
    };
    (Finished { state, addresses }, report)
}

/// One of the state's own events (the host engine's dispatch, with cores for contexts).
fn dispatch(state: &mut State, boards: &mut [Board], event: Event) {
    let now = state.now;
    match event {
        Event::PowerOn { module } => {
            if state.power_on(module) {
                boards[module].restart(now, true);
            }
        }
        Event::PowerOff { module } => {
            state.power_off(module);
            boards[module].power_off(now);
        }
        // The firmware steps itself (its timer); the end is noted after each of its steps.
        Event::Step { .. } | Event::Foreign { .. } => {}
        Event::OpDone { attempt } => state.op_done(attempt),
        Event::Clash { entry } => state.clash(entry),
        Event::Arrival(arrivals) => {
            let packet = state.next_arrival(arrivals);
            arrive(state, boards, &packet)
        }
        Event::Reset { module } => {
            if state.reset(module) {
                boards[module].restart(now, false);
            }
        }
        Event::ResetCheck { module } => {
            if state.reset_check(module) {
                boards[module].restart(now, false);
            }
        }
    }
}

fn arrive(state: &mut State, boards: &mut [Board], packet: &Packet) {
    if state.arrive(packet) {
        let b = &mut boards[packet.to().module];
        if b.on.is_some() && !b.core.rx(packet.to().connector, &packet.bytes) {
            b.stats.arbiter_drops += 1;
        }
    }
}

/// What a core did, as the calls of the HAL it stands for.
fn apply(state: &mut State, b: &mut Board, o: &Output, max_args: usize) {
    let m = o.module;
    let e = o.event;
    match e.kind {
        emu::EV_TX => {
            let frame = b.outgoing.get_or_insert_with(|| Outgoing {
                mask: e.b,
                bytes: Vec::new(),
            });
            frame.bytes.push(e.a);
            let want = frame
                .bytes
                .get(1)
                .map_or(usize::MAX, |len| usize::from(*len).max(2));
            if frame.bytes.len() >= want {
                if let Some(frame) = b.outgoing.take() {
                    send(state, m, &frame);
                }
            }
        }
        emu::EV_WRITE => {
            b.regs[usize::from(e.a) % board::REGS] = e.b;
            match e.a {
                board::REG_GO => start(state, b, m, max_args),
                board::REG_ADDRESS => b.address = e.b,
                board::REG_LEDS => state.leds(m, e.b),
                _ => {}
            }
        }
        emu::EV_PINS => pins(state, b, m, e),
        emu::EV_TEXT => {
            b.text
                .extend([e.a, e.b].into_iter().take_while(|&c| c != 0));
            if e.a == 0 || e.b == 0 {
                if let Some(d) = state.describer.as_mut() {
                    d.set_text(m, &b.text);
                }
                b.text.clear();
            }
        }
        _ => {}
    }
}

/// A whole frame: every transmitter enabled is a broadcast, else a send per enabled channel.
fn send(state: &mut State, m: usize, frame: &Outgoing) {
    if frame.mask == u8::MAX {
        state.broadcast(m, &frame.bytes);
        return;
    }
    for c in 0..board::CHANNELS {
        if frame.mask & (1 << c) != 0 {
            state.send_on(m, c, &frame.bytes);
        }
    }
}

fn start(state: &mut State, b: &Board, m: usize, max_args: usize) {
    let r = &b.regs;
    let args: Vec<i16> = (0..max_args)
        .map(|k| {
            let at = board::REG_ARGS + 2 * k;
            i16::from_le_bytes([r[at % board::REGS], r[(at + 1) % board::REGS]])
        })
        .collect();
    let call = OpCall {
        address: r[usize::from(board::REG_ADDRESS)],
        statement: u16::from_le_bytes([r[board::REG_STATEMENT], r[board::REG_STATEMENT + 1]]),
        op: r[board::REG_OP],
        index: r[board::REG_INDEX],
        args: &args,
    };
    state.op_start(m, &call);
}

/// The status pins: a step or a receive ends (cycles measured); after a step, the end flag.
fn pins(state: &mut State, b: &mut Board, m: usize, e: emu::Event) {
    let rose = e.a & !b.pins;
    let fell = b.pins & !e.a;
    b.pins = e.a;
    if rose & board::PIN_STEP != 0 {
        b.since_step = e.cycle;
    }
    if rose & board::PIN_RECEIVE != 0 {
        b.since_receive = e.cycle;
    }
    if fell & board::PIN_STEP != 0 {
        let cycles = e.cycle.saturating_sub(b.since_step);
        b.stats.steps += 1;
        b.stats.step_cycles += cycles;
        b.stats.step_cycles_max = b.stats.step_cycles_max.max(cycles);
        // The pins say what dr_module_finished answered: the end, a stop, or neither.
        let answer = if e.a & board::PIN_FINISHED != 0 {
            crate::stops::END_GOAL
        } else if e.a & board::PIN_STOPPED != 0 {
            crate::stops::END_STOPPED
        } else {
            0
        };
        state.note_end(m, answer);
    }
    if fell & board::PIN_RECEIVE != 0 {
        let cycles = e.cycle.saturating_sub(b.since_receive);
        b.stats.receives += 1;
        b.stats.receive_cycles += cycles;
        b.stats.receive_cycles_max = b.stats.receive_cycles_max.max(cycles);
    }
}
