//! The simulator's memory grows linearly with the statements of the sequence: the heap that
//! `Simulator::new` and a run's setup need for 4n statements is about four times what n
//! need, never sixteen (a table of every statement's transitive dependents made it
//! quadratic: 1 GB at 10,000 statements). Bytes and their ratio are asserted, never time.

mod common;

use common::counting::Counting;
use common::{config, simulator, EIGHT};
use dynarole_codegen::Protocol;
use dynarole_sim::{Run, Scenario};
use std::fmt::Write;

#[global_allocator]
static HEAP: Counting = Counting::new();

/// Statements of the smaller program (the larger has four times as many).
const SMALL: usize = 1_000;
/// The largest ratio of the peaks accepted: linear growth gives at most 4 (fixed costs bring
/// it below), quadratic growth 16.
const MAX_RATIO: f64 = 6.0;

/// `n` statements on one module of the eight: M0's connector 0 retracted and extended in
/// turn, each statement waiting for the one before it (a chain, the worst case of a
/// transitive table), valid on `eight.json` and ending where it started.
fn pairs(n: usize) -> String {
    let mut source = String::from("robot atron;\nsequence s {\n");
    for k in 0..n {
        let op = if k % 2 == 0 { "retract" } else { "extend" };
        let _ = writeln!(source, "    M0.Connector[$CONNECTOR_0].{op}();");
    }
    source.push_str("}\n");
    source
}

/// The peak heap of compiling `n` statements for the simulator and of a short run of them
/// (setup, power-on and the first operations), over what was allocated before.
fn peak_bytes(n: usize) -> usize {
    let source = pairs(n);
    let start = config(EIGHT);
    let mut scenario = Scenario::default();
    scenario.timing.extend_ms = Some(10);
    scenario.timing.retract_ms = Some(10);
    scenario.timeout_ms = 500;
    let base = HEAP.current();
    HEAP.reset_peak();
    let sim = simulator(&source, &["s"], Protocol::Lattice);
    let report = sim
        .run(&Run {
            start: &start,
            expect: None,
            scenario: &scenario,
            seed: 1,
            trace: false,
        })
        .expect("runs");
    let peak = HEAP.peak() - base;
    assert!(report.statements_done > 0, "{}", report.summary());
    eprintln!(
        "{n} statements: peak {peak} B ({} B per statement)",
        peak / n
    );
    peak
}

/// One test: the allocator counts the whole process, so nothing else may run beside it.
#[test]
fn memory_grows_linearly_with_the_statements() {
    // A first run builds and caches what every later one shares (the C compiler's output
    // directory names, the robot registry): not counted in either peak.
    peak_bytes(10);
    let small = peak_bytes(SMALL);
    let large = peak_bytes(4 * SMALL);
    let ratio = large as f64 / small as f64;
    assert!(
        ratio < MAX_RATIO,
        "4x the statements took {ratio:.1}x the heap ({small} B, then {large} B)"
    );
}
