//! The trace's state column: each module's protocol state as text, read from its context
//! buffer through the runtime's `dr_sim_describe` (below both the engine, which owns the
//! buffers, and the state, which writes the trace).

use crate::build::DescribeFn;
use std::ffi::c_void;

/// Reads each module's protocol state as text (`dr_sim_describe`) for the trace's state
/// column. It holds pointers into the engine's context buffers: the engine installs it in
/// the state for the run and removes it before the buffers go.
pub struct Describer {
    describe: DescribeFn,
    contexts: Vec<*mut c_void>,
    /// Whether the module's runtime has been initialised (a context before that is zeros).
    initialised: Vec<bool>,
}

/// Longest description kept (the runtimes' are about 20 characters).
pub const DESCRIPTION_BYTES: usize = 64;

impl Describer {
    /// Reads the `contexts` of `n` modules with `describe`, none initialised yet.
    pub(crate) fn new(describe: DescribeFn, contexts: Vec<*mut c_void>, n: usize) -> Describer {
        Describer {
            describe,
            contexts,
            initialised: vec![false; n],
        }
    }

    /// Module `m`'s protocol state, or `-` before its first init.
    pub fn describe(&self, m: usize, out: &mut [u8; DESCRIPTION_BYTES]) -> usize {
        let (Some(ctx), Some(true)) = (self.contexts.get(m), self.initialised.get(m)) else {
            out[0] = b'-';
            return 1;
        };
        let cap = u8::try_from(out.len()).unwrap_or(u8::MAX);
        // SAFETY: `ctx` is module m's live, initialised context (the engine removes the
        // describer before freeing the buffers); dr_module_describe only reads it and writes
        // at most `cap` bytes into `out`. A call from inside a HAL callback reads the context
        // of a module whose step is suspended in that callback: same thread, no data race.
        let len = unsafe { (self.describe)(*ctx, out.as_mut_ptr(), cap) };
        usize::from(len).min(out.len())
    }

    /// Module `m` has run its init: its context now means something.
    pub(crate) fn initialised(&mut self, m: usize) {
        if let Some(flag) = self.initialised.get_mut(m) {
            *flag = true;
        }
    }
}
