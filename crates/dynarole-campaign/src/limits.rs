//! The campaign's size limit, below both the file's checks (`spec.rs`: the seeds) and the
//! planner (`plan.rs`: points x protocols x seeds).

/// Most runs a campaign may plan (points x protocols x seeds). A run takes a fraction of a
/// second at best, so a million is already days of computing; past it the file is refused
/// before anything is planned.
pub const MAX_RUNS: u64 = 1_000_000;
