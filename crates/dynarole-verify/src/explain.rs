//! A counterexample of spin in the user's terms: the events of a replayed trail translated
//! back to modules, statements and source locations, as numbered steps (one function per
//! kind of event) under a headline saying which property is violated and how.

use crate::search::Check;
use crate::trail::Event;
use dynarole_core::lower::{Ir, PAPER_STATE_END};
use dynarole_core::span::line_col;
use std::collections::{BTreeMap, BTreeSet};

/// A counterexample found by a check: the events of its trail (module indices into
/// `module_names`, statement numbers into the IR), and what they say.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Counterexample {
    pub check: Check,
    /// The module index of the events checked (compositional model), if any.
    pub module: Option<usize>,
    pub events: Vec<Event>,
    /// For each module index of the events, the module's name.
    pub module_names: Vec<String>,
    pub explanation: Explanation,
    /// The explanation as printed.
    pub text: String,
    /// For each `Copy` event (by its index in `events`), the module's copy of the shared
    /// state in the user's terms (what a viewer's state panel shows).
    pub copies: BTreeMap<usize, String>,
}

/// The violated property and the steps that lead to it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Explanation {
    /// E.g. `S1 violated: M2 started #2 ... before #0 was done`.
    pub headline: String,
    pub steps: Vec<Step>,
    /// Number of steps told before each of spin's `START OF CYCLE` markers: the steps after
    /// it repeat forever.
    pub cycle_starts: Vec<usize>,
    /// Deliveries not told because they repeat the link's previous packet.
    pub skipped: usize,
}

/// One step of a counterexample.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Step {
    /// The index of the event it tells in [`Counterexample::events`].
    pub event: usize,
    pub text: String,
}

impl std::fmt::Display for Explanation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "{}", self.headline)?;
        writeln!(f, "counterexample:")?;
        for k in 0..=self.steps.len() {
            for _ in self.cycle_starts.iter().filter(|&&c| c == k) {
                writeln!(f, "  then, forever:")?;
            }
            if let Some(step) = self.steps.get(k) {
                writeln!(f, "  {:>3}. {}", k + 1, step.text)?;
            }
        }
        if self.skipped > 0 {
            writeln!(
                f,
                "  ({} deliveries that repeat the link's previous packet are not shown)",
                self.skipped
            )?;
        }
        Ok(())
    }
}

/// What the explanation needs to know.
pub struct Context<'a> {
    pub ir: &'a Ir,
    pub module_names: &'a [String],
    /// The paper protocol's layout: (first state, statements) per unit; empty for the lattice.
    pub paper_states: &'a [(u8, Vec<usize>)],
    pub path: &'a str,
    pub source: &'a str,
}

impl Context<'_> {
    fn module(&self, m: usize) -> &str {
        self.module_names.get(m).map_or("?", String::as_str)
    }

    fn location(&self, s: usize) -> String {
        match self.ir.statements.get(s) {
            Some(st) => {
                let (line, col) = line_col(self.source, st.span.start);
                format!("{}:{line}:{col}", self.path)
            }
            None => self.path.to_string(),
        }
    }

    fn statement(&self, s: usize) -> String {
        match self.ir.statements.get(s) {
            Some(st) => format!("#{s} `{}` ({})", st.text, self.location(s)),
            None => format!("#{s}"),
        }
    }

    /// `#0, #2` for a set of statements.
    fn list(items: &[usize]) -> String {
        if items.is_empty() {
            return "none".into();
        }
        items
            .iter()
            .map(|s| format!("#{s}"))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The paper protocol's state number in the user's terms.
    fn paper_state(&self, state: i64) -> String {
        match state {
            0 => "0 (initial)".into(),
            s if s == i64::from(PAPER_STATE_END) => format!("{PAPER_STATE_END} (end)"),
            _ => {
                let unit = self
                    .paper_states
                    .iter()
                    .rev()
                    .find(|(first, _)| i64::from(*first) <= state);
                match unit {
                    Some((first, statements)) => format!(
                        "{state} ({} of {})",
                        match state - i64::from(*first) {
                            0 => "start",
                            1 => "hand-over/wait",
                            _ => "wait",
                        },
                        Self::list(statements)
                    ),
                    None => state.to_string(),
                }
            }
        }
    }

    pub(crate) fn copy(&self, fields: &[i64]) -> String {
        if self.paper_states.is_empty() {
            // Lattice: epoch, low, done bits above low.
            let (epoch, low, bits) = (
                fields.first().copied().unwrap_or(0),
                fields.get(1).copied().unwrap_or(0),
                fields.get(2).copied().unwrap_or(0),
            );
            let mut done: Vec<usize> = (0..low.max(0) as usize).collect();
            for i in 0..32usize {
                if (bits >> i) & 1 == 1 {
                    done.push(low.max(0) as usize + i);
                }
            }
            format!("epoch {epoch}, done {}", Self::list(&done))
        } else {
            let state = fields.first().copied().unwrap_or(0);
            let address = fields.get(1).copied().unwrap_or(0);
            let pending: Vec<String> = fields
                .iter()
                .skip(2)
                .filter(|p| **p != 0)
                .map(|p| p.to_string())
                .collect();
            format!(
                "state {}, recipient {address}, pending {{{}}}",
                self.paper_state(state),
                pending.join(", ")
            )
        }
    }
}

/// The counterexample as numbered steps, with the violated property first.
pub fn explain(events: &[Event], cx: &Context) -> String {
    tell(events, cx).to_string()
}

/// The explanation of `events`.
pub fn tell(events: &[Event], cx: &Context) -> Explanation {
    let mut teller = Teller {
        events,
        cx,
        late: false,
        last_copy: BTreeMap::new(),
        copies: BTreeMap::new(),
        consumed: BTreeSet::new(),
        issued: BTreeSet::new(),
    };
    let mut explanation = Explanation {
        headline: headline(events, cx),
        steps: Vec::new(),
        cycle_starts: Vec::new(),
        skipped: 0,
    };
    for (index, event) in events.iter().enumerate() {
        match event {
            Event::CycleStart => explanation.cycle_starts.push(explanation.steps.len()),
            Event::Deliver { from, to, fields } => {
                match teller.deliver(index, *from, *to, fields) {
                    Some(text) => explanation.steps.push(Step { event: index, text }),
                    None => explanation.skipped += 1,
                }
            }
            _ => {
                if let Some(text) = teller.step(index, event) {
                    explanation.steps.push(Step { event: index, text });
                }
            }
        }
    }
    explanation
}

/// The statements physically done in the run.
fn physically_done(events: &[Event]) -> Vec<usize> {
    events
        .iter()
        .filter_map(|e| match e {
            Event::Done { s, .. } => Some(*s),
            _ => None,
        })
        .collect()
}

/// `#0, #2 were` (or `#1 was`): statements not done, of all the IR's statements unless
/// `among` is given.
fn not_done(cx: &Context, done: &[usize], among: Option<Vec<usize>>) -> String {
    let open: Vec<usize> = among
        .unwrap_or_else(|| (0..cx.ir.statements.len()).collect())
        .into_iter()
        .filter(|s| !done.contains(s))
        .collect();
    format!(
        "{} {}",
        Context::list(&open),
        if open.len() == 1 { "was" } else { "were" }
    )
}

/// The first line: the property violated, by whom, and what was not done.
fn headline(events: &[Event], cx: &Context) -> String {
    let done = physically_done(events);
    let violation = events.iter().find_map(|e| match e {
        Event::Violation { property, m, s } => Some((property.as_str(), *m, *s)),
        _ => None,
    });
    match violation {
        Some((property, m, s)) => violation_headline(cx, &done, property, m, s),
        None if events.contains(&Event::CycleStart) => {
            let never: Vec<usize> = (0..cx.ir.statements.len())
                .filter(|s| !done.contains(s))
                .collect();
            format!(
                "L violated: the sequence never finishes (statements never done: {}); the steps after `then, forever:` repeat endlessly, every link delivering",
                Context::list(&never)
            )
        }
        None => "counterexample without a recorded violation".to_string(),
    }
}

/// The headline of an assertion violated by module `m` at statement `s`.
fn violation_headline(cx: &Context, done: &[usize], property: &str, m: usize, s: usize) -> String {
    match property {
        "S1" => {
            let deps = cx
                .ir
                .statements
                .get(s)
                .map(|st| st.deps.iter().map(|d| usize::from(*d)).collect())
                .unwrap_or_default();
            format!(
                "S1 violated: {} started {} before {} done",
                cx.module(m),
                cx.statement(s),
                not_done(cx, done, Some(deps))
            )
        }
        "S2" => format!(
            "S2 violated: {} issued {} again after a statement that depends on it had started",
            cx.module(m),
            cx.statement(s)
        ),
        "G1" | "G2" | "G3" | "G4" => guarantee_headline(property, cx.module(m), s),
        _ => format!(
            "S3 violated: {} declared the end while {} not done",
            cx.module(m),
            not_done(cx, done, None)
        ),
    }
}

/// The headline of a broken guarantee of the compositional model.
fn guarantee_headline(property: &str, module: &str, s: usize) -> String {
    let what = match property {
        "G1" => format!("its copy holds #{s} done, which no module has recorded"),
        "G2" => format!("its copy holds #{s} done but not everything #{s} waits for"),
        "G3" => format!("its copy lost #{s}, which it completed itself"),
        _ => format!(
            "#{s} was marked done before it was physically done, or before what it waits for was"
        ),
    };
    format!("{property} violated (a guarantee of the compositional model): {module}: {what}")
}

/// What has been told so far, for the steps still to tell.
struct Teller<'e, 'c> {
    events: &'e [Event],
    cx: &'c Context<'c>,
    /// The next delivery is a late one.
    late: bool,
    /// The last packet told on each link (from, to).
    last_copy: BTreeMap<(usize, usize), Vec<i64>>,
    /// Each module's copy as last told.
    copies: BTreeMap<usize, Vec<i64>>,
    /// Indices of `Copy` events already told with the step before them.
    consumed: BTreeSet<usize>,
    /// (epoch, statement) issued so far.
    issued: BTreeSet<(usize, usize)>,
}

impl Teller<'_, '_> {
    /// The step telling the event at `index` (not a delivery or a cycle marker), if it is
    /// worth one.
    fn step(&mut self, index: usize, event: &Event) -> Option<String> {
        let cx = self.cx;
        match event {
            Event::Issue { m, s, e } => Some(self.issue(index, *m, *s, *e)),
            Event::Done { m, s } => Some(format!(
                "the operation of #{s} finishes on {} (physically)",
                cx.module(*m)
            )),
            Event::Complete { m, s } => Some(format!("{} sees #{s} complete", cx.module(*m))),
            Event::Hear { m, fields } => Some(self.hear(index, *m, fields)),
            Event::Record { m, s } => self.record(index, *m, *s),
            Event::Capture { slot, from, to } => self.capture(index, *slot, *from, *to),
            Event::Late { .. } => {
                self.late = true;
                None
            }
            Event::Copy { m, fields } => self.copy(index, *m, fields),
            Event::Reset { m } => Some(format!("{} resets", cx.module(*m))),
            Event::End { m } => Some(format!("{} declares the end", cx.module(*m))),
            Event::Violation { .. } | Event::CycleStart | Event::Deliver { .. } => None,
        }
    }

    /// `; M1 now holds ...` when module m's copy `after` differs from the one last told.
    fn now_holds(&self, m: usize, after: Option<&Vec<i64>>) -> String {
        after
            .filter(|a| self.copies.get(&m) != Some(*a))
            .map_or(String::new(), |a| {
                format!("; {} now holds {}", self.cx.module(m), self.cx.copy(a))
            })
    }

    /// Module m starts (or issues again) statement s in epoch e, with the copy it then holds
    /// (the next copy of m the model prints).
    fn issue(&mut self, index: usize, m: usize, s: usize, e: usize) -> String {
        let again = !self.issued.insert((e, s));
        let epoch = if e > 0 {
            format!(" in epoch {e}")
        } else {
            String::new()
        };
        let next_copy = self.events[index + 1..]
            .iter()
            .enumerate()
            .find_map(|(j, x)| match x {
                Event::Copy { m: k, fields } if *k == m => Some((index + 1 + j, fields)),
                _ => None,
            });
        if let Some((at, _)) = next_copy {
            self.consumed.insert(at);
        }
        let now = self.now_holds(m, next_copy.map(|(_, fields)| fields));
        format!(
            "{} {} {}{epoch}{now}",
            self.cx.module(m),
            if again { "issues again" } else { "starts" },
            self.cx.statement(s)
        )
    }

    /// Compositional model: module m hears a packet holding `fields`.
    fn hear(&mut self, index: usize, m: usize, fields: &[i64]) -> String {
        let after = self.copy_after(index, m);
        let now = self.now_holds(m, after.as_ref());
        if let Some(a) = after.filter(|a| self.copies.get(&m) != Some(a)) {
            self.copies.insert(m, a);
        }
        format!(
            "{} hears a packet (some neighbour's, sent at some earlier time): {}{now}",
            self.cx.module(m),
            self.cx.copy(fields)
        )
    }

    /// Compositional model: the checked module's own recording follows its `Complete` (told
    /// there); another module's is its completion.
    fn record(&self, index: usize, m: usize, s: usize) -> Option<String> {
        let own = index > 0
            && matches!(self.events[index - 1], Event::Complete { m: k, s: t } if k == m && t == s);
        (!own).then(|| {
            format!(
                "{} sees #{s} complete (its copy holds it now)",
                self.cx.module(m)
            )
        })
    }

    /// Module `to` hears `from`'s packet; `None` (not told) when it repeats the link's
    /// previous packet and changes nothing.
    fn deliver(&mut self, index: usize, from: usize, to: usize, fields: &[i64]) -> Option<String> {
        let was_late = std::mem::take(&mut self.late);
        // What the receiver holds after it (the next event is its copy).
        let after = self.copy_after(index, to);
        let changed = after
            .as_ref()
            .is_some_and(|a| self.copies.get(&to) != Some(a));
        let repeated = self.last_copy.get(&(from, to)).map(Vec::as_slice) == Some(fields);
        if !was_late && !changed && repeated {
            return None;
        }
        let now = self.now_holds(to, after.as_ref());
        self.last_copy.insert((from, to), fields.to_vec());
        Some(format!(
            "{} hears {}{}: {}{now}",
            self.cx.module(to),
            self.cx.module(from),
            if was_late {
                "'s earlier packet, delivered late"
            } else {
                ""
            },
            self.cx.copy(fields)
        ))
    }

    /// A packet held in flight: worth a step only when it is delivered late.
    fn capture(&self, index: usize, slot: usize, from: usize, to: usize) -> Option<String> {
        delivered_late(&self.events[index + 1..], slot).then(|| {
            format!(
                "{} sends a packet to {} that stays in flight (it arrives late)",
                self.cx.module(from),
                self.cx.module(to)
            )
        })
    }

    /// A step that changed module m's copy without starting anything (a hand-over, a
    /// completion seen) is worth a line of its own.
    fn copy(&mut self, index: usize, m: usize, fields: &[i64]) -> Option<String> {
        let changed = self.copies.get(&m).map(Vec::as_slice) != Some(fields);
        self.copies.insert(m, fields.to_vec());
        (changed && !self.consumed.contains(&index) && index > 0)
            .then(|| format!("{} now holds {}", self.cx.module(m), self.cx.copy(fields)))
    }

    /// Module m's copy right after the event at `index` (the model prints it next), marked
    /// as told so that it is not a step of its own.
    fn copy_after(&mut self, index: usize, m: usize) -> Option<Vec<i64>> {
        match self.events.get(index + 1) {
            Some(Event::Copy { m: k, fields }) if *k == m => {
                self.consumed.insert(index + 1);
                Some(fields.clone())
            }
            _ => None,
        }
    }
}

/// Whether the next use of `slot` in `rest` is a late delivery (not a new capture).
fn delivered_late(rest: &[Event], slot: usize) -> bool {
    rest.iter()
        .find_map(|e| match e {
            Event::Capture { slot: k, .. } if *k == slot => Some(false),
            Event::Late { slot: k, .. } if *k == slot => Some(true),
            _ => None,
        })
        .unwrap_or(false)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(event: usize, text: &str) -> Step {
        Step {
            event,
            text: text.into(),
        }
    }

    #[test]
    fn the_steps_after_spins_cycle_marker_are_told_as_repeating() {
        let explanation = Explanation {
            headline: "L violated".into(),
            steps: vec![step(0, "M0 starts #0"), step(2, "M1 hears M0")],
            cycle_starts: vec![1],
            skipped: 2,
        };
        assert_eq!(
            explanation.to_string(),
            "L violated\ncounterexample:\n    1. M0 starts #0\n  then, forever:\n    2. M1 hears M0\n  (2 deliveries that repeat the link's previous packet are not shown)\n"
        );
        let at_the_end = Explanation {
            cycle_starts: vec![2],
            skipped: 0,
            ..explanation
        };
        assert!(at_the_end
            .to_string()
            .ends_with("2. M1 hears M0\n  then, forever:\n"));
    }
}
