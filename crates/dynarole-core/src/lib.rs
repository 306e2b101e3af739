//! The dynarole language core: from `.dr` source text to checked, reversible sequences.
//!
//! Pipeline: `source → lexer::lex → tokens → parser::parse → ast::SourceFile →
//! check::analyze → check::Program → (reverse) → expand::Plan → lower::Ir`; `driver` runs it
//! for every caller (robot lookup, diagnostics in order, sequence selection, lowering).
//!
//! **Architecture invariant**: this crate does no IO. Sources, plugin texts and configurations
//! come in as strings; results and diagnostics go out as data.

#![deny(clippy::print_stdout, clippy::print_stderr)]

pub mod ast;
pub mod check;
pub mod diagnostic;
pub mod driver;
pub mod expand;
pub mod format;
pub mod lexer;
pub mod limits;
pub mod lower;
pub mod parser;
pub mod reverse;
pub mod robot;
pub mod span;
pub mod standalone;
pub mod suggest;
pub mod synchronous;
pub mod toml_error;

pub use check::{analyze, Program};
pub use diagnostic::{Diagnostic, DiagnosticKind, Severity};
pub use parser::{parse, Parsed};
pub use robot::{RobotApi, RobotRegistry};
pub use span::Span;

/// Parses and checks `source`: the syntax and checking diagnostics together, in source order.
pub fn check_source(source: &str, registry: &RobotRegistry) -> Vec<Diagnostic> {
    driver::analyze_all(&parse(source), registry).1
}
