//! The event loop: pops events in (time, sequence) order and runs the generated C where an
//! event concerns a module (power-on and resets run its init, steps its step, arrivals its
//! receive). Every module has its own zeroed context buffer.

use crate::build::Entry;
use crate::ffi::{self, Installed};
use crate::state::{Event, Packet, State};
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
    /// u64 words, so that every context is aligned for the runtime's pointers and integers.
    buffers: Vec<Vec<u64>>,
}

impl Contexts {
    fn new(entry: Entry, n: usize) -> Contexts {
        let words = entry.module_size.div_ceil(8).max(1);
        Contexts {
            entry,
            buffers: vec![vec![0u64; words]; n],
        }
    }

    fn ptr(&mut self, m: usize) -> Option<*mut c_void> {
        self.buffers
            .get_mut(m)
            .map(|b| b.as_mut_ptr().cast::<c_void>())
    }

    fn init(&mut self, m: usize) {
        if let Some(ctx) = self.ptr(m) {
            // SAFETY: ctx is this module's buffer of at least dr_sim_module_size() bytes,
            // zeroed or left by an earlier init, as dr_module_init requires.
            unsafe { (self.entry.init)(ctx, ffi::platform(m)) }
        }
    }

    fn step(&mut self, m: usize) -> bool {
        let Some(ctx) = self.ptr(m) else {
            return false;
        };
        // SAFETY: an initialised context (steps are scheduled only after power-on).
        unsafe {
            (self.entry.step)(ctx);
            (self.entry.finished)(ctx) != 0
        }
    }

    fn receive(&mut self, packet: &Packet) {
        let Some(ctx) = self.ptr(packet.to.module) else {
            return;
        };
        let len = u8::try_from(packet.bytes.len()).unwrap_or(u8::MAX);
        // SAFETY: an initialised context and `len` readable bytes.
        unsafe { (self.entry.receive)(ctx, packet.to.connector, packet.bytes.as_ptr(), len) }
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
    let state = Rc::new(RefCell::new(state));
    let installed = Installed::new(&state);
    let mut contexts = Contexts::new(entry, n);
    loop {
        let event = state.borrow_mut().pop(timeout);
        let Some(event) = event else {
            break;
        };
        dispatch(&state, &mut contexts, event);
        if installed.faulted() {
            return Err("a HAL callback failed (a bug in the simulator)".into());
        }
        if state.borrow().all_finished() {
            break;
        }
    }
    let addresses = (0..n).map(|m| contexts.address(m)).collect();
    drop(installed);
    let mut state = Rc::try_unwrap(state)
        .map_err(|_| "the simulation state is still shared".to_string())?
        .into_inner();
    if !state.all_finished() {
        state.now = timeout;
        state.log(None, "timeout", "");
    }
    Ok(Finished { state, addresses })
}

fn dispatch(state: &Rc<RefCell<State>>, contexts: &mut Contexts, event: Event) {
    match event {
        Event::PowerOn { module } => {
            if state.borrow_mut().power_on(module) {
                contexts.init(module);
            }
        }
        Event::PowerOff { module } => state.borrow_mut().power_off(module),
        Event::Step { module, generation } => {
            if !state.borrow().step_due(module, generation) {
                return;
            }
            let finished = contexts.step(module);
            let mut s = state.borrow_mut();
            s.note_finished(module, finished);
            s.schedule_step(module, generation);
        }
        Event::OpDone { attempt } => state.borrow_mut().op_done(attempt),
        Event::Arrival(packet) => {
            if state.borrow_mut().arrive(&packet) {
                contexts.receive(&packet);
            }
        }
        Event::Reset { module } => {
            if state.borrow_mut().reset(module) {
                contexts.init(module);
            }
        }
        Event::ResetCheck { module } => {
            if state.borrow_mut().reset_check(module) {
                contexts.init(module);
            }
        }
    }
}
