//! The simulator's memory per module: the heap a run needs on the scale benchmark's grid
//! (`benches/scale.rs`), counted by a counting global allocator, stays under its budget, so
//! that the figure cannot grow back silently (bytes are asserted, never time).

mod common;

use common::counting::Counting;
use common::grid::{square, structure_json, SOURCE};
use dynarole_codegen::Protocol;
use dynarole_sim::{Preset, Run, Scenario};
use dynarole_world::Configuration;

#[global_allocator]
static HEAP: Counting = Counting::new();

/// Modules of the grid: enough for the per-module part to dominate the fixed costs.
const MODULES: usize = 3_000;
/// Heap bytes per module a run may need at its peak, the world model included (issue 15's
/// goal: under 1 KB of simulator memory per module; 893 B when this was written).
const BUDGET: usize = 1_024;

#[test]
fn a_run_needs_little_heap_per_module() {
    let sim = common::simulator(SOURCE, &["spread"], Protocol::Lattice);
    let start = Configuration::from_json_str(&structure_json("grid", &square(MODULES)))
        .expect("valid configuration");
    let mut scenario = Scenario::default();
    scenario.network.preset = Preset::Ussr;
    scenario.timeout_ms = 600_000;
    sim.module_context_bytes(Preset::Ussr).expect("builds");
    let base = HEAP.current();
    let copy = start.clone();
    let config = HEAP.current() - base;
    drop(copy);
    HEAP.reset_peak();
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
    let kept = HEAP.current() - base;
    assert!(report.success, "{:?}", report.failures);
    let per = |b: usize| b / MODULES;
    eprintln!(
        "per module: peak {} B, report {} B, configuration {} B, events {}",
        per(peak),
        per(kept),
        per(config),
        report.counters.events
    );
    assert!(per(peak) < BUDGET, "{} B per module at the peak", per(peak));
}
