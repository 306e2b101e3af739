//! Benchmark: the lattice protocol's adaptive dissemination against the fixed 100 ms period
//! on eight2car (`eight.json` to `car.json`) and the tour (`car.json` back to `car.json`),
//! `atron` preset, the same seeds (1 to `SEEDS`, default 200) at loss 0, 0.3 and 0.6. Prints
//! a Markdown table (docs/benchmarks.md, "Adaptive dissemination"): success, packets sent per
//! run, median and 95th-percentile completion of the successful runs, and at loss 0 the mean
//! completion over the mechanical critical path plus one 100 ms period per hand-over, and
//! over the same bound with each module's statements one at a time (as the runtime ran them
//! before a module started its overlapping statements together, as one batch).
//!
//! `cargo bench -p dynarole-sim --bench dissemination` (`SEEDS=20` for a quick look; `CASE=tour`
//! or `LOSS=0.6` for one case or loss level; `ADAPTIVE_ONLY=1` skips the fixed runs: the
//! columns against fixed then compare adaptive with itself)

use dynarole_codegen::{CompileOptions, Dissemination, Protocol};
use dynarole_core::{analyze, parse};
use dynarole_sim::{Report, Run, Scenario, Simulator};
use dynarole_world::Configuration;

const EIGHT2CAR: &str = include_str!("../../../robots/atron/examples/eight2car.dr");
const EIGHT: &str = include_str!("../../../robots/atron/examples/eight.json");
const CAR: &str = include_str!("../../../robots/atron/examples/car.json");
/// One broadcast period of the fixed dissemination per hand-over (`DR_CONF_BROADCAST_MS`).
const PERIOD_MS: u64 = 100;
const LOSSES: [f64; 3] = [0.0, 0.3, 0.6];

/// A reconfiguration of the comparison: its name, sequence, start and goal.
struct Case {
    name: &'static str,
    sequence: &'static str,
    start: &'static str,
    goal: &'static str,
}

const CASES: [Case; 2] = [
    Case {
        name: "eight2car",
        sequence: "eight2car",
        start: EIGHT,
        goal: CAR,
    },
    Case {
        name: "tour",
        sequence: "tour",
        start: CAR,
        goal: CAR,
    },
];

/// What one (case, mode, loss) point measured.
struct Point {
    runs: usize,
    successes: usize,
    packets: f64,
    median_ms: f64,
    p95_ms: f64,
    mean_ms: f64,
}

fn simulator(sequence: &str, dissemination: Dissemination) -> Simulator {
    let parsed = parse(EIGHT2CAR);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let plans = vec![program.expand(sequence).expect("sequence exists")];
    let options = CompileOptions {
        protocol: Protocol::Lattice,
        dissemination,
        name: "bench".into(),
        ..CompileOptions::default()
    };
    Simulator::new(&program, &plans, &options).expect("compiles")
}

fn config(text: &str) -> Configuration {
    dynarole_robots::read_configuration(text).expect("valid configuration")
}

fn scenario(loss: f64) -> Scenario {
    let mut s = Scenario::default();
    s.network.loss = loss;
    s
}

/// The nearest-rank percentile `p` (0-100) of sorted `values`.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = ((p / 100.0) * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

/// Runs seeds 1..=seeds, on every core (a simulator per thread: it is not shared), and
/// summarises them.
fn measure(case: &Case, dissemination: Dissemination, scenario: &Scenario, seeds: u64) -> Point {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as u64;
    let worker = |t: u64| -> Vec<Report> {
        let sim = simulator(case.sequence, dissemination);
        let start = config(case.start);
        let goal = config(case.goal);
        (1..=seeds)
            .filter(|s| s % threads == t)
            .map(|seed| {
                sim.run(&Run {
                    start: &start,
                    expect: Some(&goal),
                    scenario,
                    seed,
                    trace: false,
                })
                .expect("runs")
            })
            .collect()
    };
    let mut reports: Vec<Report> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let worker = &worker;
                scope.spawn(move || worker(t))
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a worker ran"))
            .collect()
    });
    reports.sort_by_key(|r| r.seed);
    let mut done: Vec<f64> = reports
        .iter()
        .filter(|r| r.success)
        .filter_map(|r| r.completion_ms)
        .collect();
    done.sort_by(f64::total_cmp);
    let packets: u64 = reports.iter().map(|r| r.counters.packets_sent).sum();
    Point {
        runs: reports.len(),
        successes: done.len(),
        packets: packets as f64 / reports.len().max(1) as f64,
        median_ms: percentile(&done, 50.0),
        p95_ms: percentile(&done, 95.0),
        mean_ms: done.iter().sum::<f64>() / done.len().max(1) as f64,
    }
}

fn main() {
    let seeds: u64 = std::env::var("SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200);
    let only_case = std::env::var("CASE").ok();
    let only_loss: Option<f64> = std::env::var("LOSS").ok().and_then(|s| s.parse().ok());
    let modes: &[Dissemination] = if std::env::var_os("ADAPTIVE_ONLY").is_some() {
        &[Dissemination::Adaptive]
    } else {
        &[Dissemination::Fixed, Dissemination::Adaptive]
    };
    println!("| case | loss | dissemination | success | packets/run | median s | p95 s | fixed/adaptive packets | median vs fixed | p95 vs fixed |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut bounds = Vec::new();
    for case in CASES
        .iter()
        .filter(|c| only_case.as_deref().is_none_or(|n| n == c.name))
    {
        let path_sim = simulator(case.sequence, Dissemination::Fixed);
        for loss in LOSSES
            .into_iter()
            .filter(|l| only_loss.is_none_or(|o| o == *l))
        {
            let scenario = scenario(loss);
            let points: Vec<(Dissemination, Point)> = modes
                .iter()
                .map(|&d| (d, measure(case, d, &scenario, seeds)))
                .collect();
            let fixed = &points[0].1;
            for (d, p) in &points {
                println!(
                    "| {} | {loss} | {} | {}/{} | {:.0} | {:.2} | {:.2} | {:.2}x | {:+.1} % | {:+.1} % |",
                    case.name,
                    d.name(),
                    p.successes,
                    p.runs,
                    p.packets,
                    p.median_ms / 1000.0,
                    p.p95_ms / 1000.0,
                    fixed.packets / p.packets,
                    (p.median_ms / fixed.median_ms - 1.0) * 100.0,
                    (p.p95_ms / fixed.p95_ms - 1.0) * 100.0,
                );
                if loss == 0.0 {
                    let durations =
                        (path_sim.durations(&scenario.timing)).expect("the robot's timing preset");
                    let path = path_sim.critical_path(&durations);
                    let serial = path_sim.critical_path_one_at_a_time(&durations);
                    let bound = path.with_handovers(PERIOD_MS) as f64;
                    let serial_bound = serial.with_handovers(PERIOD_MS) as f64;
                    bounds.push(format!(
                        "| {} | {} | {:.2} | {:.2} ({} hand-overs) | {:.3} | {:.2} ({} hand-overs) | {:.3} |",
                        case.name,
                        d.name(),
                        p.mean_ms / 1000.0,
                        bound / 1000.0,
                        path.handovers,
                        p.mean_ms / bound,
                        serial_bound / 1000.0,
                        serial.handovers,
                        p.mean_ms / serial_bound
                    ));
                }
            }
        }
    }
    println!("\n| case | dissemination | mean completion s (loss 0) | critical path + 100 ms per hand-over s | ratio | one operation at a time per module + 100 ms per hand-over s | ratio |");
    println!("|---|---|---|---|---|---|---|");
    for line in bounds {
        println!("{line}");
    }
}
