//! Back-ends of the dynarole compiler: from the IR (`dynarole_core::lower::Ir`) to a
//! self-contained directory of portable C (runtime included) for each protocol, and to a
//! Promela model of it (lattice and paper protocols) for the spin model checker.
//!
//! **Architecture invariant**: every back-end is generated from the same IR, so the C that
//! runs on the modules and the models that check it cannot drift apart.

mod c;
pub mod choice;
mod limits;
mod nesc;
mod options;
mod paper;
mod predicate;
mod promela;
mod protocol;
mod runtime;
mod token;

pub use c::{generate_c, generate_nesc, Generated};
pub use choice::{Choice, UnknownName};
pub use limits::target_limits;
pub use nesc::nesc_files;
pub use options::CompileOptions;
pub use promela::events as trail_events;
pub use promela::{
    generate_compositional, generate_promela, liveness_graph, Fault, LivenessGraph, Model,
    ModelOptions, Topology, TopologyLink, TopologyModule, MAX_MODEL_MODULES, MAX_MODEL_WINDOW,
};
pub use protocol::default_failure_policy;
pub use protocol::{
    Dissemination, GroupRun, Growth, Modelled, OnFailure, PaperMerge, Payload, Protocol,
    ProtocolInfo, Setting, TokenRetries, Variant, MAX_RETRIES, PROTOCOLS,
};
pub use runtime::{synchronous_delay_ms, warning_flags};
pub use token::TokenRoutes;
