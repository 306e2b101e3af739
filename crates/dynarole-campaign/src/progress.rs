//! How a campaign tells its progress: to an observer it is handed (the CLI draws a bar or
//! prints lines on stderr), so that the library never writes to the terminal itself.

/// Told how the runs of a campaign (or of a shard) advance; it decides how, and whether, to
/// show them.
pub trait Progress: Sync {
    /// The runs of `label` (`campaign`, `shard 3/8`) start: `total` `what` in all, `before`
    /// of them done earlier (a resumed campaign or shard).
    fn started(&mut self, _label: &str, _before: u64, _total: u64, _what: &str) {}
    /// One more done; called from any worker thread.
    fn advanced(&self) {}
    /// They stopped: all done, or an error follows.
    fn finished(&mut self) {}
    /// Whether the caller wants the runs to stop (an interrupt): asked before each run, from
    /// any worker thread; the runs already recorded stay, so the campaign resumes from them.
    fn stop_requested(&self) -> bool {
        false
    }
}

/// Progress told to nobody (tests, and callers that show none).
pub struct Quiet;

impl Progress for Quiet {}
