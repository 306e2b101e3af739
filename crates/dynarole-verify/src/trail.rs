//! The trail of a counterexample as events: what the model prints with `printf("@...")`
//! while spin replays the trail (`spin -T -t`), read back into values. The vocabulary (names,
//! fields, format) is defined once, in `dynarole_codegen::trail_events`, which the Promela
//! writers print with.

use dynarole_codegen::trail_events::{parse_printed, EventKind, Printed};

/// One event of a replayed trail (see `dynarole_codegen::trail_events::EVENTS`).
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

/// Reads the events from the output of `spin -T -t` (other lines are spin's own, and so is a
/// line that does not have its event's fields).
pub fn parse_events(output: &str) -> Vec<Event> {
    let mut events = Vec::new();
    for line in output.lines() {
        if line.contains("START OF CYCLE") {
            events.push(Event::CycleStart);
            continue;
        }
        events.extend(parse_printed(line).and_then(|p| event(&p)));
    }
    events
}

/// The event of a line read with the vocabulary (`trail_events::EVENTS`, whose field order
/// the numbers follow).
fn event(p: &Printed) -> Option<Event> {
    let n = |k: usize| -> Option<usize> { usize::try_from(*p.numbers.get(k)?).ok() };
    Some(match p.kind {
        EventKind::Issue => Event::Issue {
            m: n(0)?,
            s: n(1)?,
            e: n(2)?,
        },
        EventKind::Done => Event::Done { m: n(0)?, s: n(1)? },
        EventKind::Complete => Event::Complete { m: n(0)?, s: n(1)? },
        EventKind::Deliver => Event::Deliver {
            from: n(0)?,
            to: n(1)?,
            fields: p.copy.clone(),
        },
        EventKind::Hear => Event::Hear {
            m: n(0)?,
            fields: p.copy.clone(),
        },
        EventKind::Record => Event::Record { m: n(0)?, s: n(1)? },
        EventKind::Capture => Event::Capture {
            slot: n(0)?,
            from: n(1)?,
            to: n(2)?,
        },
        EventKind::Late => Event::Late {
            slot: n(0)?,
            from: n(1)?,
            to: n(2)?,
        },
        EventKind::Copy => Event::Copy {
            m: n(0)?,
            fields: p.copy.clone(),
        },
        EventKind::Reset => Event::Reset { m: n(0)? },
        EventKind::End => Event::End { m: n(0)? },
        EventKind::Violation => Event::Violation {
            property: p.words.first()?.clone(),
            m: n(0)?,
            s: n(1)?,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_are_read_and_spins_own_lines_skipped() {
        let output = "ltl finishes: <> ([] (x))\n  @issue 2 1 0\n@deliver 0 1 4 1 0\n@bogus 1\n<<<<<START OF CYCLE>>>>>\n@violation S1 2 1\nspin: trail ends after 3 steps\n";
        assert_eq!(
            parse_events(output),
            vec![
                Event::Issue { m: 2, s: 1, e: 0 },
                Event::Deliver {
                    from: 0,
                    to: 1,
                    fields: vec![4, 1, 0]
                },
                Event::CycleStart,
                Event::Violation {
                    property: "S1".into(),
                    m: 2,
                    s: 1
                },
            ]
        );
    }

    /// Every event the writers can print, with every field an expression (spin prints a
    /// number for each) or a known value, comes back as the event of its kind.
    #[test]
    fn every_event_the_writers_print_is_read_back() {
        use dynarole_codegen::trail_events::{expr, printf, value, Field, EVENTS};
        for spec in EVENTS {
            let mut args = Vec::new();
            let mut printed = format!("@{}", spec.name);
            for (k, field) in spec.fields.iter().enumerate() {
                match field {
                    Field::Number(name) => {
                        args.push(if k % 2 == 0 {
                            expr(*name)
                        } else {
                            value(k + 1)
                        });
                    }
                    Field::Word(_) => args.push(value("S2")),
                }
                printed.push_str(&match field {
                    Field::Number(_) => format!(" {}", k + 1),
                    Field::Word(_) => " S2".to_string(),
                });
            }
            if spec.copy {
                args.extend([expr("x"), expr("y")]);
                printed.push_str(" 7 8");
            }
            let statement = printf(spec.kind, &args);
            assert!(statement.starts_with(&format!("printf(\"@{} ", spec.name)));
            // What spin prints for the printf: each %d replaced by the number the test chose.
            let events = parse_events(&format!("spin: noise\n{printed}\n"));
            assert_eq!(events.len(), 1, "{printed}");
            let back = parse_printed(&printed).map(|p| p.kind);
            assert_eq!(back, Some(spec.kind), "{printed}");
            let numbers = spec.fields.iter().filter(|f| matches!(f, Field::Number(_)));
            assert_eq!(
                parse_printed(&printed).map(|p| p.numbers.len()),
                Some(numbers.count())
            );
        }
    }

    #[test]
    fn a_line_without_its_fields_is_not_an_event() {
        assert_eq!(parse_events("@issue 1 2\n@done x 1\n@reset 1 2\n"), vec![]);
    }
}
