//! The event loop: pops events in queue order (`queue::Key`) and runs the generated C where
//! an event concerns a module (power-on and resets run its init, steps its step, arrivals
//! its receive). Every module has its own zeroed context buffer. With the tickless stepping
//! (`Scenario::stepping`) each module's next step is planned from its
//! `dr_module_next_wakeup` after each of these (`wake.rs`).

use crate::build::Entry;
use crate::describe::Describer;
use crate::event::Event;
use crate::ffi::{self, Installed};
use crate::packet::Packet;
use crate::state::State;
use std::cell::RefCell;
use std::ffi::c_void;
use std::rc::Rc;

/// The state after the run and the address each module's runtime found.
pub struct Finished {
    pub state: State,
    pub addresses: Vec<u8>,
}

struct Contexts {
    entry: Entry,
    /// Every module's context, one after the other in one buffer (no allocation per module),
    /// in u64 words, so that every context is aligned for the runtime's pointers and integers.
    words: Vec<u64>,
    /// Words per context.
    stride: usize,
    modules: usize,
}

impl Contexts {
    fn new(entry: Entry, n: usize) -> Contexts {
        let stride = entry.module_size.div_ceil(8).max(1);
        Contexts {
            entry,
            words: vec![0u64; n * stride],
            stride,
            modules: n,
        }
    }

    fn ptr(&mut self, m: usize) -> Option<*mut c_void> {
        self.words
            .get_mut(m * self.stride..(m + 1) * self.stride)
            .map(|b| b.as_mut_ptr().cast::<c_void>())
    }

    fn init(&mut self, m: usize) {
        if let Some(ctx) = self.ptr(m) {
            // SAFETY: ctx is this module's buffer of at least dr_sim_module_size() bytes,
            // zeroed or left by an earlier init, as dr_module_init requires.
            unsafe { (self.entry.init)(ctx, ffi::platform(m)) }
        }
    }

    /// A step, and then `dr_module_finished`'s answer (`stops.rs`: the end, a stop, neither).
    fn step(&mut self, m: usize) -> u8 {
        let Some(ctx) = self.ptr(m) else {
            return 0;
        };
        // SAFETY: an initialised context (steps are scheduled only after power-on).
        unsafe {
            (self.entry.step)(ctx);
            (self.entry.finished)(ctx)
        }
    }

    /// `dr_module_next_wakeup`: the answer bits and the instant in the module's clock.
    fn next_wakeup(&mut self, m: usize) -> (u8, u32) {
        let Some(ctx) = self.ptr(m) else {
            return (0, 0);
        };
        let mut at_ms = 0u32;
        // SAFETY: an initialised context (asked only after its init); writes one u32.
        let answer = unsafe { (self.entry.next_wakeup)(ctx, &mut at_ms) };
        (answer, at_ms)
    }

    /// Whether the module knows the end (not a stop: `dr_module_finished` is `DR_END_GOAL`).
    fn finished(&mut self, m: usize) -> bool {
        let Some(ctx) = self.ptr(m) else {
            return false;
        };
        // SAFETY: an initialised context; reads it only.
        unsafe { (self.entry.finished)(ctx) == crate::stops::END_GOAL }
    }

    fn receive(&mut self, packet: &Packet) {
        let Some(ctx) = self.ptr(packet.to().module) else {
            return;
        };
        let len = u8::try_from(packet.bytes.len()).unwrap_or(u8::MAX);
        // SAFETY: an initialised context and `len` readable bytes.
        unsafe { (self.entry.receive)(ctx, packet.to().connector, packet.bytes.as_ptr(), len) }
    }

    /// `frame` as robot `robot` sends it in execution `execution` (the scenario's second
    /// robot, or another launch of this one); `None` when it is not a frame.
    fn restamp(&self, frame: &[u8], robot: u16, execution: u32) -> Option<Vec<u8>> {
        let len = u8::try_from(frame.len()).ok()?;
        let mut out = vec![0u8; usize::from(u8::MAX)];
        // SAFETY: `len` readable bytes in, `out` has room for the 255 bytes it may write.
        let written = unsafe {
            (self.entry.restamp)(
                frame.as_ptr(),
                len,
                robot,
                execution,
                out.as_mut_ptr(),
                u8::MAX,
            )
        };
        out.truncate(usize::from(written));
        (written > 0).then_some(out)
    }

    /// What reads the modules' protocol state for the trace; valid while `self` lives.
    fn describer(&mut self) -> Describer {
        let n = self.modules;
        let contexts = (0..n).filter_map(|m| self.ptr(m)).collect();
        Describer::new(self.entry.describe, contexts, n)
    }

    fn address(&mut self, m: usize) -> u8 {
        match self.ptr(m) {
            // SAFETY: reads one field of a context (zero if the module never started).
            Some(ctx) => unsafe { (self.entry.address)(ctx) },
            None => 0xFF,
        }
    }
}

/// Runs until every module has declared the end, or the scenario's timeout.
pub fn run(entry: Entry, state: State) -> Result<Finished, String> {
    let n = state.n_modules();
    let timeout = state.scenario.timeout_ms * 1000;
    let mut contexts = Contexts::new(entry, n);
    let mut state = state;
    if state.tracing() {
        state.describer = Some(contexts.describer());
    }
    let state = Rc::new(RefCell::new(state));
    let installed = Installed::new(&state);
    loop {
        let event = state.borrow_mut().pop(timeout);
        let Some(event) = event else {
            break;
        };
        dispatch(&state, &mut contexts, event);
        if installed.faulted() {
            state.borrow_mut().describer = None;
            return Err("a HAL callback failed (a bug in the simulator)".into());
        }
        if state.borrow().all_finished() {
            break;
        }
    }
    let addresses = (0..n).map(|m| contexts.address(m)).collect();
    drop(installed);
    state.borrow_mut().describer = None;
    let mut state = Rc::try_unwrap(state)
        .map_err(|_| "the simulation state is still shared".to_string())?
        .into_inner();
    if !state.all_finished() {
        state.now = timeout;
        state.log(None, dynarole_recording::TraceEvent::Timeout, "");
    }
    Ok(Finished { state, addresses })
}

/// Runs module `m`'s init (power-on, reset) and notes it for the trace's state column.
fn init(state: &Rc<RefCell<State>>, contexts: &mut Contexts, m: usize) {
    contexts.init(m);
    state.borrow_mut().forget_stop(m);
    if let Some(d) = state.borrow_mut().describer.as_mut() {
        d.initialised(m);
    }
}

/// Tickless: plans module `m`'s next step from its runtime's answer (after its init, a step
/// or a packet; a module off is not planned).
fn replan(state: &Rc<RefCell<State>>, contexts: &mut Contexts, m: usize) {
    if !state.borrow().tickless() || !state.borrow().modules[m].powered {
        return;
    }
    let (answer, at_ms) = contexts.next_wakeup(m);
    state.borrow_mut().plan_wake(m, answer, at_ms);
}

/// Tickless, after module `m` received a packet: its plan, and a step at its next instant
/// when the packet told it the end (the fixed stepping notes the end after a step).
fn after_packet(state: &Rc<RefCell<State>>, contexts: &mut Contexts, m: usize) {
    if !state.borrow().tickless() {
        return;
    }
    replan(state, contexts, m);
    let noted = state.borrow().modules[m].finished_at.is_some();
    if !noted && contexts.finished(m) {
        state.borrow_mut().wake_soon(m);
    }
}

/// Tickless: operation statuses may have changed; modules waiting for theirs are woken.
fn after_operations(state: &Rc<RefCell<State>>) {
    let mut s = state.borrow_mut();
    if s.tickless() {
        s.wake_op_waiters();
    }
}

fn dispatch(state: &Rc<RefCell<State>>, contexts: &mut Contexts, event: Event) {
    match event {
        Event::PowerOn { module } => {
            if state.borrow_mut().power_on(module) {
                init(state, contexts, module);
            }
        }
        Event::PowerOff { module } => {
            state.borrow_mut().power_off(module);
            after_operations(state);
        }
        Event::Step { module, generation } => {
            let module = module as usize;
            if !state.borrow_mut().step_due(module, generation) {
                state.borrow_mut().uncount();
                return;
            }
            let end = contexts.step(module);
            state.borrow_mut().note_end(module, end);
            if state.borrow().tickless() {
                replan(state, contexts, module);
            } else {
                state.borrow_mut().schedule_step(module);
            }
        }
        Event::OpDone { attempt } => {
            state.borrow_mut().op_done(attempt);
            after_operations(state);
        }
        Event::Clash { entry } => state.borrow_mut().clash(entry),
        Event::Arrival(arrivals) => {
            let packet = state.borrow_mut().next_arrival(arrivals);
            if state.borrow_mut().arrive(&packet) {
                contexts.receive(&packet);
                after_packet(state, contexts, packet.to().module);
            }
        }
        Event::Reset { module } => {
            if state.borrow_mut().reset(module) {
                init(state, contexts, module);
                replan(state, contexts, module);
            }
        }
        Event::Foreign { entry } => {
            let packet = state.borrow_mut().foreign_packet(entry);
            if let Some((to, frame, robot, execution)) = packet {
                if let Some(bytes) = contexts.restamp(&frame, robot, execution) {
                    let packet = Packet::new(0, to, to, (0, 0), bytes.into());
                    if state.borrow().modules[to.module].powered {
                        contexts.receive(&packet);
                        after_packet(state, contexts, to.module);
                    }
                }
            }
        }
        Event::ResetCheck { module } => {
            if state.borrow_mut().reset_check(module) {
                init(state, contexts, module);
                replan(state, contexts, module);
            }
        }
    }
}
