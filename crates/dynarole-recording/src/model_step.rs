//! The steps of a run on the model, as the tools that make them (replays, counterexamples)
//! hand them to the recording of a model run.

/// One step of a run on the model (a replay, or a model checker's counterexample), with
/// module names as in the configuration; `dynarole_sim::ModelRecording` turns them into a recording.
#[derive(Clone, Debug, PartialEq)]
pub enum ModelStep {
    /// The module does the statement's operation, start to end (replay).
    Operation(usize, String),
    /// The module issues the statement's operation (a counterexample's trail)...
    Issue(usize, String),
    /// ... and it completes physically.
    Done(usize, String),
    Reset(String),
    /// The module's copy of the shared protocol state is now this (the state panel).
    Copy(String, String),
    /// A property broken at this step: its name and what the trail explains.
    Violation(String, String),
}
