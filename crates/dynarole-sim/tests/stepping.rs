//! The tickless stepping gives exactly the run of the fixed 5 ms stepping: the same trace
//! (every line: time, module, event, protocol state, detail) and the same report, byte for
//! byte, for every protocol, on several sequences, seeds, presets and fault scenarios
//! (resets, power cycles, blocked links, loss, random resets, a second robot, no NV). Only
//! the number of events differs, and it must drop.

mod common;

use common::faults::add_module_faults;
use common::*;
use dynarole_codegen::{CompileOptions, Protocol, TokenRetries};
use dynarole_core::{analyze, parse};
use dynarole_replay::token_routes;
use dynarole_sim::{Foreign, RandomResets, Report, Run, Scenario, Simulator, Stepping};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const CHAIN3_DR: &str = include_str!("data/chain3.dr");
const CHAIN3: &str = include_str!("data/chain3.json");

/// `sequences` of `source` compiled for `protocol` (token routes from `start`; `no_nv` for
/// the lattice protocol without non-volatile storage).
fn compiled(
    source: &str,
    sequences: &[&str],
    start: &str,
    protocol: Protocol,
    no_nv: bool,
) -> Simulator {
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let plans: Vec<_> = sequences
        .iter()
        .map(|s| program.expand(s).expect("sequence exists"))
        .collect();
    let routes = (protocol == Protocol::Token)
        .then(|| token_routes(&program, &plans, &config(start)).expect("routes"));
    let options = CompileOptions {
        protocol,
        no_nv,
        routes,
        token_retries: TokenRetries::Tries(32),
        name: "stepping".into(),
        ..CompileOptions::default()
    };
    Simulator::new(&program, &plans, &options).expect("compiles")
}

fn run_with(
    sim: &Simulator,
    start: &str,
    expect: &str,
    scenario: &Scenario,
    seed: u64,
    stepping: Stepping,
) -> Report {
    let scenario = Scenario {
        stepping,
        ..scenario.clone()
    };
    let start = config(start);
    let expect = config(expect);
    sim.run(&Run {
        start: &start,
        expect: Some(&expect),
        scenario: &scenario,
        seed,
        trace: true,
    })
    .expect("runs")
}

/// Runs both steppings and asserts the same trace and report (events aside); returns the
/// events of (fixed, tickless).
fn assert_same(
    sim: &Simulator,
    (start, expect): (&str, &str),
    scenario: &Scenario,
    seed: u64,
    what: &str,
) -> (u64, u64) {
    let fixed = run_with(sim, start, expect, scenario, seed, Stepping::Fixed);
    let tickless = run_with(sim, start, expect, scenario, seed, Stepping::Tickless);
    let context = || format!("{what}, seed {seed}, {scenario:?}");
    let (fixed_trace, tickless_trace) = (
        fixed.trace.clone().unwrap_or_default(),
        tickless.trace.clone().unwrap_or_default(),
    );
    if fixed_trace != tickless_trace {
        let first = fixed_trace
            .lines()
            .zip(tickless_trace.lines())
            .find(|(a, b)| a != b);
        panic!(
            "{}: traces differ, first at\n fixed:    {:?}\n tickless: {:?}",
            context(),
            first.map(|p| p.0),
            first.map(|p| p.1)
        );
    }
    let events = (fixed.counters.events, tickless.counters.events);
    let strip = |r: &Report| {
        let mut r = r.clone();
        r.counters.events = 0;
        serde_json::to_string(&r).expect("serialises")
    };
    assert_eq!(strip(&fixed), strip(&tickless), "{}", context());
    assert!(
        events.1 < events.0,
        "{}: tickless {} events, fixed {}",
        context(),
        events.1,
        events.0
    );
    (events.0, events.1)
}

/// Faults of every kind at random in the first `span_ms` (loss, resets, a power cycle, a
/// blocked link, sometimes random resets).
fn random_faults(rng: &mut ChaCha8Rng, modules: &[&str], span_ms: u64) -> Scenario {
    let mut scenario = Scenario::default();
    scenario.network.loss = [0.0, 0.1, 0.3][rng.random_range(0..3)];
    add_module_faults(rng, &mut scenario, modules, span_ms, 0..=2);
    if rng.random_bool(0.2) {
        scenario.random_resets = Some(RandomResets {
            interval_ms: 1_000,
            probability: 0.05,
        });
    }
    if rng.random_bool(0.2) {
        scenario.network.preset = dynarole_sim::PresetName::named(dynarole_sim::USSR.name);
    }
    scenario.faults_until_ms = Some(span_ms + 5_000);
    scenario.timeout_ms = span_ms + 60_000;
    scenario
}

#[test]
fn eight2car_gives_the_same_run_for_every_protocol_and_far_fewer_events() {
    for protocol in [Protocol::Lattice, Protocol::Paper, Protocol::Token] {
        let sim = compiled(EIGHT2CAR, &["eight2car"], EIGHT, protocol, false);
        for seed in 0..4 {
            for loss in [0.0, 0.3] {
                let mut scenario = Scenario::default();
                scenario.network.loss = loss;
                let (fixed, tickless) = assert_same(
                    &sim,
                    (EIGHT, CAR),
                    &scenario,
                    seed,
                    &format!("{protocol:?}"),
                );
                if protocol == Protocol::Lattice && loss == 0.0 {
                    // Most of the fixed stepping's events are steps that do nothing.
                    assert!(fixed > 3 * tickless, "{fixed} vs {tickless}");
                }
            }
        }
    }
}

#[test]
fn randomised_faults_give_the_same_run_with_both_steppings() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let source = format!("{CHAIN3_DR}\nsequence back = reverse short;\n");
    let lattice = compiled(
        &source,
        &["short", "back"],
        CHAIN3,
        Protocol::Lattice,
        false,
    );
    let no_nv = compiled(&source, &["short", "back"], CHAIN3, Protocol::Lattice, true);
    let paper = compiled(CHAIN3_DR, &["short"], CHAIN3, Protocol::Paper, false);
    for seed in 0..40u64 {
        let scenario = random_faults(&mut rng, &["M0", "M1", "M2"], 8_000);
        assert_same(&lattice, (CHAIN3, CHAIN3), &scenario, seed, "lattice");
        assert_same(&no_nv, (CHAIN3, CHAIN3), &scenario, seed, "lattice no NV");
        assert_same(&paper, (CHAIN3, CHAIN3), &scenario, seed, "paper");
    }
}

#[test]
fn eight2car_then_back_under_faults_gives_the_same_run() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let modules = ["M0", "M1", "M2", "M3", "M4", "M5", "M6"];
    let lattice = compiled(
        EIGHT2CAR,
        &["eight2car", "car2eight"],
        EIGHT,
        Protocol::Lattice,
        false,
    );
    let no_nv = compiled(
        EIGHT2CAR,
        &["eight2car", "car2eight"],
        EIGHT,
        Protocol::Lattice,
        true,
    );
    let token = compiled(EIGHT2CAR, &["eight2car"], EIGHT, Protocol::Token, false);
    for seed in 0..6u64 {
        let scenario = random_faults(&mut rng, &modules, 30_000);
        assert_same(&lattice, (EIGHT, EIGHT), &scenario, seed, "lattice");
        assert_same(&no_nv, (EIGHT, EIGHT), &scenario, seed, "lattice no NV");
        assert_same(&token, (EIGHT, CAR), &scenario, seed, "token");
    }
}

#[test]
fn a_second_robot_in_range_gives_the_same_run() {
    let sim = compiled(EIGHT2CAR, &["eight2car"], EIGHT, Protocol::Lattice, false);
    let mut scenario = Scenario::default();
    scenario.foreign.push(Foreign {
        module: "M0".into(),
        connector: 0,
        robot: 7,
        from_ms: 500,
        to_ms: 20_000,
        interval_ms: 37,
        execution: None,
    });
    for seed in 0..3 {
        assert_same(&sim, (EIGHT, CAR), &scenario, seed, "foreign");
    }
}
