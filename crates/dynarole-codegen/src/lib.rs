//! Back-ends of the dynarole compiler: from the IR (`dynarole_core::lower::Ir`) to a
//! self-contained directory of portable C (runtime included) for each protocol.
//!
//! **Architecture invariant**: every back-end is generated from the same IR, so the C that
//! runs on the modules and the models that check it cannot drift apart.

mod c;
mod nesc;
mod paper;
mod predicate;
mod runtime;
mod token;

pub use c::{generate_c, generate_nesc, CompileOptions, Generated, PaperMerge, Protocol};
pub use token::{TokenRetries, TokenRoutes};
