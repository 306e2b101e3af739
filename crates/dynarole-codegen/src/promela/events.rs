//! The trail event vocabulary, defined once: every `@` line a model prints with `printf`
//! (name, fields, format), used by the Promela writers to write the `printf`s and by
//! `dynarole-verify`'s `trail.rs` to read spin's replay of a counterexample back.

/// The kinds of event a model prints.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EventKind {
    Issue,
    Done,
    Complete,
    Deliver,
    Hear,
    Record,
    Capture,
    Late,
    Copy,
    Reset,
    End,
    Violation,
}

/// A field of an event line, after the event's name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// A whole number (`%d`), named for what it is.
    Number(&'static str),
    /// A word fixed when the model is written (a property's name, `S1`).
    Word(&'static str),
}

/// One event: `@name field.. [copy..]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EventSpec {
    pub kind: EventKind,
    /// The word after `@`.
    pub name: &'static str,
    pub fields: &'static [Field],
    /// The fields are followed by a copy of the shared state: numbers whose count depends on
    /// the protocol (lattice `epoch low done`; paper `state address pending..`).
    pub copy: bool,
    pub meaning: &'static str,
}

use Field::{Number, Word};

/// Every event a model can print.
pub const EVENTS: &[EventSpec] = &[
    EventSpec {
        kind: EventKind::Issue,
        name: "issue",
        fields: &[Number("m"), Number("s"), Number("e")],
        copy: false,
        meaning: "module m issued statement s's operation in epoch e",
    },
    EventSpec {
        kind: EventKind::Done,
        name: "done",
        fields: &[Number("m"), Number("s")],
        copy: false,
        meaning: "the operation of statement s finished physically (on module m)",
    },
    EventSpec {
        kind: EventKind::Complete,
        name: "complete",
        fields: &[Number("m"), Number("s")],
        copy: false,
        meaning: "module m saw its operation of statement s complete",
    },
    EventSpec {
        kind: EventKind::Deliver,
        name: "deliver",
        fields: &[Number("from"), Number("to")],
        copy: true,
        meaning: "module `to` received `from`'s copy (the copy follows)",
    },
    EventSpec {
        kind: EventKind::Hear,
        name: "hear",
        fields: &[Number("m")],
        copy: true,
        meaning: "compositional model: module m heard a packet holding this state",
    },
    EventSpec {
        kind: EventKind::Record,
        name: "record",
        fields: &[Number("m"), Number("s")],
        copy: false,
        meaning: "compositional model: module m marked statement s done",
    },
    EventSpec {
        kind: EventKind::Capture,
        name: "capture",
        fields: &[Number("slot"), Number("from"), Number("to")],
        copy: false,
        meaning: "a copy of `from`'s state for `to` is held in flight in a slot",
    },
    EventSpec {
        kind: EventKind::Late,
        name: "late",
        fields: &[Number("slot"), Number("from"), Number("to")],
        copy: false,
        meaning: "the next delivery is a late one, from the slot",
    },
    EventSpec {
        kind: EventKind::Copy,
        name: "copy",
        fields: &[Number("m")],
        copy: true,
        meaning: "module m's copy of the shared state after a step or a reception",
    },
    EventSpec {
        kind: EventKind::Reset,
        name: "reset",
        fields: &[Number("m")],
        copy: false,
        meaning: "module m resets",
    },
    EventSpec {
        kind: EventKind::End,
        name: "end",
        fields: &[Number("m")],
        copy: false,
        meaning: "module m declares the end",
    },
    EventSpec {
        kind: EventKind::Violation,
        name: "violation",
        fields: &[Word("property"), Number("m"), Number("s")],
        copy: false,
        meaning: "the property (S1-S3, G1-G4) fails at module m, statement s",
    },
];

impl EventKind {
    /// The event's entry in [`EVENTS`].
    pub fn spec(self) -> &'static EventSpec {
        // Every kind has its entry (the vocabulary's test checks it); the first is a fallback
        // the type system needs.
        EVENTS.iter().find(|e| e.kind == self).unwrap_or(&EVENTS[0])
    }
}

/// What the model passes for a field: an expression of the model (printed with `%d`), or a
/// value already known when the model is written (printed as is).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Arg {
    Expr(String),
    Value(String),
}

/// `Arg::Expr` of a Promela expression.
pub fn expr(e: impl Into<String>) -> Arg {
    Arg::Expr(e.into())
}

/// `Arg::Value` of a value known when the model is written.
pub fn value(v: impl ToString) -> Arg {
    Arg::Value(v.to_string())
}

/// The `printf` statement of an event: `args` are its fields, then (if the event has one) the
/// copy's. The writers print events only through here.
pub fn printf(kind: EventKind, args: &[Arg]) -> String {
    let mut format = format!("@{}", kind.spec().name);
    let mut exprs: Vec<&str> = Vec::new();
    for arg in args {
        match arg {
            Arg::Expr(e) => {
                format.push_str(" %d");
                exprs.push(e);
            }
            Arg::Value(v) => {
                format.push(' ');
                format.push_str(v);
            }
        }
    }
    let mut out = format!("printf(\"{format}\\n\"");
    for e in exprs {
        out.push_str(", ");
        out.push_str(e);
    }
    out.push(')');
    out
}

/// One event line read back: its kind, its words (the `Word` fields), its numbers (the
/// `Number` fields) and the copy's numbers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Printed {
    pub kind: EventKind,
    pub words: Vec<String>,
    pub numbers: Vec<i64>,
    pub copy: Vec<i64>,
}

/// Reads one line spin printed: `None` unless it is an event of [`EVENTS`] with its fields.
pub fn parse_printed(line: &str) -> Option<Printed> {
    let mut tokens = line.trim().strip_prefix('@')?.split_whitespace();
    let name = tokens.next()?;
    let spec = EVENTS.iter().find(|e| e.name == name)?;
    let mut printed = Printed {
        kind: spec.kind,
        words: Vec::new(),
        numbers: Vec::new(),
        copy: Vec::new(),
    };
    for field in spec.fields {
        let token = tokens.next()?;
        match field {
            Number(_) => printed.numbers.push(token.parse().ok()?),
            Word(_) => printed.words.push(token.to_string()),
        }
    }
    for token in tokens {
        if !spec.copy {
            return None;
        }
        printed.copy.push(token.parse().ok()?);
    }
    Some(printed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_one_entry_and_names_are_distinct() {
        for spec in EVENTS {
            assert_eq!(spec.kind.spec(), spec);
            assert_eq!(EVENTS.iter().filter(|e| e.name == spec.name).count(), 1);
        }
    }

    #[test]
    fn a_printf_mixes_expressions_and_known_values() {
        let p = printf(EventKind::Violation, &[value("S1"), expr("m"), value(3)]);
        assert_eq!(p, "printf(\"@violation S1 %d 3\\n\", m)");
        assert_eq!(
            printf(EventKind::Reset, &[value(2)]),
            "printf(\"@reset 2\\n\")"
        );
    }
}
