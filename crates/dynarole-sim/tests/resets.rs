//! Verdicts under resets are exact: a sequence followed by its derived reverse repeats every
//! operation, and randomised resets, power cycles and blocked links on such runs must give no
//! violation for the lattice protocol with non-volatile storage; every statement the simulator
//! attributes to a module is the one that module's runtime was running.

mod common;

use common::faults::add_module_faults;
use common::*;
use dynarole_codegen::Protocol;
use dynarole_sim::{Report, Reset, Scenario, Simulator};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const CHAIN3_DR: &str = include_str!("data/chain3.dr");
const CHAIN3: &str = include_str!("data/chain3.json");

/// chain3's sequence and its derived reverse, as one run from chain3 back to chain3.
fn chain3_and_back() -> Simulator {
    let source = format!("{CHAIN3_DR}\nsequence back = reverse short;\n");
    simulator(&source, &["short", "back"], Protocol::Lattice)
}

/// The (event, statement, protocol state) of every trace line that starts, resumes, retries
/// or re-issues a statement: "#N ..." in the detail column.
fn starts(report: &Report) -> Vec<(String, usize, String)> {
    let trace = report.trace.as_deref().unwrap_or_default();
    trace
        .lines()
        .filter_map(|line| {
            let event = line.get(20..30)?.trim();
            if !matches!(event, "start" | "resume" | "retry" | "reissue") {
                return None;
            }
            let state = line.get(31..59)?.trim().to_string();
            let detail = line.get(60..)?.strip_prefix('#')?;
            let number = detail.split(' ').next()?.parse().ok()?;
            Some((event.to_string(), number, state))
        })
        .collect()
}

/// Every start the simulator logged names a statement the runtime's own state shows
/// (`run<N>` for the lattice protocol, with `+<hex>` for the others of its batch, bit k =
/// statement N + 1 + k; `tok<N>` for the token baseline).
fn assert_statements_are_the_runtimes(report: &Report, marker: &str) {
    let starts = starts(report);
    assert!(!starts.is_empty(), "{}", report.summary());
    for (event, statement, state) in starts {
        assert!(
            state
                .split(' ')
                .filter_map(|field| field.strip_prefix(marker))
                .any(|field| runs_statement(field, statement)),
            "{event} of #{statement} while the runtime shows `{state}`"
        );
    }
}

#[test]
fn a_reset_just_before_a_turn_ends_in_a_forward_then_reverse_run_is_no_violation() {
    // eight2car then car2eight: M1 reset 30 ms before its turn ends (the case that was once
    // reported as "S1 ... #44 started before its dependencies" although nothing went wrong).
    let sim = simulator(EIGHT2CAR, &["eight2car", "car2eight"], Protocol::Lattice);
    let clean = run(&sim, EIGHT, Some(EIGHT), &Scenario::default(), 1);
    let turn_ends = ends_of(&clean, "M1");
    assert!(!turn_ends.is_empty(), "{}", clean.summary());
    for end in turn_ends {
        let mut scenario = Scenario::default();
        scenario.reset.push(Reset {
            module: "M1".into(),
            at_ms: end.saturating_sub(30),
        });
        let report = run(&sim, EIGHT, Some(EIGHT), &scenario, 1);
        assert!(report.violations.is_empty(), "{}", report.summary());
        assert!(report.success, "{}", report.summary());
        assert_statements_are_the_runtimes(&report, "run");
    }
}

/// When `module`'s operations end in a run (ms), from its "done" trace lines.
fn ends_of(report: &Report, module: &str) -> Vec<u64> {
    let trace = report.trace.as_deref().unwrap_or_default();
    trace
        .lines()
        .filter(|l| l.get(13..19).map(str::trim) == Some(module))
        .filter(|l| l.get(20..30).map(str::trim) == Some("done"))
        .filter_map(|l| l.get(0..12)?.trim().split('.').next()?.parse().ok())
        .collect()
}

/// A random mix of resets, power cycles and blocked links in the first `span_ms`.
fn random_faults(rng: &mut ChaCha8Rng, modules: &[&str], span_ms: u64) -> Scenario {
    let mut scenario = lossy(0.1);
    add_module_faults(rng, &mut scenario, modules, span_ms, 1..=3);
    scenario.faults_until_ms = Some(span_ms + 5_000);
    scenario
}

fn lossy(loss: f64) -> Scenario {
    let mut s = Scenario::default();
    s.network.loss = loss;
    s
}

/// A lattice run under faults: no violation, the goal reached, every start the runtime's own.
fn assert_clean_run(report: &Report, seed: u64, scenario: &Scenario) {
    let context = || format!("seed {seed}, {scenario:?}\n{}", report.summary());
    assert!(report.violations.is_empty(), "{}", context());
    assert!(report.success, "{}", context());
    assert_statements_are_the_runtimes(report, "run");
}

#[test]
fn a_thousand_randomised_fault_runs_forward_then_reverse_have_no_violation() {
    let sim = chain3_and_back();
    let mut rng = ChaCha8Rng::seed_from_u64(19);
    let mut resets = 0;
    for seed in 0..1_000u64 {
        let scenario = random_faults(&mut rng, &["M0", "M1", "M2"], 12_000);
        let report = run(&sim, CHAIN3, Some(CHAIN3), &scenario, seed);
        assert_clean_run(&report, seed, &scenario);
        resets += report.counters.resets;
    }
    assert!(
        resets >= 1_000,
        "the faults struck too rarely: {resets} resets"
    );
}

#[test]
fn randomised_faults_on_eight2car_and_back_have_no_violation() {
    let sim = simulator(EIGHT2CAR, &["eight2car", "car2eight"], Protocol::Lattice);
    let modules = ["M0", "M1", "M2", "M3", "M4", "M5", "M6"];
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    for seed in 0..12u64 {
        let scenario = random_faults(&mut rng, &modules, 60_000);
        let report = run(&sim, EIGHT, Some(EIGHT), &scenario, seed);
        assert_clean_run(&report, seed, &scenario);
    }
}
