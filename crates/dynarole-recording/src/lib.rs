//! dynarole-recording: the one format the viewer reads (`docs/viewer.md`): a run's start
//! configuration, its trace, every operation's motion as the world model computed it, and
//! keyframes of every module's pose. Built by the simulator, by replay and by verify's
//! counterexample through [`Builder`]; poses come from `dynarole-world` only.

mod builder;
mod format;
mod model_step;
mod pose;

pub use builder::{Builder, Source};
pub use format::*;
pub use model_step::ModelStep;
pub use pose::{poses_at, settled_at};
