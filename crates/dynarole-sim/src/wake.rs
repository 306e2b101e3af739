//! Tickless stepping: when a module's C runs next, from its `dr_module_next_wakeup` answer,
//! a packet that made a step useful, or its operation's completion. Every wake-up is one of
//! the module's 5 ms instants (power-on plus a multiple of 5 ms), the one at which the fixed
//! stepping would have acted, so both give the same run (`docs/simulator.md`, "Stepping").

use crate::ops::RUNNING;
use crate::state::{State, STEP_US};

/// `DR_WAKE_AT` of `runtime/dr_module.h`: at the first instant whose clock reaches `at_ms`.
pub const WAKE_AT: u8 = 0x01;
/// `DR_WAKE_OP`: at the first instant at which the operation status is not RUNNING.
pub const WAKE_OP: u8 = 0x02;
/// The step period in the modules' clock (ms): at their instants it reads a multiple of it.
const STEP_MS: u32 = (STEP_US / 1000) as u32;

impl State {
    /// Module `m`'s first 5 ms instant whose step comes after the event being dispatched.
    fn next_instant(&self, m: usize) -> u64 {
        let on = self.modules[m].power_on_at;
        let since = self.now.saturating_sub(on);
        let at = on + since.div_ceil(STEP_US) * STEP_US;
        if self.step_key(m, at) <= self.current() {
            at + STEP_US
        } else {
            at
        }
    }

    /// A step of `m` at its instant `at`, unless an earlier one is already queued (a step
    /// that is not needed changes nothing: the `dr_module_next_wakeup` contract).
    fn wake_at_instant(&mut self, m: usize, at: u64) {
        if self.modules[m].next_step.is_some_and(|queued| queued <= at) {
            return;
        }
        self.put_step(m, at);
    }

    /// A step of `m` at its next instant (a packet made it finished, its operation ended).
    pub fn wake_soon(&mut self, m: usize) {
        if self.modules[m].powered {
            let at = self.next_instant(m);
            self.wake_at_instant(m, at);
        }
    }

    /// Follows module `m`'s `dr_module_next_wakeup` answer (`answer` bits, `at_ms` in its
    /// clock), given after its init, a step or a packet.
    pub fn plan_wake(&mut self, m: usize, answer: u8, at_ms: u32) {
        if !self.modules[m].powered {
            return;
        }
        let soon = self.next_instant(m);
        let mut wake = None;
        if answer & WAKE_OP != 0 && self.op_status(m) != RUNNING {
            wake = Some(soon);
        }
        if answer & WAKE_OP != 0 && wake.is_none() {
            self.op_waiters.insert(m);
        } else {
            self.op_waiters.remove(&m);
        }
        if answer & WAKE_AT != 0 {
            // The module's clock reads an exact multiple of STEP_MS at its instants, so the
            // fixed stepping first sees `at_ms` reached at the first instant at or after it.
            let clock = self.clock_at(m, soon);
            let ahead = at_ms.wrapping_sub(clock) as i32;
            let at = match u64::try_from(ahead) {
                Ok(ms) if ms > 0 => soon + ms.div_ceil(u64::from(STEP_MS)) * STEP_US,
                _ => soon,
            };
            wake = Some(wake.map_or(at, |w: u64| w.min(at)));
        }
        if let Some(at) = wake {
            self.wake_at_instant(m, at);
        }
    }

    /// Operation statuses may have changed (a completion, a refusal, a power-off): every
    /// module waiting for its status to leave RUNNING and seeing it do so is woken.
    pub fn wake_op_waiters(&mut self) {
        let ended: Vec<usize> = self
            .op_waiters
            .iter()
            .copied()
            .filter(|&m| self.op_status(m) != RUNNING)
            .collect();
        for m in ended {
            self.op_waiters.remove(&m);
            self.wake_soon(m);
        }
    }

    /// What `dr_hal_now_ms` answers module `m` at `time`.
    pub(crate) fn clock_at(&self, m: usize, time: u64) -> u32 {
        let since = time.saturating_sub(self.modules[m].power_on_at) / 1000;
        (since & u64::from(u32::MAX)) as u32
    }
}
