//! Benchmark: the simulator on eight2car (`eight.json` to `car.json`), lattice and paper
//! protocols, 0 % and 30 % loss (atron preset; the figures also with the ussr preset), with
//! the fixed 5 ms stepping and the tickless one (`Scenario::stepping`; same runs, fewer
//! events).
//! Criterion times one run; before that, the
//! figures of `README.md` ("Figures") are printed: simulated seconds per wall second, events
//! per second, completion time, and completion over the mechanical critical path (with and
//! without one broadcast period per hand-over).
//!
//! `cargo bench -p dynarole-sim --bench sim`

use criterion::{criterion_group, criterion_main, Criterion};
use dynarole_codegen::{CompileOptions, Protocol};
use dynarole_core::{analyze, parse};
use dynarole_sim::{Preset, Run, Scenario, Simulator, Stepping};
use dynarole_world::Configuration;
use std::time::Instant;

const EIGHT2CAR: &str = include_str!("../../../robots/atron/examples/eight2car.dr");
const EIGHT: &str = include_str!("../../../robots/atron/examples/eight.json");
const CAR: &str = include_str!("../../../robots/atron/examples/car.json");
/// The runtime's broadcast period (`DR_CONF_BROADCAST_MS`): what a hand-over costs at most
/// when no packet is lost.
const BROADCAST_MS: u64 = 100;
/// Seeds per configuration for the printed figures.
const SEEDS: u64 = 50;

fn simulator(protocol: Protocol) -> Simulator {
    let parsed = parse(EIGHT2CAR);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let plans = vec![program.expand("eight2car").expect("eight2car")];
    let options = CompileOptions {
        protocol,
        name: "bench".into(),
        ..CompileOptions::default()
    };
    Simulator::new(&program, &plans, &options).expect("compiles")
}

fn config(text: &str) -> Configuration {
    dynarole_robots::read_configuration(text).expect("valid configuration")
}

fn scenario(preset: Preset, loss: f64, stepping: Stepping) -> Scenario {
    let mut s = Scenario::default();
    s.network.preset = dynarole_sim::PresetName::named(preset.name);
    s.network.loss = loss;
    s.stepping = stepping;
    s
}

/// CPU time of this thread so far (s), from `/proc/thread-self/schedstat` (Linux): on a
/// shared machine it measures the work, where the wall time also measures the others' load.
fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |ns| ns / 1e9)
}

fn name(protocol: Protocol) -> &'static str {
    protocol.name()
}

/// Runs SEEDS seeds and prints one line of figures.
fn figures(
    sim: &Simulator,
    protocol: Protocol,
    (preset, loss, stepping): (Preset, f64, Stepping),
    start: &Configuration,
    car: &Configuration,
) {
    let scenario = scenario(preset, loss, stepping);
    let durations = (sim.durations(&scenario.timing)).expect("the robot's timing preset");
    let path = sim.critical_path(&durations);
    let bound_ms = path.with_handovers(BROADCAST_MS);
    let run = |seed| {
        sim.run(&Run {
            start,
            expect: Some(car),
            scenario: &scenario,
            seed,
            trace: false,
        })
        .expect("runs")
    };
    let _ = run(0); // builds or loads the C
    let started = Instant::now();
    let cpu_started = cpu_seconds();
    let reports: Vec<_> = (0..SEEDS).map(run).collect();
    let wall = started.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu_started;
    let successes = reports.iter().filter(|r| r.success).count();
    let simulated: f64 = reports.iter().map(|r| r.end_ms / 1000.0).sum();
    let events: u64 = reports.iter().map(|r| r.counters.events).sum();
    let completions: Vec<f64> = reports.iter().filter_map(|r| r.completion_ms).collect();
    let mean = completions.iter().sum::<f64>() / completions.len().max(1) as f64;
    let min = completions.iter().copied().fold(f64::INFINITY, f64::min);
    let max = completions.iter().copied().fold(0.0, f64::max);
    println!(
        "{} {:<8} {:<7} loss {:>3.0} %: {successes}/{SEEDS} ok; {:>7.0} simulated s / wall s ({:>7.0} / CPU s); {:>9.0} events/s ({:.0} events/run); \
         completion {:.3} s ({:.3}-{:.3}); critical path {:.3} s ({} statements, {} hand-overs) -> x{:.3}; \
         + {BROADCAST_MS} ms per hand-over {:.3} s -> x{:.3}",
        preset.name,
        format!("{stepping:?}").to_lowercase(),
        name(protocol),
        loss * 100.0,
        simulated / wall,
        simulated / cpu,
        events as f64 / wall,
        events as f64 / SEEDS as f64,
        mean / 1000.0,
        min / 1000.0,
        max / 1000.0,
        path.duration_ms as f64 / 1000.0,
        path.statements.len(),
        path.handovers,
        mean / path.duration_ms as f64,
        bound_ms as f64 / 1000.0,
        mean / bound_ms as f64,
    );
}

fn benches(c: &mut Criterion) {
    let start = config(EIGHT);
    let car = config(CAR);
    let sims: Vec<(Protocol, Simulator)> = [Protocol::Lattice, Protocol::Paper]
        .into_iter()
        .map(|p| (p, simulator(p)))
        .collect();
    for preset in [dynarole_robot_atron::NETWORK_PRESETS[0], dynarole_sim::USSR] {
        for (protocol, sim) in &sims {
            for loss in [0.0, 0.3] {
                for stepping in [Stepping::Fixed, Stepping::Tickless] {
                    figures(sim, *protocol, (preset, loss, stepping), &start, &car);
                }
            }
        }
    }
    for (protocol, sim) in &sims {
        for loss in [0.0, 0.3] {
            for stepping in [Stepping::Fixed, Stepping::Tickless] {
                let scenario = scenario(dynarole_robot_atron::NETWORK_PRESETS[0], loss, stepping);
                let run = Run {
                    start: &start,
                    expect: Some(&car),
                    scenario: &scenario,
                    seed: 1,
                    trace: false,
                };
                c.bench_function(
                    &format!(
                        "simulate eight2car, {}, loss {loss}, {stepping:?}",
                        name(*protocol)
                    ),
                    |b| b.iter(|| sim.run(&run).expect("runs")),
                );
            }
        }
    }
}

criterion_group! {
    name = sim_benches;
    config = Criterion::default().sample_size(10);
    targets = benches
}
criterion_main!(sim_benches);
