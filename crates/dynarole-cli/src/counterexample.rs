//! A counterexample of spin, in the user's terms: the `@` events the model prints during a
//! replay of the trail, translated back to modules, statements and source locations.

use dynarole_core::lower::{Ir, PAPER_STATE_END};
use dynarole_core::span::line_col;
use std::collections::BTreeMap;
use std::fmt::Write;

/// One event of a replayed trail (see the `printf("@...")` of the model).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Event {
    /// Module m issued statement s's operation (in epoch e).
    Issue {
        m: usize,
        s: usize,
        e: usize,
    },
    /// The operation of statement s finished physically (on module m).
    Done {
        m: usize,
        s: usize,
    },
    /// Module m saw its operation of statement s complete.
    Complete {
        m: usize,
        s: usize,
    },
    /// Module `to` received `from`'s copy; the fields are the copy (protocol-specific).
    Deliver {
        from: usize,
        to: usize,
        fields: Vec<i64>,
    },
    /// Compositional model: module m heard a packet holding this state (from any neighbour,
    /// sent at any earlier time).
    Hear {
        m: usize,
        fields: Vec<i64>,
    },
    /// Compositional model: module m marked statement s done (the robot now knows it).
    Record {
        m: usize,
        s: usize,
    },
    /// A copy of `from`'s state for `to` held in flight (slot), to be delivered later.
    Capture {
        slot: usize,
        from: usize,
        to: usize,
    },
    /// The next delivery is a late one (from slot).
    Late {
        slot: usize,
        from: usize,
        to: usize,
    },
    /// Module m's copy of the shared state after a step or a reception.
    Copy {
        m: usize,
        fields: Vec<i64>,
    },
    Reset {
        m: usize,
    },
    End {
        m: usize,
    },
    Violation {
        property: String,
        m: usize,
        s: usize,
    },
    /// Spin's marker: what follows repeats forever.
    CycleStart,
}

/// Reads the events from the output of `spin -T -t`.
pub fn parse_events(output: &str) -> Vec<Event> {
    let mut events = Vec::new();
    for line in output.lines() {
        let line = line.trim();
        if line.contains("START OF CYCLE") {
            events.push(Event::CycleStart);
            continue;
        }
        let Some(rest) = line.strip_prefix('@') else {
            continue;
        };
        let mut words = rest.split_whitespace();
        let kind = words.next().unwrap_or("");
        let words: Vec<&str> = words.collect();
        let n = |k: usize| -> usize { words.get(k).and_then(|w| w.parse().ok()).unwrap_or(0) };
        // The numbers from word k on (a copy of the shared state).
        let fields = |k: usize| -> Vec<i64> {
            words
                .iter()
                .skip(k)
                .filter_map(|w| w.parse().ok())
                .collect()
        };
        let event = match kind {
            "issue" => Event::Issue {
                m: n(0),
                s: n(1),
                e: n(2),
            },
            "done" => Event::Done { m: n(0), s: n(1) },
            "complete" => Event::Complete { m: n(0), s: n(1) },
            "deliver" => Event::Deliver {
                from: n(0),
                to: n(1),
                fields: fields(2),
            },
            "hear" => Event::Hear {
                m: n(0),
                fields: fields(1),
            },
            "record" => Event::Record { m: n(0), s: n(1) },
            "capture" => Event::Capture {
                slot: n(0),
                from: n(1),
                to: n(2),
            },
            "late" => Event::Late {
                slot: n(0),
                from: n(1),
                to: n(2),
            },
            "copy" => Event::Copy {
                m: n(0),
                fields: fields(1),
            },
            "reset" => Event::Reset { m: n(0) },
            "end" => Event::End { m: n(0) },
            "violation" => Event::Violation {
                property: words.first().unwrap_or(&"?").to_string(),
                m: n(1),
                s: n(2),
            },
            _ => continue,
        };
        events.push(event);
    }
    events
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

    /// A module's copy of the shared state in the user's terms.
    pub fn copy(&self, fields: &[i64]) -> String {
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
    let mut out = String::new();
    let violation = events.iter().find_map(|e| match e {
        Event::Violation { property, m, s } => Some((property.clone(), *m, *s)),
        _ => None,
    });
    let cyclic = events.contains(&Event::CycleStart);
    let mut physically_done: Vec<usize> = Vec::new();
    for e in events {
        if let Event::Done { s, .. } = e {
            physically_done.push(*s);
        }
    }
    match &violation {
        Some((property, m, s)) => {
            let st = cx.ir.statements.get(*s);
            let headline = match property.as_str() {
                "S1" => {
                    let missing: Vec<usize> = st
                        .map(|st| {
                            st.deps
                                .iter()
                                .map(|d| usize::from(*d))
                                .filter(|d| !physically_done.contains(d))
                                .collect()
                        })
                        .unwrap_or_default();
                    format!(
                        "S1 violated: {} started {} before {} {} done",
                        cx.module(*m),
                        cx.statement(*s),
                        Context::list(&missing),
                        if missing.len() == 1 { "was" } else { "were" }
                    )
                }
                "S2" => format!(
                    "S2 violated: {} issued {} again after a statement that depends on it had started",
                    cx.module(*m),
                    cx.statement(*s)
                ),
                "G1" | "G2" | "G3" | "G4" => guarantee_headline(property, cx.module(*m), *s),
                _ => {
                    let open: Vec<usize> = (0..cx.ir.statements.len())
                        .filter(|s| !physically_done.contains(s))
                        .collect();
                    format!(
                        "S3 violated: {} declared the end while {} {} not done",
                        cx.module(*m),
                        Context::list(&open),
                        if open.len() == 1 { "was" } else { "were" }
                    )
                }
            };
            let _ = writeln!(out, "{headline}");
        }
        None if cyclic => {
            let never: Vec<usize> = (0..cx.ir.statements.len())
                .filter(|s| !physically_done.contains(s))
                .collect();
            let _ = writeln!(
                out,
                "L violated: the sequence never finishes (statements never done: {}); the steps after `then, forever:` repeat endlessly, every link delivering",
                Context::list(&never)
            );
        }
        None => {
            let _ = writeln!(out, "counterexample without a recorded violation");
        }
    }
    let _ = writeln!(out, "counterexample:");
    let mut k = 0usize;
    let mut late = false;
    let mut last_copy: BTreeMap<(usize, usize), Vec<i64>> = BTreeMap::new();
    let mut skipped = 0usize;
    let mut copies: BTreeMap<usize, Vec<i64>> = BTreeMap::new();
    let mut consumed: std::collections::BTreeSet<usize> = Default::default();
    let mut issued: std::collections::BTreeSet<(usize, usize)> = Default::default();
    for (index, e) in events.iter().enumerate() {
        let line = match e {
            Event::Issue { m, s, e } => {
                let again = !issued.insert((*e, *s));
                let epoch = if *e > 0 {
                    format!(" in epoch {e}")
                } else {
                    String::new()
                };
                let now = events[index + 1..]
                    .iter()
                    .enumerate()
                    .find_map(|(j, x)| match x {
                        Event::Copy { m: k, fields } if k == m => {
                            consumed.insert(index + 1 + j);
                            Some(fields)
                        }
                        _ => None,
                    })
                    .filter(|a| copies.get(m) != Some(*a))
                    .map_or(String::new(), |a| {
                        format!("; {} now holds {}", cx.module(*m), cx.copy(a))
                    });
                Some(format!(
                    "{} {} {}{epoch}{now}",
                    cx.module(*m),
                    if again { "issues again" } else { "starts" },
                    cx.statement(*s)
                ))
            }
            Event::Done { m, s } => Some(format!(
                "the operation of #{s} finishes on {} (physically)",
                cx.module(*m)
            )),
            Event::Complete { m, s } => Some(format!("{} sees #{s} complete", cx.module(*m))),
            Event::Hear { m, fields } => {
                let after = copy_after(events, index, *m, &mut consumed);
                let now = after
                    .filter(|a| copies.get(m) != Some(a))
                    .map_or(String::new(), |a| {
                        let text = format!("; {} now holds {}", cx.module(*m), cx.copy(&a));
                        copies.insert(*m, a);
                        text
                    });
                Some(format!(
                    "{} hears a packet (some neighbour's, sent at some earlier time): {}{now}",
                    cx.module(*m),
                    cx.copy(fields)
                ))
            }
            // The checked module's own recording follows its `Complete`; another module's is
            // its completion.
            Event::Record { m, s } => {
                let own = index > 0
                    && matches!(events[index - 1], Event::Complete { m: k, s: t } if k == *m && t == *s);
                (!own).then(|| {
                    format!(
                        "{} sees #{s} complete (its copy holds it now)",
                        cx.module(*m)
                    )
                })
            }
            Event::Deliver { from, to, fields } => {
                let was_late = std::mem::take(&mut late);
                // What the receiver holds after it (the next event is its copy).
                let after = copy_after(events, index, *to, &mut consumed);
                let changed = after.as_ref().filter(|a| copies.get(to) != Some(*a));
                let now = changed.map_or(String::new(), |a| {
                    format!("; {} now holds {}", cx.module(*to), cx.copy(a))
                });
                if !was_late && changed.is_none() && last_copy.get(&(*from, *to)) == Some(fields) {
                    skipped += 1;
                    None
                } else {
                    last_copy.insert((*from, *to), fields.clone());
                    Some(format!(
                        "{} hears {}{}: {}{now}",
                        cx.module(*to),
                        cx.module(*from),
                        if was_late {
                            "'s earlier packet, delivered late"
                        } else {
                            ""
                        },
                        cx.copy(fields)
                    ))
                }
            }
            // Only a packet that is delivered late is worth a step.
            Event::Capture { slot, from, to } if delivered_late(&events[index + 1..], *slot) => {
                Some(format!(
                    "{} sends a packet to {} that stays in flight (it arrives late)",
                    cx.module(*from),
                    cx.module(*to)
                ))
            }
            Event::Capture { .. } => None,
            Event::Late { .. } => {
                late = true;
                None
            }
            Event::Copy { m, fields } => {
                // A step that changed the copy without starting anything (a hand-over, a
                // completion seen) is worth a line of its own.
                let changed = copies.get(m) != Some(fields);
                copies.insert(*m, fields.clone());
                (changed && !consumed.contains(&index) && index > 0)
                    .then(|| format!("{} now holds {}", cx.module(*m), cx.copy(fields)))
            }
            Event::Reset { m } => Some(format!("{} resets", cx.module(*m))),
            Event::End { m } => Some(format!("{} declares the end", cx.module(*m))),
            Event::Violation { .. } => None,
            Event::CycleStart => {
                let _ = writeln!(out, "  then, forever:");
                None
            }
        };
        if let Some(line) = line {
            k += 1;
            let _ = writeln!(out, "  {k:>3}. {line}");
        }
    }
    if skipped > 0 {
        let _ = writeln!(
            out,
            "  ({skipped} deliveries that repeat the link's previous packet are not shown)"
        );
    }
    out
}

/// Module m's copy right after the event at `index` (the model prints it next), marked as
/// told so that it is not a step of its own.
fn copy_after(
    events: &[Event],
    index: usize,
    m: usize,
    consumed: &mut std::collections::BTreeSet<usize>,
) -> Option<Vec<i64>> {
    match events.get(index + 1) {
        Some(Event::Copy { m: k, fields }) if *k == m => {
            consumed.insert(index + 1);
            Some(fields.clone())
        }
        _ => None,
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
