//! Model checking of compiled sequences with spin: the model of a robot (`model`), the spin
//! runner (`spin`), the checks and their report (`check`, `report`), and a counterexample
//! read back from its trail (`trail`) and told in the source's terms (`explain`).
//!
//! The library prints nothing and knows no exit code: `check::verify` returns a
//! [`report::Report`] and streams its entries and the progress of the tools to an
//! [`report::Observer`]; the command line prints them.

pub mod check;
pub mod explain;
pub mod model;
pub mod recorded;
pub mod report;
pub mod search;
pub mod spin;
pub mod trail;

pub use check::{header, verify, Source, VerifyOptions, BOUNDED_STEPS};
pub use explain::{explain, tell, Context, Counterexample, Explanation, Step};
pub use model::{build, modelled, BuildOptions, Built, Inputs, Method, Models, AUTO_FULL_MODULES};
pub use report::{describe, CheckName, Entry, Header, Observer, Phase, Quiet, Report, Verdict};
pub use spin::{check_tools, Check, Limits, PanResult, Progress};
pub use trail::{parse_events, Event};

use dynarole_core::Diagnostic;

/// Why a verification (or the building of a model) could not give a verdict.
#[derive(Debug)]
pub enum VerifyError {
    /// The source cannot be modelled as asked: diagnostics of the source file (bad input).
    Source(Vec<Diagnostic>),
    /// Bad input that is not in the source (the configuration, a module's roles).
    Input(String),
    /// Options that do not go together, or name nothing (bad usage).
    Usage(String),
    /// A failure of dynarole or of the tools it runs (spin, the C compiler, pan), or of the
    /// files it writes: never a verdict on the sequence.
    Internal(String),
    /// The observer asked the check to stop (`Observer::stop_requested`): no verdict.
    Interrupted,
}

impl std::fmt::Display for VerifyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            VerifyError::Source(diagnostics) => {
                write!(f, "{} problem(s) in the source", diagnostics.len())
            }
            VerifyError::Input(m) | VerifyError::Usage(m) | VerifyError::Internal(m) => {
                f.write_str(m)
            }
            VerifyError::Interrupted => {
                f.write_str("interrupted: the check stopped before a verdict")
            }
        }
    }
}

impl std::error::Error for VerifyError {}
