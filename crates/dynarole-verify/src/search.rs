//! What a search is and what pan said of it: below the runner (`spin.rs`), the report
//! (`report.rs`) and the explanation (`explain.rs`), which all speak of them.

/// Safety (assertions S1-S3) or liveness (the LTL formula `finishes`, weak fairness).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Check {
    Safety,
    Liveness,
}

/// What one pan run said.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PanResult {
    pub errors: u64,
    pub states: u64,
    pub transitions: u64,
    pub depth: u64,
    pub seconds: f64,
    pub memory_mb: f64,
    pub out_of_memory: bool,
    pub depth_limited: bool,
    pub timed_out: bool,
    pub bitstate: bool,
    /// The search was bounded in depth (`Limits::depth`).
    pub bounded: bool,
    /// pan printed its statistics (a search that ran, whatever it found).
    pub reported: bool,
    /// The first line of pan's error report, e.g. `pan:1: assertion violated false (at depth 17)`.
    pub error_line: Option<String>,
}

impl PanResult {
    /// The search covered every reachable state.
    pub fn complete(&self) -> bool {
        !self.out_of_memory && !self.depth_limited && !self.timed_out && !self.bitstate
    }
}
