//! Robot operations: how a module's `dr_hal_op_start` of a statement relates to what already
//! happened to it, how long it takes, what the world says when it completes, and the checks
//! S1, S2 and S3. The scenario's operation faults are in `ops/faults.rs`.

mod faults;

use crate::event::Event;
use crate::report::{Refusal, Violation};
use crate::sequence::OpKind;
use crate::state::{uniform, Attempt, Clash, State};
use dynarole_core::check::ResolvedStatement;
use dynarole_core::synchronous::lockstep_ms;
use dynarole_recording::TraceEvent;
use dynarole_replay::{Along, Pairs};
use dynarole_world::{Action, SweepCheck};

/// How a call of `dr_hal_op_start` relates to what already happened to its statement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Call {
    /// Its operation is in progress (a module re-entering it after a reset): wait for it.
    Resume(usize),
    /// It was started and failed: a new attempt.
    Retry(usize),
    /// The first start.
    First(usize),
    /// It was done already: done again physically (the world decides what that does).
    Reissue(usize),
}

/// One call of `dr_hal_op_start`: the statement the module's runtime says it runs (never
/// guessed from the operation: sequences repeat operations, a reverse repeats every one) and
/// the operation it asks the hardware for.
pub struct OpCall<'a> {
    /// The address the module's runtime has (its role).
    pub address: u8,
    pub statement: u16,
    pub op: u8,
    pub index: u8,
    /// The arguments, padded with zeros to `DR_CONF_MAX_ARGS`.
    pub args: &'a [i16],
}

const DONE: u8 = 1;
pub const RUNNING: u8 = 0;
const FAILED: u8 = 2;

impl State {
    /// `dr_hal_op_start` of module `m`.
    pub fn op_start(&mut self, m: usize, request: &OpCall) {
        if !self.modules[m].powered {
            return;
        }
        let Some(call) = self.classify(request) else {
            self.counters.ops_unknown += 1;
            self.clear_finished_waits(m);
            self.modules[m].failed = true;
            if self.tracing() {
                let OpCall {
                    address,
                    statement,
                    op,
                    index,
                    args,
                } = request;
                let detail = format!(
                    "statement {statement} is not address {address} op {op} index {index} args {args:?}"
                );
                self.log(Some(m), TraceEvent::UnknownOp, detail);
            }
            return;
        };
        self.clear_finished_waits(m);
        let s = match call {
            Call::Resume(s) | Call::Retry(s) | Call::First(s) | Call::Reissue(s) => s,
        };
        let waiting = self.waiting.entry(m).or_default();
        if !waiting.contains(&s) {
            waiting.push(s);
        }
        let label = self.trace_label(s);
        match call {
            Call::First(s) => {
                self.check_dependencies(m, s);
                self.phys[s].started = Some(self.now);
                self.log(Some(m), TraceEvent::Start, label);
            }
            Call::Resume(_) => self.log(Some(m), TraceEvent::Resume, label),
            Call::Retry(_) => self.log(Some(m), TraceEvent::Retry, label),
            Call::Reissue(_) => {
                self.counters.ops_reissued += 1;
                self.log(Some(m), TraceEvent::Reissue, label);
            }
        }
        if call != Call::First(s) {
            self.check_not_overtaken(m, s);
        }
        if !matches!(call, Call::Resume(_)) {
            self.begin_attempt(m, s);
        }
    }

    /// `dr_hal_op_status`: running while any operation the module waits for runs.
    pub fn op_status(&self, m: usize) -> u8 {
        let waiting = self.waiting.get(&m).map_or(&[][..], Vec::as_slice);
        if waiting.iter().any(|s| self.phys[*s].running.is_some()) {
            RUNNING
        } else if self.modules[m].failed {
            FAILED
        } else {
            DONE
        }
    }

    /// What the named statement's history makes this call; `None` when the statement does not
    /// exist or is not the operation the module asked for (generated code and IR disagree).
    fn classify(&self, request: &OpCall) -> Option<Call> {
        let s = usize::from(request.statement);
        let matches = self
            .seq
            .matches(s, request.address, request.op, request.index, request.args);
        let phys = self.phys.get(s).filter(|_| matches)?;
        Some(if phys.running.is_some() {
            Call::Resume(s)
        } else if phys.started.is_none() {
            Call::First(s)
        } else if phys.done.is_none() {
            Call::Retry(s)
        } else {
            Call::Reissue(s)
        })
    }

    /// A new batch of operations starts once every earlier one has finished.
    fn clear_finished_waits(&mut self, m: usize) {
        let phys = &self.phys;
        let waiting = self.waiting.get(&m).map_or(&[][..], Vec::as_slice);
        if waiting.iter().all(|s| phys[*s].running.is_none()) {
            self.waiting.remove(&m);
            self.modules[m].failed = false;
        }
    }

    /// S1: every dependency of `s` is physically done.
    fn check_dependencies(&mut self, m: usize, s: usize) {
        let missing: Vec<usize> = self.seq.ir.statements[s]
            .deps
            .iter()
            .map(|d| usize::from(*d))
            .filter(|d| self.phys.get(*d).is_some_and(|p| p.done.is_none()))
            .collect();
        if !missing.is_empty() {
            self.violation(
                TraceEvent::S1,
                m,
                s,
                missing,
                "started before its dependencies were done",
            );
        }
    }

    /// S2: `s` is issued again only while nothing that depends on it has started.
    fn check_not_overtaken(&mut self, m: usize, s: usize) {
        let started: Vec<usize> = (self.seq.transitive_dependents(s).into_iter())
            .filter(|t| self.phys[*t].started.is_some())
            .collect();
        if !started.is_empty() {
            self.violation(
                TraceEvent::S2,
                m,
                s,
                started,
                "re-issued after a dependent statement started",
            );
        }
    }

    /// S3: module `m` declared the end; every operation must be done and none running.
    pub fn check_end(&mut self, m: usize) {
        let open: Vec<usize> = (0..self.seq.len())
            .filter(|s| self.phys[*s].done.is_none() || self.phys[*s].running.is_some())
            .collect();
        if let Some(first) = open.first().copied() {
            self.violation(
                TraceEvent::S3,
                m,
                first,
                open,
                "end declared before every operation was done",
            );
        }
    }

    /// A check (`S1`, `S2`, `S3`) failed: its trace line and the report's violation, both
    /// named by the check's event.
    fn violation(
        &mut self,
        check: TraceEvent,
        m: usize,
        s: usize,
        involved: Vec<usize>,
        what: &str,
    ) {
        if self.tracing() {
            let others: Vec<String> = involved.iter().map(|t| format!("#{t}")).collect();
            let detail = format!(
                "{}: {what} ({})",
                self.statement_label(s),
                others.join(", ")
            );
            self.log(Some(m), check, &detail);
        }
        self.violations.push(Violation {
            check: check.name().to_string(),
            time_ms: self.now as f64 / 1000.0,
            module: self.view().name(m),
            statement: s,
            text: self.seq.text(s).to_string(),
            involved,
            message: what.to_string(),
        });
    }

    fn begin_attempt(&mut self, m: usize, s: usize) {
        let id = self.next_id;
        self.next_id += 1;
        let fault = self.injected_fault(m, s);
        self.attempts.insert(
            id,
            Attempt {
                statement: s,
                module: m,
                fault,
            },
        );
        self.phys[s].running = Some(id);
        self.phys[s].failed = false;
        self.modules[m].stats.operations += 1;
        self.counters.ops_started += 1;
        // An attempt that fails moves nothing: it breaks no link and sweeps nothing.
        if self.seq.kinds[s].moves() && fault.is_none() {
            self.note_turn(id, m, s);
        }
        // Saturating: a plugin's absurd turn (a huge count of quarters) is never reached.
        let at = (self.now).saturating_add(self.duration_ms(m, s).saturating_mul(1000));
        self.schedule(at, Event::OpDone { attempt: id });
        if self.seq.kinds[s] == OpKind::Turn && at > self.now && fault.is_none() {
            self.spans.insert(id, (self.now, at));
            self.check_running_turns();
        }
    }

    /// The running turns changed (one started, ended or was cut short), or an operation
    /// completed while they run (a latch changes what they move): all of them
    /// together, with their fractions going linearly with time from now until the earliest of
    /// them ends (`dynarole_replay::first_contact`: each turn's motion on the world's
    /// configuration now, which holds every turn already done), are searched for the first
    /// instant two modules come within the limit, due as a clash. The search of the previous
    /// change is superseded: a turn that started since may move the modules it named. Turns
    /// the search does not compose (not one rotation each, not a tree) are not checked.
    pub(crate) fn check_running_turns(&mut self) {
        self.pending_clash = None;
        if self.spans.is_empty() {
            return;
        }
        let running: Vec<(u64, (u64, u64))> = self.spans.iter().map(|(k, v)| (*k, *v)).collect();
        let mut turns = Vec::new();
        for &(id, span) in &running {
            let Some(&Attempt {
                statement, module, ..
            }) = self.attempts.get(&id)
            else {
                continue;
            };
            let name = self.view().name(module);
            let resolved = &self.seq.resolved[statement];
            if let Some(motion) = self.world.motion(&self.seq.robot, resolved, &name) {
                turns.push((id, statement, module, span, motion));
            }
        }
        let Some(until) = turns.iter().map(|t| t.3 .1).min() else {
            return;
        };
        // A turn of a synchronous group is applied without its own sweep (`op_done`): its
        // sweep is searched here, with every pair of points, even while it runs alone.
        let lockstep = turns.iter().any(|t| self.seq.synchronous(t.1).is_some());
        if (turns.len() < 2 && !lockstep) || until <= self.now {
            return;
        }
        let pairs = if lockstep {
            Pairs::All
        } else {
            Pairs::MovedByTwo
        };
        let fraction = |t: u64, (a, b): (u64, u64)| (t - a) as f64 / (b - a) as f64;
        let from: Vec<f64> = turns.iter().map(|t| fraction(self.now, t.3)).collect();
        let to: Vec<f64> = turns.iter().map(|t| fraction(until, t.3)).collect();
        let group: Vec<(&dynarole_world::Motion, usize)> =
            turns.iter().map(|t| (&t.4, t.2)).collect();
        let Along::Contact(c) =
            dynarole_replay::first_contact(&group, (&from, &to), &self.world, pairs)
        else {
            return;
        };
        let at = self.now + ((until - self.now) as f64 * c.at).round() as u64;
        let entry = u32::try_from(self.clashes.len()).unwrap_or(u32::MAX);
        self.clashes.push(Clash {
            attempts: c.turns.iter().map(|&t| turns[t].0).collect(),
            statements: c.turns.iter().map(|&t| turns[t].1).collect(),
            modules: c.modules,
            limit: turns.iter().map(|t| t.4.limit).fold(0.0, f64::max),
        });
        self.pending_clash = Some(entry);
        self.schedule(at, Event::Clash { entry });
    }

    /// A clash found at the last change of the running turns is due: a violation on the
    /// latest started of the turns involved, if it is still the search in force and every one
    /// of them still runs, and not already reported for these turns and modules.
    pub fn clash(&mut self, entry: u32) {
        if self.pending_clash != Some(entry) {
            return;
        }
        let Some(clash) = usize::try_from(entry)
            .ok()
            .and_then(|e| self.clashes.get(e))
        else {
            return;
        };
        let all_running = (clash.attempts.iter().zip(&clash.statements))
            .all(|(&id, &s)| self.phys[s].running == Some(id));
        let key = (clash.attempts.clone(), clash.modules);
        if !all_running || self.clashes_reported.contains(&key) {
            return;
        }
        let (Some(&latest), Some(&s)) = (clash.attempts.last(), clash.statements.last()) else {
            return;
        };
        let Some(m) = self.attempts.get(&latest).map(|a| a.module) else {
            return;
        };
        let others: Vec<usize> = clash.statements[..clash.statements.len() - 1].to_vec();
        let named: Vec<String> = others.iter().map(|o| format!("#{o}")).collect();
        let with = match named.is_empty() {
            // A synchronous group's turn alone: its own sweep (`check_running_turns`).
            true => "running alone, ".to_string(),
            false => format!("running at once with {}, ", named.join(", ")),
        };
        let view = self.view();
        let what = format!(
            "{with}it brings {} and {} closer than the limit ({} {})",
            view.name(clash.modules.0),
            view.name(clash.modules.1),
            clash.limit,
            self.world.model().length_unit(),
        );
        self.clashes_reported.insert(key);
        self.violation(TraceEvent::Clash, m, s, others, &what);
    }

    /// The operation's nominal duration, varied at random when the scenario asks for it.
    fn duration_ms(&mut self, m: usize, s: usize) -> u64 {
        let nominal = self.nominal_ms(m, s);
        let variation = self.scenario.timing.variation;
        // A synchronous group's turns keep their pace: lock-step is the point of them.
        if variation <= 0.0 || self.seq.synchronous(s).is_some() {
            return nominal;
        }
        let factor = 1.0 - variation + 2.0 * variation * uniform(&mut self.rng_timing);
        (nominal as f64 * factor).round() as u64
    }

    fn nominal_ms(&self, m: usize, s: usize) -> u64 {
        let kind = self.seq.kinds[s];
        if let Some(group) = self.seq.synchronous(s) {
            if !self.already_there(m, s) {
                // Every turn of the group at the pace of its longest (lock-step).
                let members: Vec<&ResolvedStatement> =
                    group.map(|k| &self.seq.resolved[k]).collect();
                return lockstep_ms(&self.seq.robot, self.durations, &members);
            }
        }
        // A turn to the angle the joint already has (re-issued after it completed, or written
        // with a `from` that is not the joint's angle), or a move re-issued after it took
        // effect, moves nothing.
        if self.already_there(m, s) {
            return 0;
        }
        let quarters = match kind {
            OpKind::Turn => self.quarter_turns(m, s),
            _ => 0,
        };
        kind.nominal_ms(&self.durations, quarters)
    }

    /// Which modules move during a turn (the modules of its sweep's points), so that their
    /// links break while it lasts.
    fn note_turn(&mut self, id: u64, m: usize, s: usize) {
        let name = self.view().name(m);
        let Some(motion) = self
            .world
            .motion(&self.seq.robot, &self.seq.resolved[s], &name)
        else {
            self.turns.insert(id, (m, vec![false; self.modules.len()]));
            return;
        };
        let mut moving = vec![false; self.modules.len()];
        let view = self.view();
        for (module, _) in &motion.moving {
            if let Some(i) = view.index(module) {
                moving[i] = true;
            }
        }
        self.turns.insert(id, (m, moving));
    }

    /// An operation's time has come: the world applies it or refuses it.
    pub fn op_done(&mut self, id: u64) {
        let Some(Attempt {
            statement: s,
            module: m,
            fault,
        }) = self.attempts.remove(&id)
        else {
            return;
        };
        self.turns.remove(&id);
        let was_running_turn = self.spans.remove(&id).is_some();
        if self.phys[s].running != Some(id) {
            return;
        }
        self.phys[s].running = None;
        let label = self.trace_label(s);
        if let Some(fault) = fault {
            self.failed_by_fault(m, s, label, fault);
            return;
        }
        let name = self.view().name(m);
        // A synchronous group's turn is checked with the others while it runs, its own sweep
        // included (`check_running_turns`): alone it may pass where, in lock-step, it never is.
        let sweep = match self.seq.synchronous(s) {
            Some(_) => SweepCheck::WithOthers,
            None => SweepCheck::Alone,
        };
        if matches!(self.seq.kinds[s], OpKind::Move { .. }) && self.already_there(m, s) {
            // Re-issued after it took effect: applying it again would move the module again.
            self.completed(m, s, label, "already moved");
            return;
        }
        let applied =
            (self.world).apply_swept(&self.seq.robot, &self.seq.resolved[s], &name, sweep);
        // Links may have changed (latches, facing connectors).
        self.links.clear();
        if was_running_turn || self.spans.len() > 1 {
            // The running turns go on from the configuration with this operation done: a turn
            // in place, or a latch made or broken at this instant, which changes what the
            // turns still running move.
            self.check_running_turns();
        }
        match applied {
            Ok(outcome) => {
                let notes = if self.tracing() {
                    let notes: Vec<String> =
                        outcome.warnings.iter().map(ToString::to_string).collect();
                    notes.join("; ")
                } else {
                    String::new()
                };
                self.completed(m, s, label, &notes);
            }
            Err(_) if self.already_there(m, s) => {
                self.completed(m, s, label, "joint already there")
            }
            Err(reason) => self.refused(m, s, label, reason),
        }
    }

    fn completed(&mut self, m: usize, s: usize, label: String, note: &str) {
        self.phys[s].done.get_or_insert(self.now);
        if self.tracing() {
            let detail = if note.is_empty() {
                label
            } else {
                format!("{label} ({note})")
            };
            self.log(Some(m), TraceEvent::Done, detail);
        }
    }

    fn refused(&mut self, m: usize, s: usize, label: String, reason: String) {
        self.phys[s].failed = true;
        self.counters.ops_refused += 1;
        self.mark_failed(s);
        if self.tracing() {
            self.log(Some(m), TraceEvent::Refused, format!("{label}: {reason}"));
        }
        self.refusals.push(Refusal {
            time_ms: self.now as f64 / 1000.0,
            module: self.view().name(m),
            statement: s,
            text: self.seq.text(s).to_string(),
            reason,
        });
    }

    fn mark_failed(&mut self, s: usize) {
        for (m, waiting) in &self.waiting {
            if waiting.contains(&s) {
                if let Some(module) = self.modules.get_mut(*m) {
                    module.failed = true;
                }
            }
        }
    }

    /// A turn the world refuses because the joint is already at its target took effect
    /// already (operations are idempotent, dr_hal.h).
    fn already_there(&self, m: usize, s: usize) -> bool {
        match self.seq.kinds[s] {
            OpKind::Turn => {}
            // A move cannot be told from where the module is (the same move may be made
            // again from there): it took effect once its statement completed.
            OpKind::Move { .. } => return self.phys[s].done.is_some(),
            _ => return false,
        }
        let Some(Action::Turn { joint, to, .. }) = self.seq.actions[s] else {
            return false;
        };
        self.view().joint(m, joint) == Some(to)
    }

    /// Quarter turns statement `s`'s turn makes from module `m`'s joint angle now.
    fn quarter_turns(&self, m: usize, s: usize) -> u64 {
        let Some(Action::Turn {
            joint,
            from,
            to,
            increasing,
        }) = self.seq.actions[s]
        else {
            return 0;
        };
        let current = self.view().joint(m, joint).unwrap_or(0);
        let model = self.world.model();
        model.quarter_turns(from.unwrap_or(current), to, increasing)
    }

    /// The module lost power: its operations stop where they are and take no effect.
    pub fn interrupt_operations(&mut self, m: usize) {
        let ids: Vec<u64> = self
            .attempts
            .iter()
            .filter(|(_, a)| a.module == m)
            .map(|(id, _)| *id)
            .collect();
        let mut turn_stopped = false;
        for id in ids {
            let Some(a) = self.attempts.remove(&id) else {
                continue;
            };
            self.turns.remove(&id);
            turn_stopped |= self.spans.remove(&id).is_some();
            if self.phys[a.statement].running == Some(id) {
                self.phys[a.statement].running = None;
                self.phys[a.statement].failed = true;
                self.mark_failed(a.statement);
                let label = self.trace_label(a.statement);
                self.log(Some(m), TraceEvent::Interrupt, label);
            }
        }
        if turn_stopped {
            self.check_running_turns();
        }
    }
}
