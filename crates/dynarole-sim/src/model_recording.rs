//! The recording of a run on the model, with no network (`dynarole replay`, and `verify`'s
//! counterexamples): its steps in order, each operation taking its duration in the robot's
//! default timing preset ([`default_durations`]), so that the viewer plays it like a
//! simulation.

use crate::scenario::{default_durations, Durations};
use crate::sequence::OpKind;
use dynarole_core::check::ResolvedStatement;
use dynarole_recording::{Builder, ModelStep, Recording, TraceEvent};
use dynarole_replay::Assignment;

/// Why a model run could not be recorded.
#[derive(Debug)]
pub enum ModelRecordingError {
    /// The start configuration does not fit the statements (bad input).
    Input(String),
    /// A step names a module the configuration lacks (a bug of the caller).
    Internal(String),
}

impl std::fmt::Display for ModelRecordingError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModelRecordingError::Input(m) | ModelRecordingError::Internal(m) => f.write_str(m),
        }
    }
}

/// The recording of a run on the model (no network): the steps in order, each operation
/// taking its duration in the robot's default timing preset, so the page plays like a
/// simulation.
pub struct ModelRecording<'a> {
    pub kind: &'a str,
    pub title: &'a str,
    pub robot: &'a dynarole_core::robot::RobotApi,
    pub steps: &'a [ModelStep],
    pub statements: &'a [ResolvedStatement],
    pub start: &'a dynarole_world::Configuration,
    pub source: Option<dynarole_recording::Source<'a>>,
}

/// Pause between two steps of a model run (as a hand-over between modules would take).
const MODEL_GAP_MS: f64 = 100.0;

impl ModelRecording<'_> {
    /// The recording, with `notes` (the verdict, the explanation) as its summary.
    pub fn record(&self, notes: Vec<String>) -> Result<Recording, ModelRecordingError> {
        let texts: Vec<String> = self
            .statements
            .iter()
            .map(|s| s.describe(self.robot))
            .collect();
        let mut builder = Builder::new(
            self.kind,
            self.title,
            self.start,
            self.robot,
            self.statements,
            &texts,
            self.source,
        )
        .map_err(ModelRecordingError::Input)?;
        let kinds: Vec<OpKind> = (self.statements.iter())
            .map(|s| OpKind::of_statement(self.robot, s))
            .collect();
        let durations = default_durations(self.robot);
        let duration = |s: usize, path: Option<&dynarole_recording::Path>| -> f64 {
            let kind = kinds.get(s).copied().unwrap_or(OpKind::Other);
            nominal_ms(kind, &durations, path)
        };
        let view = dynarole_world::View::of(self.start);
        let index = |name: &str| {
            view.index(name).ok_or_else(|| {
                ModelRecordingError::Internal(format!("no module {name} in the configuration"))
            })
        };
        let mut now = 0.0;
        // Each module's last copy of the shared state, shown with each of its events.
        let mut states = vec!["-".to_string(); view.len()];
        // Per statement, when its operation was issued (a trail's completions follow later).
        let mut issued: Vec<(usize, f64, f64)> = Vec::new();
        for step in self.steps {
            match step {
                ModelStep::Operation(s, module) => {
                    let (end, _) = builder.operation(now, index(module)?, *s, &duration);
                    now = end + MODEL_GAP_MS;
                }
                ModelStep::Issue(s, module) => {
                    let label = format!("#{s} {}", texts.get(*s).map_or("", String::as_str));
                    let m = index(module)?;
                    builder.event(now, Some(m), TraceEvent::Start, &states[m], &label);
                    let path = builder.last_path();
                    issued.retain(|(x, _, _)| x != s);
                    issued.push((*s, now, duration(*s, path.as_ref())));
                    now += MODEL_GAP_MS;
                }
                ModelStep::Done(s, module) => {
                    if let Some((_, at, length)) = issued.iter().find(|(x, _, _)| x == s) {
                        now = now.max(at + length);
                    }
                    let label = format!("#{s} {}", texts.get(*s).map_or("", String::as_str));
                    let m = index(module)?;
                    builder.event(now, Some(m), TraceEvent::Done, &states[m], &label);
                    now += MODEL_GAP_MS;
                }
                ModelStep::Reset(module) => {
                    let m = index(module)?;
                    builder.event(now, Some(m), TraceEvent::Reset, &states[m], "");
                    now += MODEL_GAP_MS;
                }
                ModelStep::Copy(module, state) => {
                    let m = index(module)?;
                    state.clone_into(&mut states[m]);
                    builder.event(now, Some(m), TraceEvent::Copy, state, "");
                }
                ModelStep::Violation(module, what) => {
                    let m = index(module)?;
                    builder.event(now, Some(m), TraceEvent::Violation, &states[m], what);
                    now += MODEL_GAP_MS;
                }
            }
        }
        Ok(builder.finish(now, notes))
    }
}

/// The duration of an operation with `durations`, a turn's quarter turns read from the motion
/// the world gave it.
fn nominal_ms(kind: OpKind, durations: &Durations, path: Option<&dynarole_recording::Path>) -> f64 {
    let quarters = path.map_or(0, |p| (p.turned_deg() / 90.0).round() as u64);
    kind.nominal_ms(durations, quarters) as f64
}

/// A replay's steps: each statement (numbered in `statements`' order) done by the module of
/// its label; a label without a module (reported by the replay) does nothing.
pub fn replay_steps(statements: &[ResolvedStatement], assignment: &Assignment) -> Vec<ModelStep> {
    statements
        .iter()
        .enumerate()
        .filter_map(|(i, s)| Some(ModelStep::Operation(i, assignment.get(&s.label)?.clone())))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{nominal_ms, OpKind};
    use crate::USSR_TIMING;

    /// An operation's duration comes from the kind its plugin declares, as in a run: once a
    /// retract was told from an extend by the word `.retract(` in its text, so a plugin that
    /// names it otherwise, or an operation of kind `none`, played for the extend's 3 s.
    #[test]
    fn an_operation_lasts_as_its_kind_does_in_a_run() {
        let timing = USSR_TIMING;
        let ms = |kind| nominal_ms(kind, &timing, None);
        assert_eq!(ms(OpKind::Retract), timing.retract_ms as f64);
        assert_eq!(ms(OpKind::Extend), timing.extend_ms as f64);
        assert_eq!(ms(OpKind::Other), 0.0);
        // A turn with no motion (refused, or already at its angle) moves nothing.
        assert_eq!(ms(OpKind::Turn), 0.0);
        assert_ne!(timing.retract_ms, timing.extend_ms);
    }
}
