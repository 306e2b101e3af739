//! Scale benchmark: a flat ATRON structure of 1,000, 10,000 and 100,000 modules spreading
//! one statement's end state from a corner to every module; prints wall and CPU time,
//! simulated time, events, events per wall second, packets and bytes per module (the heap a
//! counting allocator saw at its peak, and the peak RSS), with a progress line on stderr
//! every 15 s (`README.md`, "Figures").
//!
//! `cargo bench -p dynarole-sim --bench scale` (ussr at 1,000, 10,000 and 100,000 modules,
//! atron at 1,000 and 10,000; other sizes as arguments, for every preset of
//! `DYNAROLE_SCALE_PRESETS`, default `ussr,atron`:
//! `DYNAROLE_SCALE_PRESETS=atron cargo bench -p dynarole-sim --bench scale -- 100000`), with
//! the tickless stepping unless `DYNAROLE_SCALE_STEPPING=fixed` (the same run). Each
//! row runs in a fresh process (the benchmark re-runs itself with `--row PRESET N`), so that
//! its peak RSS is its own.
//!
//! The structure is generated in memory: sites (x, 0, z) with x and z of the same parity
//! (lattice phase (0,0,1)), taken row by row (z, then x) from (0, 0) in a square of side
//! ceil(sqrt(2N)); NS_BROKEN modules at even-even sites, EW modules at odd-odd ones, every
//! NS_BROKEN module latched to its EW neighbours exactly as in the paper's "eight"
//! (`robots/atron/examples/eight.json`, checked first; the generator is `tests/common/grid.rs`,
//! shared with the memory test). Only the corner module (0, 0) has an ID (0,
//! named `M0`): the others have none, so `dr_hal_id` answers 0xFFFF for them.

#[path = "../tests/common/counting.rs"]
mod counting;
#[path = "../tests/common/grid.rs"]
mod grid;

use counting::Counting;
use dynarole_codegen::{CompileOptions, Protocol};
use dynarole_core::expand::Plan;
use dynarole_core::{analyze, parse, Program};
use dynarole_replay::RobotWorld;
use dynarole_sim::{Preset, Run, Scenario, Simulator, Stepping};
use dynarole_world::compare;
use grid::{square, structure_json, Site, SOURCE};
use std::collections::BTreeSet;
use std::time::Instant;

/// Counts the heap, so that a row also says the simulator's own bytes per module (peak
/// RSS also counts the allocator's overheads and what it keeps after a free).
#[global_allocator]
static HEAP: Counting = Counting::new();

const EIGHT: &str = include_str!("../../../robots/atron/examples/eight.json");

/// Sizes run by default, per preset: 100,000 modules with the `atron` preset takes about
/// 5 minutes on its own (random power-on phases make every step touch another module's
/// memory), so it runs only when asked (`DYNAROLE_SCALE_PRESETS=atron ... -- 100000`).
const SIZES: [(Preset, &[usize]); 2] = [
    (dynarole_sim::USSR, &[1_000, 10_000, 100_000]),
    (dynarole_robot_atron::NETWORK_PRESETS[0], &[1_000, 10_000]),
];

/// A connection without its direction: the two (module, connector) ends, sorted.
fn unordered(c: &serde_json::Value) -> (String, u64, String, u64) {
    let name = |k: usize| c[k].as_str().unwrap_or_default().to_string();
    let conn = |k: usize| c[k].as_u64().unwrap_or(u64::MAX);
    let (a, b) = ((name(0), conn(1)), (name(2), conn(3)));
    let ((a, ac), (b, bc)) = if a <= b { (a, b) } else { (b, a) };
    (a, ac, b, bc)
}

fn connections(json: &str) -> BTreeSet<(String, u64, String, u64)> {
    let value: serde_json::Value = serde_json::from_str(json).expect("JSON");
    value["connections"]
        .as_array()
        .expect("connections")
        .iter()
        .map(unordered)
        .collect()
}

/// The generator, on the eight's seven sites and names, gives the eight's connections (and
/// the same configuration).
fn check_against_eight() {
    let eight: serde_json::Value = serde_json::from_str(EIGHT).expect("eight.json");
    let sites: Vec<Site> = eight["modules"]
        .as_array()
        .expect("modules")
        .iter()
        .map(|m| Site {
            name: m["name"].as_str().expect("name").to_string(),
            id: m["id"].as_u64().map(|i| i as u32),
            x: m["position"][0].as_i64().expect("x"),
            z: m["position"][2].as_i64().expect("z"),
        })
        .collect();
    let generated = structure_json("eight", &sites);
    assert_eq!(
        connections(&generated),
        connections(EIGHT),
        "the generator does not rebuild eight.json's connections"
    );
    let a = dynarole_robots::read_configuration(&generated).expect("generated eight");
    let b = dynarole_robots::read_configuration(EIGHT).expect("eight.json");
    compare(&a, &b).expect("the generated eight is eight.json");
}

fn simulator(program: &Program, plan: &Plan) -> Simulator {
    let options = CompileOptions {
        protocol: Protocol::Lattice,
        name: "scale".into(),
        ..CompileOptions::default()
    };
    Simulator::new(program, std::slice::from_ref(plan), &options).expect("compiles")
}

/// The statement is valid on the structure: the replay crate's world does it without refusal
/// or warning.
fn check_with_replay(program: &Program, plan: &Plan) {
    let config =
        dynarole_robots::read_configuration(&structure_json("check", &square(200))).expect("ok");
    let mut world = RobotWorld::new(config, &program.robot).expect("world");
    for statement in plan.statements() {
        let outcome = world
            .apply(&program.robot, statement, "M0")
            .unwrap_or_else(|e| panic!("the replay refuses the statement: {e}"));
        assert!(outcome.warnings.is_empty(), "{:?}", outcome.warnings);
    }
}

/// Peak resident set (VmHWM) in KiB.
fn peak_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Resets VmHWM to the current RSS (Linux 4.0+); false when it cannot. The memory freed
/// since (the structure's JSON and its parse) goes back to the system first, so that the
/// run cannot reuse it unseen and the RSS it adds is its own.
fn reset_peak() -> bool {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        extern "C" {
            fn malloc_trim(pad: usize) -> i32;
        }
        // SAFETY: glibc's malloc_trim only returns free heap pages to the system.
        unsafe {
            malloc_trim(0);
        }
    }
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

fn current_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// `DYNAROLE_SCALE_STEPPING`: `fixed` or `tickless` (the default).
fn stepping() -> Stepping {
    match std::env::var("DYNAROLE_SCALE_STEPPING") {
        Err(_) => Stepping::Tickless,
        Ok(name) => dynarole_codegen::choice::parse(&name)
            .unwrap_or_else(|e| panic!("DYNAROLE_SCALE_STEPPING: {e}")),
    }
}

/// The rows to run: the given sizes (arguments) for every preset asked
/// (`DYNAROLE_SCALE_PRESETS`, default both), else `SIZES`.
fn rows() -> Vec<(Preset, usize)> {
    let text = std::env::var("DYNAROLE_SCALE_PRESETS").unwrap_or_else(|_| "ussr,atron".into());
    let presets: Vec<Preset> = text
        .split(',')
        .filter_map(|p| match p.trim() {
            "ussr" => Some(dynarole_sim::USSR),
            "atron" => Some(dynarole_robot_atron::NETWORK_PRESETS[0]),
            "" => None,
            other => panic!("unknown preset {other}"),
        })
        .collect();
    let given: Vec<usize> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .filter_map(|a| a.replace(['_', ','], "").parse().ok())
        .collect();
    let mut out = Vec::new();
    for preset in presets {
        let default = SIZES
            .iter()
            .find(|(p, _)| *p == preset)
            .map(|(_, s)| s.to_vec());
        let sizes = if given.is_empty() {
            default.unwrap_or_default()
        } else {
            given.clone()
        };
        out.extend(sizes.into_iter().map(|n| (preset, n)));
    }
    out
}

/// CPU time of this thread so far (s), from `/proc/thread-self/schedstat` (Linux).
fn cpu_s() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns / 1e9)
}

/// Bytes as MB.
fn mb(bytes: usize) -> f64 {
    bytes as f64 / 1e6
}

/// Runs `work` while a line on stderr says, every `PROGRESS_S` seconds, how long it has run
/// and how much memory the process holds (a large row runs for minutes).
fn with_progress<T>(what: &str, work: impl FnOnce() -> T) -> T {
    const PROGRESS_S: u64 = 15;
    let done = std::sync::atomic::AtomicBool::new(false);
    let started = Instant::now();
    std::thread::scope(|scope| {
        scope.spawn(|| {
            let mut next = PROGRESS_S;
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                std::thread::sleep(std::time::Duration::from_millis(200));
                if started.elapsed().as_secs() >= next {
                    next += PROGRESS_S;
                    eprintln!(
                        "scale: {what}: {:.0} s, RSS {:.0} MB, heap {:.0} MB (peak {:.0} MB)",
                        started.elapsed().as_secs_f64(),
                        current_kib().map_or(f64::NAN, |k| k as f64 / 1e3),
                        mb(HEAP.current()),
                        mb(HEAP.peak()),
                    );
                }
            }
        });
        let out = work();
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        out
    })
}

/// One row of the table: `preset` on `n` modules (run in a fresh process, so that the peak
/// RSS is this run's alone).
fn row(sim: &Simulator, preset: Preset, n: usize) {
    let context = sim.module_context_bytes(preset).expect("builds");
    let started = Instant::now();
    let what = format!("{} {n}", preset.name);
    let start = with_progress(&format!("{what}, structure"), || {
        let json = structure_json(&format!("flat-{n}"), &square(n));
        dynarole_robots::read_configuration(&json).expect("valid configuration")
    });
    let built = started.elapsed().as_secs_f64();
    let mut scenario = Scenario::default();
    scenario.network.preset = dynarole_sim::PresetName::named(preset.name);
    scenario.network.loss = 0.0;
    scenario.timeout_ms = 600_000;
    scenario.stepping = stepping();
    let before = if reset_peak() {
        current_kib()
    } else {
        peak_kib()
    };
    let heap_before = HEAP.current();
    HEAP.reset_peak();
    let started = Instant::now();
    let cpu_before = cpu_s();
    let report = with_progress(&format!("{what}, run"), || {
        sim.run(&Run {
            start: &start,
            expect: None,
            scenario: &scenario,
            seed: 1,
            trace: false,
        })
        .expect("runs")
    });
    let wall = started.elapsed().as_secs_f64();
    let cpu = match (cpu_before, cpu_s()) {
        (Some(b), Some(a)) => format!("{:.2}", a - b),
        _ => "?".into(),
    };
    let heap = (HEAP.peak() - heap_before) / n;
    let rss = match (before, peak_kib()) {
        (Some(b), Some(a)) => format!("{:.0}", (a.saturating_sub(b) * 1024) as f64 / n as f64),
        _ => "?".into(),
    };
    assert!(report.success, "{n} modules: {:?}", report.failures);
    let all = report
        .all_finished_ms
        .expect("every module declared the end");
    println!(
        "| {} | {n} | {wall:.2} | {cpu} | {built:.2} | {:.3} / {:.3} | {} | {:.2} M | {} | {context} | {heap} | {rss} |",
        preset.name,
        report.completion_ms.unwrap_or(f64::NAN) / 1000.0,
        all / 1000.0,
        report.counters.events,
        report.counters.events as f64 / wall / 1e6,
        report.counters.packets_sent,
    );
}

fn main() {
    let parsed = parse(SOURCE);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let plan = program.expand("spread").expect("spread");
    let sim = simulator(&program, &plan);
    // A child: `--row PRESET N` prints one row.
    let args: Vec<String> = std::env::args().collect();
    if let Some(k) = args.iter().position(|a| a == "--row") {
        let preset = match args.get(k + 1).map(String::as_str) {
            Some("atron") => dynarole_robot_atron::NETWORK_PRESETS[0],
            _ => dynarole_sim::USSR,
        };
        let n = args.get(k + 2).and_then(|n| n.parse().ok()).expect("N");
        row(&sim, preset, n);
        return;
    }
    check_against_eight();
    check_with_replay(&program, &plan);
    println!(
        "scale: one statement on M0 at a corner (lattice protocol, no loss, seed 1, {:?} \
         stepping); the run ends when every module has declared the end",
        stepping()
    );
    println!(
        "| preset | modules | wall s | CPU s | structure s | simulated s (first / all declared the end) | events | events / wall s | packets sent | C context B / module | peak heap B / module | peak RSS B / module |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let exe = std::env::current_exe().expect("this benchmark's path");
    for (preset, n) in rows() {
        sim.module_context_bytes(preset).expect("builds"); // into the cache, once
        let status = std::process::Command::new(&exe)
            .args(["--row", preset.name, &n.to_string()])
            .status()
            .expect("runs a row");
        assert!(status.success(), "{} {n}: {status}", preset.name);
    }
}
