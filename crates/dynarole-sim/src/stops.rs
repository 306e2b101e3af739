//! Modules stopped by their failure policy: noted when a module's runtime says so
//! (`DR_END_STOPPED` from `dr_module_finished`), with the statements whose failure stopped it,
//! and forgotten at its next init (a reset gives the module its retries again).

use crate::report::Stop;
use crate::state::State;

/// `dr_module_finished`'s answers (runtime/dr_module.h).
pub const END_GOAL: u8 = 1;
pub const END_STOPPED: u8 = 2;

impl State {
    /// What module `m`'s runtime answered after a step or a packet: the end, a stop, or
    /// neither.
    pub fn note_end(&mut self, m: usize, answer: u8) {
        match answer {
            END_GOAL => self.note_finished(m, true),
            END_STOPPED => self.note_stopped(m),
            _ => {}
        }
    }

    /// Module `m` stopped: the statements it waited for that failed, once per stop.
    fn note_stopped(&mut self, m: usize) {
        if self.stopped.contains_key(&m) {
            return;
        }
        let waiting = self.waiting.get(&m).map_or(&[][..], Vec::as_slice);
        let statements: Vec<usize> = waiting
            .iter()
            .copied()
            .filter(|s| self.phys[*s].done.is_none())
            .collect();
        let texts: Vec<&str> = statements.iter().map(|s| self.seq.text(*s)).collect();
        let stop = Stop {
            time_ms: self.now as f64 / 1000.0,
            module: self.view().name(m),
            statements,
            text: texts.join("; "),
        };
        if self.tracing() {
            let detail = format!("failure policy gave up: {}", stop.text);
            self.log(Some(m), dynarole_recording::TraceEvent::Stopped, detail);
        }
        self.stopped.insert(m, stop);
    }

    /// Module `m` was (re)initialised: it is no longer stopped.
    pub fn forget_stop(&mut self, m: usize) {
        self.stopped.remove(&m);
    }

    /// The modules stopped now, in module order.
    pub fn stops(&mut self) -> Vec<Stop> {
        std::mem::take(&mut self.stopped).into_values().collect()
    }
}
