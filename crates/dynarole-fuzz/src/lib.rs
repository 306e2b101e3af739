//! Fuzz harness on the stable toolchain: each target (front end, checker, formatter and the
//! configuration, scenario, campaign and plugin loaders) is fed every file of its corpus in
//! `fuzz/corpus/<target>/`, then a bounded number of proptest-driven mutations of those files.
//!
//! Properties checked on every input: no panic; the result is `Ok` or a well-formed error
//! (diagnostic spans inside the source and on character boundaries, loader messages not
//! empty); error text bounded in size; round trips (formatting, configurations written back)
//! give what they started from. Everything runs in process, with
//! fixed seeds, so the same build gives the same cases. See `docs/fuzzing.md`.

pub mod corpus;
pub mod mutate;
mod runner;
pub mod targets;

pub use corpus::{Corpus, Entry};
pub use runner::{run_corpus, run_mutations, Settings, Summary};
pub use targets::{Context, Outcome, Target, SOURCE_WORDS};
