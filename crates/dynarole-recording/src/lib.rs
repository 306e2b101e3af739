//! dynarole-recording: the one format the viewer reads (`docs/viewer.md`): a run's start
//! configuration, its trace, every operation's motion as the world model computed it, and
//! keyframes of every module's pose. Built by the simulator, by replay and by verify's
//! counterexample through [`Builder`]; poses come from `dynarole-world` only. The trace's
//! events are named once, here ([`TraceEvent`], `trace_event.rs`): the simulator depends on
//! this crate and the viewer reads it, so both writers and readers share one table.

mod builder;
mod format;
mod model_step;
mod pose;
mod trace_event;

pub use builder::{Builder, Source};
pub use format::*;
pub use model_step::ModelStep;
pub use pose::{poses_at, settled_at};
pub use trace_event::{
    markdown_table, unknown_event, vocabulary_json, EventSpec, Mark, MarkSpec, Operation,
    TraceEvent, EVENTS, MARKS,
};
