//! The trace's state column: each module's protocol state as text, read from its context
//! buffer through the runtime's `dr_sim_describe`, or as the text a module's firmware
//! reported (below both the engine, which owns the buffers, and the state, which writes the
//! trace).

use std::ffi::c_void;

/// `dr_sim_describe(m, out, cap)`: the compiled program's entry point that writes a module's
/// protocol state (`build.rs` loads it).
pub type DescribeFn = unsafe extern "C" fn(*mut c_void, *mut u8, u8) -> u8;

/// Reads each module's protocol state as text for the trace's state column. With contexts,
/// it holds pointers into the engine's context buffers: the engine installs it in the state
/// for the run and removes it before the buffers go. Under `--firmware`, it holds the texts
/// the modules' firmware last reported instead ([`Describer::texts`]).
pub struct Describer {
    source: Source,
    /// Whether the module's runtime has been initialised (a context before that is zeros).
    initialised: Vec<bool>,
}

enum Source {
    Contexts {
        describe: DescribeFn,
        contexts: Vec<*mut c_void>,
    },
    Texts(Vec<Vec<u8>>),
}

/// Longest description kept (the runtimes' are about 20 characters).
pub const DESCRIPTION_BYTES: usize = 64;

impl Describer {
    /// Reads the `contexts` of `n` modules with `describe`, none initialised yet.
    pub(crate) fn new(describe: DescribeFn, contexts: Vec<*mut c_void>, n: usize) -> Describer {
        Describer {
            source: Source::Contexts { describe, contexts },
            initialised: vec![false; n],
        }
    }

    /// For `n` modules whose state comes as text ([`Describer::set_text`]), `-` until then.
    pub fn texts(n: usize) -> Describer {
        Describer {
            source: Source::Texts(vec![Vec::new(); n]),
            initialised: vec![false; n],
        }
    }

    /// Module `m`'s state is now `text` (its runtime's own description; cut to the length
    /// kept).
    pub fn set_text(&mut self, m: usize, text: &[u8]) {
        if let Source::Texts(texts) = &mut self.source {
            if let Some(t) = texts.get_mut(m) {
                t.clear();
                t.extend_from_slice(&text[..text.len().min(DESCRIPTION_BYTES - 1)]);
                self.initialised(m);
            }
        }
    }

    /// Module `m`'s protocol state, or `-` before its first init.
    pub fn describe(&self, m: usize, out: &mut [u8; DESCRIPTION_BYTES]) -> usize {
        if self.initialised.get(m) != Some(&true) {
            out[0] = b'-';
            return 1;
        }
        match &self.source {
            Source::Texts(texts) => {
                let text = texts.get(m).map_or(&[][..], Vec::as_slice);
                out[..text.len()].copy_from_slice(text);
                text.len()
            }
            Source::Contexts { describe, contexts } => {
                let Some(ctx) = contexts.get(m) else {
                    out[0] = b'-';
                    return 1;
                };
                let cap = u8::try_from(out.len()).unwrap_or(u8::MAX);
                // SAFETY: `ctx` is module m's live, initialised context (the engine removes
                // the describer before freeing the buffers); dr_module_describe only reads
                // it and writes at most `cap` bytes into `out`. A call from inside a HAL
                // callback reads the context of a module whose step is suspended in that
                // callback: same thread, no data race.
                let len = unsafe { (*describe)(*ctx, out.as_mut_ptr(), cap) };
                usize::from(len).min(out.len())
            }
        }
    }

    /// Module `m` has run its init: its context now means something.
    pub(crate) fn initialised(&mut self, m: usize) {
        if let Some(flag) = self.initialised.get_mut(m) {
            *flag = true;
        }
    }
}
