//! The trail of a counterexample as events: what the model prints with `printf("@...")`
//! while spin replays the trail (`spin -T -t`), read back into values.

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

/// Reads the events from the output of `spin -T -t` (other lines are spin's own).
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
        events.extend(event(kind, &words));
    }
    events
}

/// The event `@kind words...`; `None` for a kind the model does not print.
fn event(kind: &str, words: &[&str]) -> Option<Event> {
    let n = |k: usize| -> usize { words.get(k).and_then(|w| w.parse().ok()).unwrap_or(0) };
    // The numbers from word k on (a copy of the shared state).
    let fields = |k: usize| -> Vec<i64> {
        words
            .iter()
            .skip(k)
            .filter_map(|w| w.parse().ok())
            .collect()
    };
    Some(match kind {
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
        _ => return None,
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
}
