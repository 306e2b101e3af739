//! What a run reports: outcome, times, packets, per-module figures, violations and refused
//! operations, as data (serialised by `--json`) and as a human summary.

use dynarole_world::Configuration;
use serde::{Serialize, Serializer};
use std::fmt::Write;

/// Width of the trace's state column (padded; a longer description widens its line).
pub const STATE_COLUMN: usize = 28;

/// Whole-run counters.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Counters {
    /// Events the engine processed (popped from its queue: steps, including those a power
    /// cycle cancelled, arrivals, operation completions, faults).
    pub events: u64,
    /// Calls of `dr_hal_broadcast`.
    pub broadcasts: u64,
    /// Transmissions (one per channel a broadcast goes out on), counted at the sender.
    pub packets_sent: u64,
    pub delivered: u64,
    pub lost: u64,
    pub dead: u64,
    pub collided: u64,
    pub blocked: u64,
    /// Dropped because a turn in progress broke the link.
    pub broken: u64,
    /// Dropped because the receiver was powered off.
    pub off: u64,
    /// Not sent: the channel's send buffer was full.
    pub overflow: u64,
    pub ops_started: u64,
    pub ops_reissued: u64,
    pub ops_refused: u64,
    pub ops_unknown: u64,
    pub resets: u64,
    pub power_cycles: u64,
    /// Packets of another robot injected by the scenario (`foreign`).
    pub foreign: u64,
    /// Attempts failed by an injected operation fault (`[faults]`, `[[stuck]]`); left out of
    /// `--json` when 0, as in every run without them.
    #[serde(skip_serializing_if = "is_zero")]
    pub ops_failed: u64,
    /// Modules that died in place (`[[dead]]`); left out of `--json` when 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub deaths: u64,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

impl Counters {
    /// Packets sent that did not reach the protocol.
    pub fn dropped(&self) -> u64 {
        self.lost + self.dead + self.collided + self.blocked + self.broken + self.off
    }
}

/// A check that failed: S1 (started before its dependencies were done), S2 (re-issued after
/// a dependent started) or S3 (end declared before every operation was done).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Violation {
    pub check: String,
    pub time_ms: f64,
    pub module: String,
    pub statement: usize,
    pub text: String,
    /// The other statements involved (missing dependencies, started dependents, open ones).
    pub involved: Vec<usize>,
    pub message: String,
}

/// An operation the world refused.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Refusal {
    pub time_ms: f64,
    pub module: String,
    pub statement: usize,
    pub text: String,
    pub reason: String,
}

/// A module whose failure policy gave up: an operation of its failed and was not (or no more)
/// retried, so it starts nothing more (`DR_END_STOPPED`, runtime/dr_module.h).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stop {
    pub time_ms: f64,
    pub module: String,
    /// The statements of its batch that had failed.
    pub statements: Vec<usize>,
    /// Their text, `;`-separated.
    pub text: String,
}

/// How a run ended, in one word (`--json`'s `"outcome"`, the campaign's `runs.csv` column):
/// decided here only.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Outcome {
    /// The goal was reached with every check passed.
    Success,
    /// A module's failure policy gave up and it is still stopped at the end: the robot stays
    /// where the failure left it.
    Stopped,
    /// No module declared the end before the timeout.
    Timeout,
    /// The end was declared, but the final configuration is not the expected one.
    WrongConfiguration,
    /// An S1, S2 or S3 violation, or a clash (whatever else happened).
    Violation,
    /// The end was declared with statements not done and no violation (not expected).
    Incomplete,
}

impl Outcome {
    /// The outcome of a report whose other fields are final.
    pub fn of(report: &Report) -> Outcome {
        if report.success {
            Outcome::Success
        } else if !report.violations.is_empty() {
            Outcome::Violation
        } else if !report.stopped.is_empty() {
            Outcome::Stopped
        } else if report.completion_ms.is_none() {
            Outcome::Timeout
        } else if report.configuration_matches == Some(false) {
            Outcome::WrongConfiguration
        } else {
            Outcome::Incomplete
        }
    }

    /// Its name in `--json` and in `runs.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Success => "success",
            Outcome::Stopped => "stopped",
            Outcome::Timeout => "timeout",
            Outcome::WrongConfiguration => "wrong-configuration",
            Outcome::Violation => "violation",
            Outcome::Incomplete => "incomplete",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModuleReport {
    pub name: String,
    pub id: u16,
    /// The address the module's runtime found (255: none, 254: several).
    pub address: u8,
    pub packets_sent: u64,
    pub packets_received: u64,
    pub packets_dropped: u64,
    pub operations: u64,
    pub resets: u64,
    pub power_cycles: u64,
    pub finished_ms: Option<f64>,
}

/// The result of one run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    pub success: bool,
    /// How the run ended ([`Outcome`]).
    pub outcome: Outcome,
    /// Whether the final configuration is the start configuration (the robot is back where
    /// it began, or never moved).
    pub final_matches_start: bool,
    /// The modules stopped at the end by their failure policy (empty when none).
    pub stopped: Vec<Stop>,
    /// Why the goal was not reached (empty on success).
    pub failures: Vec<String>,
    pub seed: u64,
    pub protocol: String,
    pub preset: String,
    /// When the first module declared the end (the original simulator's success time).
    pub completion_ms: Option<f64>,
    /// When the last module declared the end.
    pub all_finished_ms: Option<f64>,
    /// The modules that never declared the end, each with whether it could have heard it
    /// (said on success too: a run that ends with a module cut off is not silent about it).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub never_ended: Vec<String>,
    /// Simulated time at which the run stopped.
    pub end_ms: f64,
    pub statements: usize,
    pub statements_done: usize,
    pub counters: Counters,
    pub violations: Vec<Violation>,
    pub refusals: Vec<Refusal>,
    pub modules: Vec<ModuleReport>,
    /// The most the first starts of one synchronous group's turns were apart, in ms (the
    /// groups all of whose turns started; `None` for a program without synchronous groups).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub synchronous_spread_ms: Option<f64>,
    /// Whether the final configuration equals the expected one (`None`: nothing expected).
    pub configuration_matches: Option<bool>,
    pub difference: Option<String>,
    /// The final configuration (serialised in the data-file JSON format; `null` for a robot
    /// with no file format). Kept as the world model's own value, not as JSON: a JSON tree
    /// costs several times more memory per module.
    #[serde(serialize_with = "configuration_json")]
    pub final_configuration: Option<Configuration>,
    #[serde(skip)]
    pub trace: Option<String>,
    /// The trace as data, for the viewer's recording (`Simulator::recording`).
    #[serde(skip)]
    pub recorded: Option<crate::recorded::Recorded>,
}

/// A configuration as the JSON object of its data file, made only when a report is serialised.
fn configuration_json<S: Serializer>(c: &Option<Configuration>, s: S) -> Result<S::Ok, S::Error> {
    let value: serde_json::Value = match c {
        Some(c) => serde_json::from_str(&c.to_json_string()).map_err(serde::ser::Error::custom)?,
        None => serde_json::Value::Null,
    };
    value.serialize(s)
}

impl Report {
    /// Violations of one check.
    pub fn count(&self, check: &str) -> usize {
        self.violations.iter().filter(|v| v.check == check).count()
    }

    /// A few lines for people.
    pub fn summary(&self) -> String {
        self.summary_with(false)
    }

    /// The summary with one line on each check (S1, S2, S3) under the line that counts
    /// them: for the first report a reader sees.
    pub fn summary_explained(&self) -> String {
        self.summary_with(true)
    }

    /// The event trace as a file: a header naming the columns and the events, then the lines.
    pub fn trace_file(&self) -> Option<String> {
        self.trace
            .as_ref()
            .map(|lines| format!("{}{lines}", trace_header()))
    }

    fn summary_with(&self, explain_checks: bool) -> String {
        let mut out = String::new();
        let verdict = if self.success { "SUCCESS" } else { "FAILURE" };
        let when = self
            .completion_ms
            .map_or("never".to_string(), |t| format!("at {:.3} s", t / 1000.0));
        let _ = writeln!(
            out,
            "{verdict}: {} protocol, {} preset, seed {}: end declared {when}; {} of {} statements done; run stopped at {:.3} s",
            self.protocol,
            self.preset,
            self.seed,
            self.statements_done,
            self.statements,
            self.end_ms / 1000.0
        );
        for f in &self.failures {
            let _ = writeln!(out, "  not reached: {f}");
        }
        for m in &self.never_ended {
            let _ = writeln!(out, "  note: {m}");
        }
        for stop in &self.stopped {
            let _ = writeln!(
                out,
                "  stopped at {:.3} s on {}: #{:?} {} failed and its failure policy gave up",
                stop.time_ms / 1000.0,
                stop.module,
                stop.statements,
                stop.text
            );
        }
        self.packets_line(&mut out);
        let c = &self.counters;
        let _ = writeln!(
            out,
            "  operations: {} started, {} re-issued, {} refused, {} unknown; resets {}, power cycles {}",
            c.ops_started, c.ops_reissued, c.ops_refused, c.ops_unknown, c.resets, c.power_cycles
        );
        // Only runs with operation faults say them (every other summary is unchanged).
        if c.ops_failed + c.deaths > 0 {
            let _ = writeln!(
                out,
                "  operation faults: {} attempts failed, {} modules died",
                c.ops_failed, c.deaths
            );
        }
        // Clashes are named only in runs that have them (every other summary is unchanged).
        let clashes = match self.count("clash") {
            0 => String::new(),
            n => format!(", clash {n}"),
        };
        let _ = writeln!(
            out,
            "  violations: S1 {}, S2 {}, S3 {}{clashes}",
            self.count("S1"),
            self.count("S2"),
            self.count("S3")
        );
        if let Some(spread) = self.synchronous_spread_ms {
            let _ = writeln!(
                out,
                "  synchronous groups: their turns started at most {spread:.3} ms apart"
            );
        }
        if explain_checks {
            out.push_str(CHECKS_EXPLAINED);
        }
        for v in &self.violations {
            let _ = writeln!(
                out,
                "    {} at {:.3} s on {}: #{} {} {} (involved: {:?})",
                v.check,
                v.time_ms / 1000.0,
                v.module,
                v.statement,
                v.text,
                v.message,
                v.involved
            );
        }
        // A refused operation is usually retried: one line per statement and reason, with how
        // often and over which interval, rather than one per attempt.
        let mut shown: Vec<(usize, &str)> = Vec::new();
        for r in &self.refusals {
            if shown.contains(&(r.statement, r.reason.as_str())) {
                continue;
            }
            shown.push((r.statement, r.reason.as_str()));
            let same: Vec<&Refusal> = self
                .refusals
                .iter()
                .filter(|o| o.statement == r.statement && o.reason == r.reason)
                .collect();
            let last = same.last().map_or(r.time_ms, |o| o.time_ms);
            let times = if same.len() > 1 {
                format!(
                    "{} times from {:.3} s to {:.3} s",
                    same.len(),
                    r.time_ms / 1000.0,
                    last / 1000.0
                )
            } else {
                format!("at {:.3} s", r.time_ms / 1000.0)
            };
            let _ = writeln!(
                out,
                "  refused {times} on {}: #{} {}: {}",
                r.module, r.statement, r.text, r.reason
            );
        }
        self.modules_table(&mut out);
        out
    }

    fn packets_line(&self, out: &mut String) {
        let c = &self.counters;
        let _ = writeln!(
            out,
            "  packets: {} sent, {} delivered, {} dropped (lost {}, dead link {}, collision {}, blocked {}, turn {}, off {}), {} overflow",
            c.packets_sent,
            c.delivered,
            c.dropped(),
            c.lost,
            c.dead,
            c.collided,
            c.blocked,
            c.broken,
            c.off,
            c.overflow
        );
    }

    fn modules_table(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "  {:<6} {:>4} {:>4} {:>7} {:>7} {:>7} {:>4} {:>6} {:>10}",
            "module", "id", "addr", "sent", "recv", "dropped", "ops", "resets", "end (s)"
        );
        for m in &self.modules {
            let end = m
                .finished_ms
                .map_or("-".to_string(), |t| format!("{:.3}", t / 1000.0));
            let _ = writeln!(
                out,
                "  {:<6} {:>4} {:>4} {:>7} {:>7} {:>7} {:>4} {:>6} {:>10}",
                m.name,
                m.id,
                m.address,
                m.packets_sent,
                m.packets_received,
                m.packets_dropped,
                m.operations,
                m.resets,
                end
            );
        }
    }
}

/// What S1, S2 and S3 check (docs/simulator.md), one line each.
const CHECKS_EXPLAINED: &str = concat!(
    "    S1: no statement started before every statement it depends on was physically done\n",
    "    S2: no statement re-issued after a statement that depends on it had started\n",
    "    S3: no module declared the end before every operation was done\n",
);

/// The trace's header: the column titles, aligned with the lines `State::log` writes (time in
/// simulated milliseconds, module, event, the module's protocol state, detail), and the events.
pub(crate) fn trace_header() -> String {
    format!(
        "{:<12} {:<6} {:<10} {:<width$} {}\n{}",
        "#    time ms",
        "module",
        "event",
        "state",
        "detail",
        "# time: simulated milliseconds since the start; state: the module's protocol state as its\n\
         #   runtime describes it (`-`: none yet); detail: the statement, or the packet's link.\n\
         # events: power-on, power-off, reset, start, resume, retry, reissue, done, interrupt,\n\
         #   refused, unknown-op, finished (the module declares the end), S1/S2/S3 (a violation),\n\
         #   clash (two turns running at once bring modules within the limit), timeout; a packet\n\
         #   that did not arrive: lost, dead-link, collision, blocked, broken (a turn broke the\n\
         #   link), off (the receiver was off).\n",
        width = STATE_COLUMN
    )
}

#[cfg(test)]
mod tests {
    use super::trace_header;
    use dynarole_recording::EVENTS;
    use std::collections::BTreeSet;

    /// The header's words naming events: after `events:`, outside parentheses.
    fn header_events() -> BTreeSet<String> {
        let header = trace_header();
        let list = header
            .split("events:")
            .nth(1)
            .expect("the header lists events");
        let mut depth = 0;
        let bare: String = list
            .chars()
            .map(|c| {
                depth += i32::from(c == '(') - i32::from(c == ')');
                if depth > 0 || c == ')' {
                    ' '
                } else {
                    c
                }
            })
            .collect();
        bare.split(|c: char| !(c.is_alphanumeric() || c == '-'))
            .map(str::to_string)
            .collect()
    }

    /// The header's text is fixed (traces compare byte for byte); the vocabulary says which
    /// events it names, and this keeps the two equal.
    #[test]
    fn the_header_names_exactly_the_events_the_vocabulary_puts_there() {
        let named = header_events();
        for e in EVENTS {
            assert_eq!(named.contains(e.name), e.in_header, "{}", e.name);
        }
    }
}
