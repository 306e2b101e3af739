//! Unit tests of `src/sequence.rs`, kept beside the integration tests
//! because they read the robots' example files.

use dynarole_codegen::{CompileOptions, Protocol};
use dynarole_core::{analyze, parse};

/// The walk gives what the IR's table of transitive dependents gives, for every
/// statement of eight2car (groups, a chain, several modules) and its reverse.
#[test]
fn transitive_dependents_are_the_irs() {
    let source = include_str!("../../../../robots/atron/examples/eight2car.dr");
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let plans = ["eight2car", "car2eight"].map(|s| program.expand(s).expect("sequence"));
    let options = CompileOptions {
        protocol: Protocol::Lattice,
        name: "dependents".into(),
        ..CompileOptions::default()
    };
    let sim = crate::Simulator::new(&program, &plans, &options).expect("compiles");
    let table = sim.sequence.ir.dependents();
    for (s, expected) in table.iter().enumerate() {
        assert_eq!(&sim.sequence.transitive_dependents(s), expected, "#{s}");
    }
    assert!(table.iter().any(|d| d.len() > 1));
}
