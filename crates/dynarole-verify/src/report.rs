//! The report of a verification: the header facts, one entry per search with its verdict
//! and figures, the explained counterexample, and the overall verdict; each part renders as
//! the lines `dynarole verify` prints. An [`Observer`] receives the entries as they come and
//! the progress of the tools.

use crate::explain::Counterexample;
use crate::search::{Check, PanResult};
use std::fmt;

/// Whether a property was proved, refuted, or neither.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Verified,
    Violated,
    /// The search did not cover every state (or L could not be checked).
    Inconclusive,
}

/// What runs in a check's tools now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// `spin -a`.
    Generating,
    /// `cc` on pan.c.
    Compiling,
    /// pan.
    Searching,
}

impl fmt::Display for Phase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Phase::Generating => "generating the verifier",
            Phase::Compiling => "compiling the verifier",
            Phase::Searching => "searching",
        })
    }
}

/// Told what a verification finds while it runs (every method does nothing unless given).
pub trait Observer {
    /// The facts of the model, before any search.
    fn header(&mut self, _header: &Header) {}
    /// An entry of the report, as soon as it is known.
    fn entry(&mut self, _entry: &Entry) {}
    /// The tools of the check named `label` start.
    fn begin(&mut self, _label: &str) {}
    /// What they do now (often: every few milliseconds); `search`: pan's (states, depth) so
    /// far, once it has reported them.
    fn progress(&mut self, _label: &str, _phase: Phase, _search: Option<(u64, u64)>) {}
    /// They stopped (a result, or a failure, follows).
    fn end(&mut self) {}
    /// Whether the caller asks the check to stop (looked at while a tool runs): the tool is
    /// then stopped and the check ends with [`crate::VerifyError::Interrupted`].
    fn stop_requested(&mut self) -> bool {
        false
    }
}

/// An observer told nothing.
pub struct Quiet;

impl Observer for Quiet {}

/// A check of one model: the full model's, or one module's compositional model's.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CheckName {
    /// The module whose compositional model is checked; `None`: the full model.
    pub module: Option<String>,
    pub check: Check,
}

impl fmt::Display for CheckName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(module) = &self.module {
            write!(f, "{module}: ")?;
        }
        f.write_str(match (self.check, self.module.is_some()) {
            (Check::Safety, false) => "S1, S2, S3 (safety)",
            (Check::Safety, true) => "S1, S2, S3, G1-G4 (safety)",
            (Check::Liveness, _) => "L (finishes, weak fairness)",
        })
    }
}

/// One entry of the report (each renders as one or more complete lines).
#[derive(Clone, Debug, PartialEq)]
pub enum Entry {
    /// The compositional method is used (one model per module).
    Compositional,
    /// Compositional method: the links that surely exist carry what L needs, so L is checked.
    LivenessLinks,
    /// Compositional method: L cannot be established from the links that surely exist (it is
    /// not checked); why.
    LivenessNotEstablished { why: String },
    /// A bounded search (runs of at most `steps` steps after `init`), tried first.
    Bounded {
        name: CheckName,
        steps: u64,
        result: PanResult,
    },
    /// The exhaustive search did not fit; a bitstate search follows.
    FallingBack { name: CheckName, result: PanResult },
    /// The verdict of a check, with the figures of the search that gave it.
    Checked {
        name: CheckName,
        verdict: Verdict,
        /// A bitstate search after the exhaustive one did not fit.
        fell_back: bool,
        result: PanResult,
    },
    /// The first violation, explained.
    Counterexample(Box<Counterexample>),
    /// Compositional method: a violation may be spurious.
    MaybeSpurious,
}

impl fmt::Display for Entry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Entry::Compositional => writeln!(f, "method: compositional, one model per module (its own logic; every other module reduced to its start rule; every packet any dependency-closed state the robot has reached: any loss, delay, duplication, reordering, on any topology)"),
            Entry::LivenessLinks => writeln!(f, "  links for L: in every stage, the dependencies of the next statement reach its module, and at the end every module is reached, over links that surely exist"),
            Entry::LivenessNotEstablished { why } => {
                writeln!(f, "  L: not established (NOT checked): {why}")
            }
            Entry::Bounded { name, steps, result } => writeln!(
                f,
                "  {name}: bounded search, runs of at most {steps} steps: {} — {}",
                bounded_outcome(result),
                describe(result)
            ),
            Entry::FallingBack { name, result } => writeln!(
                f,
                "  {name}: the state space is too large for an exhaustive search ({}); trying a bitstate search",
                describe(result)
            ),
            Entry::Checked {
                name,
                verdict,
                fell_back,
                result,
            } => writeln!(
                f,
                "  {name}: {} — {}",
                verdict_word(*verdict, *fell_back || result.bitstate),
                describe(result)
            ),
            Entry::Counterexample(cx) => write!(f, "\n{}", cx.text),
            Entry::MaybeSpurious => writeln!(f, "note: the compositional model over-approximates the network, so a violation may be spurious; check it with --method full"),
        }
    }
}

fn bounded_outcome(result: &PanResult) -> &'static str {
    if result.errors > 0 {
        "a violation"
    } else if result.complete() {
        "no violation, and no run reaches the bound"
    } else {
        "no violation within the bound"
    }
}

/// A check's verdict in words; `partial`: the search was a bitstate one.
fn verdict_word(verdict: Verdict, partial: bool) -> &'static str {
    match verdict {
        Verdict::Verified => "verified",
        Verdict::Violated => "VIOLATED",
        Verdict::Inconclusive if partial => "no violation found (NOT a proof)",
        Verdict::Inconclusive => "not finished (NOT a proof)",
    }
}

/// `exhaustive, 1234 states, depth 56, 0.10 s` and what limited the search.
pub fn describe(r: &PanResult) -> String {
    let mut parts = vec![
        if r.bitstate {
            "bitstate (partial)".to_string()
        } else if r.depth_limited || (r.bounded && !r.complete()) {
            "bounded (partial)".to_string()
        } else {
            "exhaustive".to_string()
        },
        // pan reports its figures every million states and at the end: a search stopped
        // before either has none to give.
        if r.states == 0 && !r.reported {
            "states not reported".to_string()
        } else {
            format!("{} states, depth {}", r.states, r.depth)
        },
        format!("{:.2} s", r.seconds),
    ];
    if r.memory_mb > 0.0 {
        parts.push(format!("{:.0} MB", r.memory_mb));
    }
    for (limited, what) in [
        (r.out_of_memory, "out of memory"),
        (r.timed_out, "time limit reached"),
        (r.depth_limited, "depth limit reached"),
    ] {
        if limited {
            parts.push(what.into());
        }
    }
    parts.join(", ")
}

/// The facts of the model checked and the bounds of its environment.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Header {
    /// The sequences, joined by ` + `.
    pub name: String,
    /// The configuration's name (its file).
    pub configuration: String,
    /// E.g. `lattice protocol` or `paper protocol, java merge`.
    pub protocol: String,
    pub statements: usize,
    pub modules: usize,
    pub links: usize,
    /// Links that exist in every stage (the others exist part of the time).
    pub links_throughout: usize,
    pub resets: u8,
    /// The only modules that may reset; empty: any.
    pub reset_only: Vec<String>,
    /// Packets in flight delivered late, at most; `None`: any number (compositional).
    pub late: Option<u8>,
    /// Lattice protocol: runs of the sequence; `None`: one run (paper protocol).
    pub epochs: Option<u16>,
    /// A deliberately broken variant of the protocol is checked.
    pub fault: bool,
}

impl fmt::Display for Header {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "verify {} on {} ({}): {} statements, {} modules, {} links ({} throughout, {} part of the time)",
            self.name,
            self.configuration,
            self.protocol,
            self.statements,
            self.modules,
            self.links,
            self.links_throughout,
            self.links - self.links_throughout
        )?;
        let who = if self.reset_only.is_empty() {
            String::new()
        } else {
            format!(" (of {} only)", self.reset_only.join(", "))
        };
        let late = match self.late {
            Some(k) => format!("at most {k} packet(s) in flight delivered late (and again)"),
            None => "any number of packets delivered late (and again)".to_string(),
        };
        let epochs = match self.epochs {
            Some(runs) => format!("{runs} run(s) of the sequence"),
            None => "one run".to_string(),
        };
        writeln!(
            f,
            "bounds: at most {} reset(s){who}; {late}; any packet may be lost; {epochs}; operations never fail",
            self.resets
        )?;
        if self.fault {
            writeln!(
                f,
                "note: a deliberately broken variant of the protocol is checked (--fault)"
            )?;
        }
        Ok(())
    }
}

/// What a verification found.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    pub header: Header,
    /// In the order they were found.
    pub entries: Vec<Entry>,
    /// Violated when any check is, verified when every check is, otherwise inconclusive.
    pub verdict: Verdict,
}

impl Report {
    /// The explained counterexample of the first violation, if any.
    pub fn counterexample(&self) -> Option<&Counterexample> {
        self.entries.iter().find_map(|e| match e {
            Entry::Counterexample(cx) => Some(cx.as_ref()),
            _ => None,
        })
    }
}

impl fmt::Display for Verdict {
    /// The last line of the report.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Verdict::Violated => writeln!(f, "result: violated"),
            Verdict::Verified => writeln!(f, "result: verified"),
            Verdict::Inconclusive => writeln!(
                f,
                "result: inconclusive (the search did not cover every state; see above)"
            ),
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.header)?;
        for entry in &self.entries {
            write!(f, "{entry}")?;
        }
        write!(f, "{}", self.verdict)
    }
}
