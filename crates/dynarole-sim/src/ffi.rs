//! The HAL callbacks the C side calls (`struct dr_sim_callbacks` of `runtime/sim/dr_sim.c`).
//!
//! The running simulation's state is reached through a thread-local set for the duration of
//! a run ([`Installed`]); `platform` is the module's index plus one. No panic crosses the
//! boundary: each callback runs under `catch_unwind`, answers a neutral value when anything
//! goes wrong, and flags it so the engine stops the run with an error.

use crate::ops::OpCall;
use crate::state::State;
use std::cell::{Cell, RefCell};
use std::ffi::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::rc::Rc;

/// Mirrors `struct dr_sim_callbacks` field by field.
#[repr(C)]
pub struct Callbacks {
    now_ms: extern "C" fn(*mut c_void) -> u32,
    random: extern "C" fn(*mut c_void) -> u16,
    broadcast: extern "C" fn(*mut c_void, *const u8, u8),
    op_start: extern "C" fn(*mut c_void, u8, u16, u8, u8, *const i16, u8),
    op_status: extern "C" fn(*mut c_void) -> u8,
    id: extern "C" fn(*mut c_void) -> u16,
    connected: extern "C" fn(*mut c_void, u8) -> u8,
    neighbour_id: extern "C" fn(*mut c_void, u8) -> i16,
    joint: extern "C" fn(*mut c_void, u8) -> i16,
    leds: extern "C" fn(*mut c_void, u8),
    nv_read: extern "C" fn(*mut c_void, u16, *mut u8, u8),
    nv_write: extern "C" fn(*mut c_void, u16, *const u8, u8),
    send: extern "C" fn(*mut c_void, u8, *const u8, u8),
}

pub static CALLBACKS: Callbacks = Callbacks {
    now_ms,
    random,
    broadcast,
    op_start,
    op_status,
    id,
    connected,
    neighbour_id,
    joint,
    leds,
    nv_read,
    nv_write,
    send,
};

thread_local! {
    static CURRENT: RefCell<Option<Rc<RefCell<State>>>> = const { RefCell::new(None) };
    static FAULT: Cell<bool> = const { Cell::new(false) };
}

/// While alive, callbacks on this thread act on `state`.
pub struct Installed;

impl Installed {
    pub fn new(state: &Rc<RefCell<State>>) -> Installed {
        CURRENT.with(|c| *c.borrow_mut() = Some(Rc::clone(state)));
        FAULT.with(|f| f.set(false));
        Installed
    }

    /// Whether a callback failed (panicked, or found the state busy) since installation.
    pub fn faulted(&self) -> bool {
        FAULT.with(Cell::get)
    }
}

impl Drop for Installed {
    fn drop(&mut self) {
        CURRENT.with(|c| *c.borrow_mut() = None);
    }
}

/// Platform value for module `index` (never null).
pub fn platform(index: usize) -> *mut c_void {
    (index + 1) as *mut c_void
}

fn with_state<R>(platform: *mut c_void, default: R, f: impl FnOnce(&mut State, usize) -> R) -> R {
    let module = (platform as usize).wrapping_sub(1);
    let result = catch_unwind(AssertUnwindSafe(|| {
        CURRENT.with(|c| {
            let current = c.try_borrow().ok()?;
            let mut state = current.as_ref()?.try_borrow_mut().ok()?;
            if module >= state.n_modules() {
                return None;
            }
            Some(f(&mut state, module))
        })
    }));
    match result {
        Ok(Some(r)) => r,
        _ => {
            let _ = catch_unwind(|| FAULT.with(|f| f.set(true)));
            default
        }
    }
}

/// # Safety of the slices below: the C side passes `len` valid bytes (or `n` arguments).
fn bytes<'a>(ptr: *const u8, len: u8) -> &'a [u8] {
    if ptr.is_null() {
        return &[];
    }
    // SAFETY: dr_sim.c passes a buffer of `len` bytes valid for the call.
    unsafe { std::slice::from_raw_parts(ptr, usize::from(len)) }
}

extern "C" fn now_ms(p: *mut c_void) -> u32 {
    with_state(p, 0, |s, m| s.now_ms(m))
}

extern "C" fn random(p: *mut c_void) -> u16 {
    with_state(p, 0, |s, _| s.random())
}

extern "C" fn broadcast(p: *mut c_void, data: *const u8, len: u8) {
    let data = bytes(data, len);
    with_state(p, (), |s, m| s.broadcast(m, data));
}

extern "C" fn send(p: *mut c_void, channel: u8, data: *const u8, len: u8) {
    let data = bytes(data, len);
    with_state(p, (), |s, m| s.send_on(m, channel, data));
}

extern "C" fn op_start(
    p: *mut c_void,
    address: u8,
    statement: u16,
    op: u8,
    index: u8,
    args: *const i16,
    n: u8,
) {
    let args: &[i16] = if args.is_null() {
        &[]
    } else {
        // SAFETY: dr_sim.c passes the statement's DR_CONF_MAX_ARGS arguments.
        unsafe { std::slice::from_raw_parts(args, usize::from(n)) }
    };
    let call = OpCall {
        address,
        statement,
        op,
        index,
        args,
    };
    with_state(p, (), |s, m| s.op_start(m, &call));
}

extern "C" fn op_status(p: *mut c_void) -> u8 {
    with_state(p, 2, |s, m| s.op_status(m))
}

extern "C" fn id(p: *mut c_void) -> u16 {
    with_state(p, 0, |s, m| s.id(m))
}

extern "C" fn connected(p: *mut c_void, connector: u8) -> u8 {
    with_state(p, 0, |s, m| s.connected(m, connector))
}

extern "C" fn neighbour_id(p: *mut c_void, connector: u8) -> i16 {
    with_state(p, -1, |s, m| s.neighbour_id(m, connector))
}

extern "C" fn joint(p: *mut c_void, joint: u8) -> i16 {
    with_state(p, 0, |s, m| s.joint(m, joint))
}

extern "C" fn leds(p: *mut c_void, value: u8) {
    with_state(p, (), |s, m| s.leds(m, value));
}

extern "C" fn nv_read(p: *mut c_void, addr: u16, buf: *mut u8, len: u8) {
    if buf.is_null() {
        return;
    }
    // SAFETY: dr_sim.c passes a writable buffer of `len` bytes.
    let out = unsafe { std::slice::from_raw_parts_mut(buf, usize::from(len)) };
    out.fill(0xFF);
    with_state(p, (), |s, m| s.nv_read(m, addr, out));
}

extern "C" fn nv_write(p: *mut c_void, addr: u16, data: *const u8, len: u8) {
    let data = bytes(data, len);
    with_state(p, (), |s, m| s.nv_write(m, addr, data));
}
