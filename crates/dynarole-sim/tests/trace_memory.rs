//! A run writing its trace to a file holds one line at a time: its peak heap does not grow
//! with the length of the run (the trace kept in memory grows with it, 5.9 GB for 10^9 ms
//! at loss 1.0 before the trace was streamed). Bytes and their ratio are asserted, never time.

mod common;

use common::counting::Counting;
use common::{config, simulator, EIGHT, EIGHT2CAR};
use dynarole_codegen::Protocol;
use dynarole_sim::{Outputs, Run, Scenario};

#[global_allocator]
static HEAP: Counting = Counting::new();

/// Simulated time of the shorter run (ms); the longer lasts four times as long.
const SHORT_MS: u64 = 200_000;
/// The largest ratio of the two runs' peaks accepted with the trace streamed (1 when
/// nothing grows with the run; a trace kept in memory gives about 4).
const MAX_RATIO: f64 = 1.5;

/// The peak heap of a run of eight2car that never ends (every packet lost) for `ms`
/// simulated milliseconds, its trace streamed (or kept, with `keep`), and the trace's bytes.
fn peak(ms: u64, keep: bool) -> (usize, u64) {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let start = config(EIGHT);
    let mut scenario = Scenario::default();
    scenario.network.loss = 1.0;
    scenario.timeout_ms = ms;
    sim.module_context_bytes(dynarole_robot_atron::NETWORK_PRESETS[0])
        .expect("builds");
    let base = HEAP.current();
    HEAP.reset_peak();
    // A file, as far as the heap is concerned: the bytes leave the process.
    let file: Box<dyn std::io::Write> = Box::new(std::io::sink());
    let outputs = Outputs {
        trace: (!keep).then_some(file),
        ..Outputs::default()
    };
    let run = Run {
        start: &start,
        expect: None,
        scenario: &scenario,
        seed: 1,
        trace: keep,
    };
    let report = sim.run_with(&run, outputs).expect("runs");
    let peak = HEAP.peak() - base;
    let bytes = report.trace.as_ref().map_or(0, |t| t.len() as u64);
    assert!(!report.success);
    assert!(report.counters.lost > 1000, "{}", report.summary());
    eprintln!(
        "{} s simulated, trace {}: peak heap {peak} B",
        ms / 1000,
        if keep { "kept" } else { "streamed" }
    );
    (peak, bytes)
}

/// One test: the allocator counts the whole process, so nothing else may run beside it.
#[test]
fn a_streamed_trace_needs_no_more_memory_for_a_longer_run() {
    let (short, _) = peak(SHORT_MS, false);
    let (long, _) = peak(4 * SHORT_MS, false);
    let ratio = long as f64 / short as f64;
    assert!(
        ratio < MAX_RATIO,
        "a run 4x as long took {ratio:.2}x the heap ({short} B, then {long} B)"
    );
    // The measure sees what it should: the same runs with the trace kept grow with it.
    let (kept_short, bytes) = peak(SHORT_MS, true);
    let (kept_long, _) = peak(4 * SHORT_MS, true);
    assert!(kept_short as u64 > bytes && kept_long > 3 * kept_short);
}
