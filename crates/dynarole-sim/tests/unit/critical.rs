//! Unit tests of `src/critical.rs`, kept beside the integration tests
//! because they read the robots' example files.

use crate::{Simulator, USSR_TIMING};
use dynarole_codegen::{CompileOptions, Protocol};
use dynarole_core::{analyze, parse};

fn simulator(source: &str) -> Simulator {
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let plans = vec![program.expand("s").expect("sequence s")];
    let options = CompileOptions {
        protocol: Protocol::Lattice,
        name: "critical".into(),
        ..CompileOptions::default()
    };
    Simulator::new(&program, &plans, &options).expect("compiles")
}

#[test]
fn the_heaviest_chain_and_its_handovers() {
    // #0 (M1, 2 s) -> #1 (M1, 3 s) and #2 (M0, half turn 0.86 s) -> #3 (M0, 0.86 s):
    // 0-1-3 weighs 5.86 s with one hand-over (M1 to M0); 0-2-3 only 3.72 s.
    let sim = simulator(
        "robot atron;\nsequence s {\n    M1.Connector[2].retract();\n    \
         M1.Connector[2].extend() &\n    M0.Joint.rotateFromToBy(0, 216, true, 150);\n    \
         M0.Joint.rotateFromToBy(216, 0, false, 150);\n}\n",
    );
    let path = sim.critical_path(&USSR_TIMING);
    assert_eq!(path.statements, vec![0, 1, 3]);
    assert_eq!(path.duration_ms, 2000 + 3000 + 860);
    assert_eq!(path.handovers, 1);
    assert_eq!(path.with_handovers(100), 5960);
}

#[test]
fn rotate_to_starts_where_the_previous_turn_ended_and_ties_take_more_handovers() {
    // #1 turns back from 108 (where #0 ended): a quarter, 0.55 s. #2 (M1) and #3 (M0)
    // weigh the same after #1; #4 depends on both and is M0's: the chain through #2
    // (a hand-over M0 to M1 and back) is preferred to the one through #3 (none).
    let sim = simulator(
        "robot atron;\nsequence s {\n    M0.Joint.rotateFromToBy(0, 108, true, 150);\n    \
         M0.Joint.rotateToBy(0, false, 150);\n    M1.Connector[2].retract() &\n    \
         M0.Connector[4].retract();\n    M0.Connector[4].extend();\n}\n",
    );
    let path = sim.critical_path(&USSR_TIMING);
    assert_eq!(path.duration_ms, 550 + 550 + 2000 + 3000);
    assert_eq!(path.statements, vec![0, 1, 2, 4]);
    assert_eq!(path.handovers, 2);
}

#[test]
fn one_at_a_time_adds_a_modules_own_order() {
    // #1 and #2 are M1's, joined by `&`: the meaning lets them overlap (3 s), the runtime
    // runs them one after the other (2 + 3 s), then M0's turn (a hand-over).
    let sim = simulator(
        "robot atron;\nsequence s {\n    M1.Connector[2].retract();\n    \
         M1.Connector[4].retract() &\n    M1.Connector[2].extend();\n    \
         M0.Joint.rotateFromToBy(0, 108, true, 150);\n}\n",
    );
    let meaning = sim.critical_path(&USSR_TIMING);
    assert_eq!(meaning.duration_ms, 2000 + 3000 + 550);
    let runtime = sim.critical_path_one_at_a_time(&USSR_TIMING);
    assert_eq!(runtime.duration_ms, 2000 + 2000 + 3000 + 550);
    assert_eq!(runtime.statements, vec![0, 1, 2, 3]);
    assert_eq!(runtime.handovers, 1);
}

#[test]
fn any_weights() {
    // With every statement weighing 1: three statements on the longest chain.
    let sim = simulator(
        "robot atron;\nsequence s {\n    M1.Connector[2].retract();\n    \
         M1.Connector[2].extend() &\n    M0.Joint.rotateFromToBy(0, 216, true, 150);\n    \
         M0.Joint.rotateFromToBy(216, 0, false, 150);\n}\n",
    );
    let path = super::chain(&sim.sequence.ir, super::Order::Meaning, |_| 1);
    assert_eq!(path.duration_ms, 3);
    assert_eq!(path.statements.len(), 3);
    assert_eq!(path.handovers, 1);
}

#[test]
fn a_synchronous_group_waits_for_the_countdown_and_moves_at_its_longest_members_pace() {
    // #0 retracts (2 s); then M3's quarter turn and M4's half turn start together after the
    // runtime's countdown for two members, and both take the half turn's 0.86 s.
    let sim = simulator(
        "robot atron;\nsequence s {\n    M3.Connector[0].retract();\n    sync {\n        \
         M3.Joint.rotateFromToBy(0, 108, true, 150) &\n        \
         M4.Joint.rotateFromToBy(0, 216, false, 150);\n    };\n}\n",
    );
    let countdown = dynarole_codegen::synchronous_delay_ms(2);
    assert!(countdown > 0);
    let path = sim.critical_path(&USSR_TIMING);
    assert_eq!(path.duration_ms, 2000 + countdown + 860);
    assert_eq!(path.statements.len(), 2);
}
