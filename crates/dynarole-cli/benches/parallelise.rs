//! Benchmark of `parallelise`: the shipped sequences written all in order, and sequential
//! chains of 100 and 1,000 random valid moves on a 100-module ATRON chain. Prints the table of
//! `docs/parallelise.md` (statements, groups, critical paths, time taken), then times
//! eight2car and the 1,000-statement chain with criterion.

use criterion::{criterion_group, criterion_main, Criterion};
use dynarole_codegen::{CompileOptions, Protocol};
use dynarole_core::{analyze, parse};
use dynarole_replay::{assign_modules, parallelise, Parallelised, Request, RobotWorld};
use dynarole_robot_atron::generated::atron_chain_json;
use dynarole_robot_atron::World;
use dynarole_sim::{form_makespan, makespan};
use dynarole_sim::{Run, Scenario, Simulator};
use std::time::{Duration, Instant};

const EIGHT2CAR: &str = include_str!("../../../robots/atron/examples/eight2car.dr");
const FIG5: &str = include_str!("../../../robots/atron/examples/fig5.dr");
const MTRAN: &str = include_str!("../../../robots/mtran/examples/move_module.dr");
const EIGHT: &str = include_str!("../../../robots/atron/examples/eight.json");
const CAR: &str = include_str!("../../../robots/atron/examples/car.json");
const SNAKE: &str = include_str!("../../../robots/atron/examples/snake.json");
const SNAKE4: &str = include_str!("../../../robots/mtran/examples/mtran-snake4.json");
const SNAKE4_MOVED: &str = include_str!("../../../robots/mtran/examples/mtran-snake4-moved.json");

/// Simulated time after which a run counts as not finished (ms): 10,000 s.
const SIMULATION_LIMIT_MS: u64 = 10_000_000;

/// One sequence to parallelise: the file as shipped, the sequence and where it starts.
struct Case {
    name: String,
    source: String,
    sequence: &'static str,
    config: String,
    /// `--window`: only pairs at most this far apart are checked.
    window: Option<usize>,
}

/// What one case gives: the table's row.
struct Row {
    statements: usize,
    groups: usize,
    shipped_ms: Result<u64, String>,
    before_ms: Result<u64, String>,
    after_ms: Result<u64, String>,
    time: Duration,
    /// Completion of the generated C in the simulator at 0 % loss: all `;`, parallelised.
    simulated: (Result<f64, String>, Result<f64, String>),
    /// The same for the shipped file, when it has its own `&`.
    simulated_shipped: Option<Result<f64, String>>,
}

/// Completion time (ms) of `sequence` run by the simulator from `config`, fault-free.
fn simulated(source: &str, sequence: &str, config: &str) -> Result<f64, String> {
    let parsed = parse(source);
    let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.ok_or("does not check")?;
    let plan = program.expand(sequence).ok_or("no sequence")?;
    let options = CompileOptions {
        name: "bench".into(),
        ..CompileOptions::default()
    };
    let simulator = Simulator::new(&program, &[plan], &options).map_err(|e| e.to_string())?;
    let start = dynarole_robots::read_configuration(config).map_err(|e| e.to_string())?;
    // The default scenario stops a run at 300 s; a chain of statements on a 100-module robot
    // takes longer (each hand-over travels the chain hop by hop, about one broadcast period
    // per hop), so the time limit is raised and nothing else changed.
    let scenario = Scenario {
        timeout_ms: SIMULATION_LIMIT_MS,
        ..Scenario::default()
    };
    let report = simulator
        .run(&Run {
            start: &start,
            expect: None,
            scenario: &scenario,
            seed: 1,
            trace: false,
        })
        .map_err(|e| e.to_string())?;
    report
        .completion_ms
        .ok_or_else(|| "did not finish".to_string())
}

fn sequential(source: &str) -> String {
    source.replace(" &\n", ";\n")
}

/// Parallelises `sequence` of `source` (lattice forms) and returns the result.
fn run(
    source: &str,
    sequence: &str,
    config: &str,
    window: Option<usize>,
) -> (Parallelised, Vec<Result<u64, String>>) {
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let config = dynarole_robots::read_configuration(config).expect("configuration");
    let plan = program.expand(sequence).expect("sequence");
    let assignment = assign_modules(&program, &[plan], &config).expect("labels");
    let world = RobotWorld::new(config, &program.robot).expect("world");
    let request = Request {
        program: &program,
        sequence,
        world,
        assignment: &assignment,
        name: "out",
        blocks: true,
        one_module_overlap: true,
        window,
    };
    let found = parallelise(&request).unwrap_or_else(|e| panic!("{e:?}"));
    let estimates = found
        .forms
        .iter()
        .map(|f| form_makespan(&found, f, "out", Protocol::Lattice, &program.robot))
        .collect();
    (found, estimates)
}

fn critical_path(source: &str, sequence: &str) -> Result<u64, String> {
    let parsed = parse(source);
    let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.ok_or("does not check")?;
    let plan = program.expand(sequence).ok_or("no sequence")?;
    makespan(&program, &[plan], Protocol::Lattice)
}

fn row(case: &Case) -> Row {
    let source = sequential(&case.source);
    let started = Instant::now();
    let (found, estimates) = run(&source, case.sequence, &case.config, case.window);
    let time = started.elapsed();
    let best = (0..estimates.len())
        .min_by_key(|k| estimates[*k].clone().unwrap_or(u64::MAX))
        .unwrap_or(0);
    let written = format!("{}\n{}", found.header, found.forms[best].text);
    let simulated_shipped = case
        .source
        .contains(" &")
        .then(|| simulated(&case.source, case.sequence, &case.config));
    let simulated = (
        simulated(&source, case.sequence, &case.config),
        simulated(&written, "out", &case.config),
    );
    Row {
        simulated,
        simulated_shipped,
        statements: found.statements.len(),
        groups: found.forms[best].groups,
        shipped_ms: critical_path(&case.source, case.sequence),
        before_ms: critical_path(&source, case.sequence),
        after_ms: estimates[best].clone(),
        time,
    }
}

fn seconds(ms: &Result<u64, String>) -> String {
    match ms {
        Ok(ms) => format!("{:.2} s", *ms as f64 / 1000.0),
        Err(e) => format!("n/a ({e})"),
    }
}

fn sim_seconds(ms: &Result<f64, String>) -> String {
    match ms {
        Ok(ms) => format!("{:.2} s", ms / 1000.0),
        Err(e) => format!("n/a ({e})"),
    }
}

/// `count` moves a planner might list: random operations (a fixed xorshift stream) tried on
/// the model, the accepted ones kept, all joined by `;`.
fn random_moves(config: &str, n: usize, count: usize) -> String {
    let config = dynarole_robots::read_configuration(config).expect("a configuration");
    let c = (config.downcast_ref::<dynarole_robot_atron::AtronConfiguration>())
        .expect("an atron configuration");
    let mut world = World::new(c.clone());
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut body = String::new();
    let mut kept = 0;
    for _ in 0..count * 1000 {
        if kept == count {
            break;
        }
        let m = (next() % n as u64) as usize;
        let name = format!("M{m}");
        let c = (next() % 8) as u8;
        let joint = world.configuration().modules()[m].joint_units;
        let mut trial = world.clone();
        let (text, ok) = match next() % 3 {
            0 => (
                format!("M{m}.Connector[{c}].retract()"),
                trial.retract(&name, c),
            ),
            1 => (
                format!("M{m}.Connector[{c}].extend()"),
                trial.extend(&name, c),
            ),
            _ => {
                let to = (joint + 108) % 432;
                (
                    format!("M{m}.Joint.rotateFromToBy({joint}, {to}, true, 150)"),
                    trial.rotate(&name, joint, to, true),
                )
            }
        };
        // A step with a warning is done by the model but not kept: the world goes back.
        if ok.is_ok_and(|o| o.warnings.is_empty()) {
            world = trial;
            body.push_str(&format!("    {text};\n"));
            kept += 1;
        }
    }
    assert_eq!(kept, count, "not enough valid moves");
    format!("robot atron;\nsequence chain {{\n{body}}}\n")
}

fn cases() -> Vec<Case> {
    let shipped = |name: &str, source: &str, sequence: &'static str, config: &str| Case {
        name: name.to_string(),
        source: source.to_string(),
        sequence,
        config: config.to_string(),
        window: None,
    };
    let big = atron_chain_json(100);
    let mut out = vec![
        shipped("eight2car", EIGHT2CAR, "eight2car", EIGHT),
        shipped("eight2car (fig5.dr)", FIG5, "eight2car", EIGHT),
        shipped("car2eight", EIGHT2CAR, "car2eight", CAR),
        shipped("eight2snake", EIGHT2CAR, "eight2snake", EIGHT),
        shipped("snake2eight", EIGHT2CAR, "snake2eight", SNAKE),
        shipped("tour", EIGHT2CAR, "tour", CAR),
        shipped("left2right (M-TRAN)", MTRAN, "left2right", SNAKE4),
        shipped("right2left (M-TRAN)", MTRAN, "right2left", SNAKE4_MOVED),
    ];
    for (count, window) in [(100, None), (1000, None), (100, Some(16)), (1000, Some(16))] {
        let name = match window {
            Some(w) => format!("{count} random moves, 100-module chain, window {w}"),
            None => format!("{count} random moves, 100-module chain"),
        };
        out.push(Case {
            name,
            source: random_moves(&big, 100, count),
            sequence: "chain",
            config: big.clone(),
            window,
        });
    }
    out
}

fn benches(c: &mut Criterion) {
    let cases = cases();
    write_inputs(&cases);
    println!("| sequence | statements | groups | critical path: shipped | all `;` | parallelised | simulated: shipped | all `;` | parallelised | time |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for case in &cases {
        let r = row(case);
        let (sim_before, sim_after) = (sim_seconds(&r.simulated.0), sim_seconds(&r.simulated.1));
        let sim_shipped = r
            .simulated_shipped
            .as_ref()
            .map_or("(none)".to_string(), sim_seconds);
        println!(
            "| {} | {} | {} | {} | {} | {} | {sim_shipped} | {sim_before} | {sim_after} | {:.3} s |",
            case.name,
            r.statements,
            r.groups,
            seconds(&r.shipped_ms),
            seconds(&r.before_ms),
            seconds(&r.after_ms),
            r.time.as_secs_f64()
        );
    }
    for case in [&cases[0], &cases[cases.len() - 1]] {
        let source = sequential(&case.source);
        c.bench_function(&format!("parallelise {}", case.name), |b| {
            b.iter(|| run(&source, case.sequence, &case.config, case.window))
        });
    }
}

/// Writes the generated chains (and their 100-module start) under `target/parallelise-bench/`,
/// so the command itself can be timed on them (`docs/benchmarks.md`).
fn write_inputs(cases: &[Case]) {
    let dir =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/parallelise-bench");
    let mut files = vec![("chain100.json".to_string(), atron_chain_json(100))];
    for case in cases
        .iter()
        .filter(|c| c.sequence == "chain" && c.window.is_none())
    {
        files.push((
            format!("chain{}.dr", case.source.matches(");").count()),
            case.source.clone(),
        ));
    }
    let written = std::fs::create_dir_all(&dir).and_then(|()| {
        files
            .iter()
            .try_for_each(|(name, text)| std::fs::write(dir.join(name), text))
    });
    match written {
        Ok(()) => println!("inputs written to {}", dir.display()),
        Err(e) => println!("inputs not written to {}: {e}", dir.display()),
    }
}

criterion_group! {
    name = parallelise_benches;
    config = Criterion::default().sample_size(10);
    targets = benches
}
criterion_main!(parallelise_benches);
