//! The trace event vocabulary, defined once: every event a trace line can name (its word,
//! what it means, what the viewer draws for it), from which the simulator's and the model
//! recordings' writers take their events, `Recording::check` reads a recording's events back,
//! and the viewer's page gets its colours and its legend ([`vocabulary_json`]).

use serde_json::{json, Value};

/// The kinds of event a trace line names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TraceEvent {
    PowerOn,
    PowerOff,
    Dead,
    Reset,
    Start,
    Resume,
    Retry,
    Reissue,
    Done,
    Interrupt,
    Refused,
    Failed,
    UnknownOp,
    Finished,
    Stopped,
    S1,
    S2,
    S3,
    Clash,
    Timeout,
    Lost,
    DeadLink,
    Collision,
    Blocked,
    Broken,
    Off,
    Foreign,
    Copy,
    Violation,
}

/// The kinds of marker on the viewer's timeline (a recording's `markers[].kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mark {
    Reset,
    Power,
    Violation,
    Refused,
    Link,
}

/// What an event does to the operation of the statement it names (the swimlane's bars).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operation {
    /// Nothing: the event is no start or end of an operation.
    None,
    /// A physical attempt begins (a bar starts).
    Starts,
    /// The attempt ends; its bar takes this colour (the motion's `outcome` is the event's name).
    Ends(&'static str),
}

/// One event: its word in the trace and in a recording's `events[].event`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EventSpec {
    pub kind: TraceEvent,
    pub name: &'static str,
    pub meaning: &'static str,
    /// The marker the viewer puts on the timeline for it, if any.
    pub mark: Option<Mark>,
    pub operation: Operation,
    /// A packet that did not arrive (its trace lines are capped in a recording).
    pub dropped_packet: bool,
    /// Named in the `#` lines at the top of a trace file. The header's text is kept as it
    /// was written (traces are compared byte for byte), and it predates `foreign`, `dead` and
    /// `failed`; `copy` and `violation` come only from runs on the model, which write no
    /// trace file.
    pub in_header: bool,
}

/// One marker kind: its word, its colour on the page, what it marks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MarkSpec {
    pub kind: Mark,
    pub name: &'static str,
    pub colour: &'static str,
    pub meaning: &'static str,
}

/// A row of [`EVENTS`], spelled short: (kind, name, meaning, mark, operation, dropped packet,
/// in the header).
const fn spec(
    kind: TraceEvent,
    name: &'static str,
    meaning: &'static str,
    mark: Option<Mark>,
    operation: Operation,
    flags: (bool, bool),
) -> EventSpec {
    EventSpec {
        kind,
        name,
        meaning,
        mark,
        operation,
        dropped_packet: flags.0,
        in_header: flags.1,
    }
}

use Operation::{Ends, Starts};
use TraceEvent as E;

/// Neither a dropped packet nor left out of the header.
const PLAIN: (bool, bool) = (false, true);
const PACKET: (bool, bool) = (true, true);
const NOT_IN_HEADER: (bool, bool) = (false, false);

/// Every event a trace can name, in the order the trace header lists them.
#[rustfmt::skip]
pub const EVENTS: &[EventSpec] = &[
    spec(E::PowerOn, "power-on", "the module is powered on (marked from its second power-on)", Some(Mark::Power), Operation::None, PLAIN),
    spec(E::PowerOff, "power-off", "the module is powered off: silent, its operation stops", Some(Mark::Power), Operation::None, PLAIN),
    spec(E::Dead, "dead", "the module dies in place (`dead` in the scenario): off for good, its parts stay where they are, latched", Some(Mark::Power), Operation::None, NOT_IN_HEADER),
    spec(E::Reset, "reset", "the module resets and runs its init again", Some(Mark::Reset), Operation::None, PLAIN),
    spec(E::Start, "start", "the module starts a statement's operation for the first time", None, Starts, PLAIN),
    spec(E::Resume, "resume", "the module, after a reset, waits for its operation still in progress", None, Operation::None, PLAIN),
    spec(E::Retry, "retry", "the module starts again an operation that failed", None, Starts, PLAIN),
    spec(E::Reissue, "reissue", "the module starts again an operation already done", None, Starts, PLAIN),
    spec(E::Done, "done", "the operation completed physically", None, Ends("#2ca02c"), PLAIN),
    spec(E::Interrupt, "interrupt", "the operation stopped unfinished (its module lost power or died)", None, Ends("#7f7f7f"), PLAIN),
    spec(E::Refused, "refused", "the world refused the operation (the detail says why)", Some(Mark::Refused), Ends("#d62728"), PLAIN),
    spec(E::Failed, "failed", "the operation ended without effect, failed by the scenario (`transient`, or `stuck` and the part)", Some(Mark::Refused), Ends("#e377c2"), NOT_IN_HEADER),
    spec(E::UnknownOp, "unknown-op", "the module asked for an operation its statement does not have", None, Operation::None, PLAIN),
    spec(E::Finished, "finished", "the module declares the end", None, Operation::None, PLAIN),
    spec(E::Stopped, "stopped", "an operation of the module failed and its failure policy gave up: it starts nothing more", Some(Mark::Refused), Operation::None, NOT_IN_HEADER),
    spec(E::S1, "S1", "violation: a statement started before its dependencies were done", Some(Mark::Violation), Operation::None, PLAIN),
    spec(E::S2, "S2", "violation: a statement re-issued after a dependent one started", Some(Mark::Violation), Operation::None, PLAIN),
    spec(E::S3, "S3", "violation: the end declared before every operation was done", Some(Mark::Violation), Operation::None, PLAIN),
    spec(E::Clash, "clash", "violation: two turns running at once bring two modules within the limit (the detail names them)", Some(Mark::Violation), Operation::None, PLAIN),
    spec(E::Timeout, "timeout", "the run reached its time limit before every module declared the end", None, Operation::None, PLAIN),
    spec(E::Lost, "lost", "a packet lost to the background loss", None, Operation::None, PACKET),
    spec(E::DeadLink, "dead-link", "a packet lost on a dead link", Some(Mark::Link), Operation::None, PACKET),
    spec(E::Collision, "collision", "a packet lost in a collision (half duplex)", None, Operation::None, PACKET),
    spec(E::Blocked, "blocked", "a packet lost on a link the scenario blocks", Some(Mark::Link), Operation::None, PACKET),
    spec(E::Broken, "broken", "a packet lost because a turn broke the link", None, Operation::None, PACKET),
    spec(E::Off, "off", "a packet lost because the receiver was off", None, Operation::None, PACKET),
    spec(E::Foreign, "foreign", "a packet of another robot's module arrives (`foreign` in the scenario)", None, Operation::None, NOT_IN_HEADER),
    spec(E::Copy, "copy", "runs on the model: the module's copy of the shared state changed", None, Operation::None, NOT_IN_HEADER),
    spec(E::Violation, "violation", "runs on the model: a property is broken here (the detail names it)", Some(Mark::Violation), Operation::None, NOT_IN_HEADER),
];

/// Every marker kind of the timeline.
#[rustfmt::skip]
pub const MARKS: &[MarkSpec] = &[
    MarkSpec { kind: Mark::Reset, name: "reset", colour: "#d62728", meaning: "resets" },
    MarkSpec { kind: Mark::Power, name: "power", colour: "#9467bd", meaning: "power off and on, deaths" },
    MarkSpec { kind: Mark::Violation, name: "violation", colour: "#000000", meaning: "violations of the checks or of a model's property" },
    MarkSpec { kind: Mark::Refused, name: "refused", colour: "#ff7f0e", meaning: "refused or failed operations" },
    MarkSpec { kind: Mark::Link, name: "link", colour: "#8c564b", meaning: "blocked or dead links, once per episode" },
];

impl TraceEvent {
    /// The event's entry in [`EVENTS`].
    pub fn spec(self) -> &'static EventSpec {
        // Every kind has its entry (the vocabulary's test checks it); the first is a fallback
        // the type system needs.
        EVENTS.iter().find(|e| e.kind == self).unwrap_or(&EVENTS[0])
    }

    /// The word of the trace.
    pub fn name(self) -> &'static str {
        self.spec().name
    }

    /// The event a word names, if any.
    pub fn parse(name: &str) -> Option<TraceEvent> {
        EVENTS.iter().find(|e| e.name == name).map(|e| e.kind)
    }

    /// The marker it puts on the timeline.
    pub fn mark(self) -> Option<Mark> {
        self.spec().mark
    }
}

impl std::fmt::Display for TraceEvent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Mark {
    /// The marker kind's entry in [`MARKS`].
    pub fn spec(self) -> &'static MarkSpec {
        MARKS.iter().find(|m| m.kind == self).unwrap_or(&MARKS[0])
    }

    pub fn name(self) -> &'static str {
        self.spec().name
    }
}

/// Why a recording's event word is none of [`EVENTS`]: the field and every word it could be.
pub fn unknown_event(field: &str, name: &str) -> String {
    let names: Vec<&str> = EVENTS.iter().map(|e| e.name).collect();
    format!(
        "field `{field}`: `{name}` is not a trace event (one of {})",
        names.join(", ")
    )
}

/// The vocabulary as the viewer's page reads it: every event (name, meaning, mark, the
/// colour of the bar it ends) and every marker kind (name, colour, meaning).
pub fn vocabulary_json() -> Value {
    let events: Vec<Value> = EVENTS
        .iter()
        .map(|e| {
            let ends = match e.operation {
                Ends(colour) => Some(colour),
                _ => None,
            };
            json!({
                "name": e.name,
                "meaning": e.meaning,
                "mark": e.mark.map(Mark::name),
                "ends": ends,
            })
        })
        .collect();
    let marks: Vec<Value> = MARKS
        .iter()
        .map(|m| json!({"name": m.name, "colour": m.colour, "meaning": m.meaning}))
        .collect();
    json!({ "events": events, "marks": marks })
}

/// The events as the table of `docs/simulator.md` states them (its test keeps them equal).
pub fn markdown_table() -> String {
    let mut out = String::from("| event | meaning | timeline marker |\n|---|---|---|\n");
    for e in EVENTS {
        let mark = e.mark.map_or("", Mark::name);
        out.push_str(&format!("| `{}` | {} | {mark} |\n", e.name, e.meaning));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_one_entry_and_names_are_distinct() {
        for spec in EVENTS {
            assert_eq!(spec.kind.spec(), spec);
            assert_eq!(TraceEvent::parse(spec.name), Some(spec.kind));
            assert_eq!(EVENTS.iter().filter(|e| e.name == spec.name).count(), 1);
        }
        for mark in MARKS {
            assert_eq!(mark.kind.spec(), mark);
            assert!(
                EVENTS.iter().any(|e| e.mark == Some(mark.kind)),
                "{}",
                mark.name
            );
        }
    }

    #[test]
    fn an_unknown_word_is_no_event_and_the_message_lists_them() {
        assert_eq!(TraceEvent::parse("delivered"), None);
        let message = unknown_event("events[3].event", "frobnicate");
        assert!(message.starts_with("field `events[3].event`: `frobnicate` is not a trace event"));
        assert!(message.contains("power-on") && message.contains("violation"));
    }
}
