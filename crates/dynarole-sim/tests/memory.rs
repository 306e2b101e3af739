//! The simulator's memory per module: the heap a run needs on the scale benchmark's grid
//! (`benches/scale.rs`), counted by a counting global allocator, stays under its budget, so
//! that the figure cannot grow back silently (bytes are asserted, never time).

mod common;

use common::counting::Counting;
use common::grid::{square, structure_json, SOURCE};
use dynarole_codegen::Protocol;
use dynarole_sim::{Preset, Run, Scenario, Simulator};
use dynarole_world::Configuration;

#[global_allocator]
static HEAP: Counting = Counting::new();

/// Modules of the grid: enough for the per-module part to dominate the fixed costs.
const MODULES: usize = 3_000;
/// Heap bytes per module a run may need at its peak, the world model included (issue 15's
/// goal: under 1 KB of simulator memory per module; about 900 B with either preset when this
/// was written).
const BUDGET: usize = 1_024;

/// One run of the grid with `preset`: its peak heap per module (over what was allocated
/// before it), after checking that it succeeded.
fn peak_per_module(sim: &Simulator, start: &Configuration, preset: Preset) -> usize {
    let mut scenario = Scenario::default();
    scenario.network.preset = dynarole_sim::PresetName::named(preset.name);
    scenario.timeout_ms = 600_000;
    sim.module_context_bytes(preset).expect("builds");
    let base = HEAP.current();
    HEAP.reset_peak();
    let report = sim
        .run(&Run {
            start,
            expect: None,
            scenario: &scenario,
            seed: 1,
            trace: false,
        })
        .expect("runs");
    let peak = HEAP.peak() - base;
    let kept = HEAP.current() - base;
    assert!(report.success, "{:?}", report.failures);
    eprintln!(
        "{}: per module, peak {} B, report {} B; events {}",
        preset.name,
        peak / MODULES,
        kept / MODULES,
        report.counters.events
    );
    peak / MODULES
}

/// Both presets in one test, one after the other: the allocator counts the whole process.
#[test]
fn a_run_needs_little_heap_per_module() {
    let sim = common::simulator(SOURCE, &["spread"], Protocol::Lattice);
    let start = dynarole_robots::read_configuration(&structure_json("grid", &square(MODULES)))
        .expect("valid configuration");
    for preset in [dynarole_sim::USSR, dynarole_robot_atron::NETWORK_PRESETS[0]] {
        let peak = peak_per_module(&sim, &start, preset);
        assert!(
            peak < BUDGET,
            "{}: {peak} B per module at the peak",
            preset.name
        );
    }
}
