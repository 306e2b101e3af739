//! The simulator end to end: eight2car on both protocols, loss, determinism, a reset in the
//! middle of an operation, dead links, power cycles, blocked links, a refused operation, the
//! scenario format, and a golden trace.

mod common;

use common::*;
use dynarole_codegen::Protocol;
use dynarole_sim::{Block, Power, Report, Reset, Scenario};

const CHAIN3_DR: &str = include_str!("data/chain3.dr");
const CHAIN3: &str = include_str!("data/chain3.json");
const CHAIN3_AFTER: &str = include_str!("data/chain3-after.json");

fn ussr() -> Scenario {
    let mut s = Scenario::default();
    s.network.preset = dynarole_sim::PresetName::named(dynarole_sim::USSR.name);
    s
}

fn lossy(loss: f64) -> Scenario {
    let mut s = Scenario::default();
    s.network.loss = loss;
    s
}

fn assert_success(report: &Report) {
    assert!(report.success, "{}", report.summary());
    assert_eq!(report.statements_done, report.statements);
    assert_eq!(report.configuration_matches, Some(true));
}

/// One trace line in its columns: time (ms), module, event, protocol state, detail.
struct Line<'a> {
    ms: u64,
    module: &'a str,
    event: &'a str,
    state: &'a str,
    detail: &'a str,
}

/// Splits a trace line at its fixed columns (time 12, module 6, event 10, state 28).
fn columns(line: &str) -> Line<'_> {
    let field = |from: usize, to: usize| line.get(from..to.min(line.len())).unwrap_or("").trim();
    Line {
        ms: field(0, 8).parse().unwrap_or(0),
        module: field(13, 19),
        event: field(20, 30),
        state: field(31, 59),
        detail: line.get(60..).unwrap_or(""),
    }
}

/// When a module started a statement, from the trace (ms).
fn start_time(report: &Report, statement: usize) -> u64 {
    let trace = report.trace.as_deref().unwrap_or_default();
    let prefix = format!("#{statement} ");
    trace
        .lines()
        .map(columns)
        .find(|l| l.event == "start" && l.detail.starts_with(&prefix))
        .unwrap_or_else(|| panic!("statement {statement} never started:\n{trace}"))
        .ms
}

#[test]
fn eight2car_lattice_reaches_the_car_without_violations() {
    for preset in [dynarole_robot_atron::NETWORK_PRESETS[0], dynarole_sim::USSR] {
        let mut scenario = Scenario::default();
        scenario.network.preset = dynarole_sim::PresetName::named(preset.name);
        let report = eight2car(Protocol::Lattice, &scenario, 1);
        assert_success(&report);
        assert!(report.violations.is_empty(), "{}", report.summary());
        assert_eq!(report.counters.ops_started, 25);
        assert!(report.counters.packets_sent > 100);
    }
}

/// The same run with both disseminations: the fixed period sends a broadcast every 100 ms for
/// the whole run (over 1,000 packets on eight2car), adaptive at least three times fewer, and
/// both reach the car without violations.
#[test]
fn adaptive_dissemination_sends_fewer_packets_than_the_fixed_period() {
    let parsed = dynarole_core::parse(EIGHT2CAR);
    let (program, _) = dynarole_core::analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.expect("eight2car analyses");
    let plans = vec![program.expand("eight2car").expect("eight2car")];
    let sent = |dissemination| {
        let options = dynarole_codegen::CompileOptions {
            dissemination,
            ..options(Protocol::Lattice)
        };
        let sim = dynarole_sim::Simulator::new(&program, &plans, &options).expect("compiles");
        let report = run(&sim, EIGHT, Some(CAR), &Scenario::default(), 1);
        assert_success(&report);
        assert!(report.violations.is_empty(), "{}", report.summary());
        report.counters.packets_sent
    };
    let fixed = sent(dynarole_codegen::Dissemination::Fixed);
    let adaptive = sent(dynarole_codegen::Dissemination::Adaptive);
    assert!(fixed > 1000, "fixed sent {fixed}");
    assert!(
        adaptive * 3 < fixed,
        "adaptive sent {adaptive}, fixed {fixed}"
    );
}

#[test]
fn eight2car_paper_reaches_the_car() {
    for preset in [dynarole_robot_atron::NETWORK_PRESETS[0], dynarole_sim::USSR] {
        let mut scenario = Scenario::default();
        scenario.network.preset = dynarole_sim::PresetName::named(preset.name);
        let report = eight2car(Protocol::Paper, &scenario, 1);
        assert_eq!(
            report.configuration_matches,
            Some(true),
            "{}",
            report.summary()
        );
        assert_eq!(report.statements_done, 25, "{}", report.summary());
        assert!(report.completion_ms.is_some());
    }
}

#[test]
fn eight2car_lattice_survives_thirty_percent_loss() {
    for seed in 0..4 {
        let report = eight2car(Protocol::Lattice, &lossy(0.3), seed);
        assert_success(&report);
        assert!(report.violations.is_empty(), "{}", report.summary());
        assert!(report.counters.lost > 0);
    }
}

#[test]
fn same_seed_same_trace_other_seed_other_trace() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let scenario = lossy(0.2);
    let a = run(&sim, EIGHT, Some(CAR), &scenario, 42);
    let b = run(&sim, EIGHT, Some(CAR), &scenario, 42);
    let c = run(&sim, EIGHT, Some(CAR), &scenario, 43);
    assert!(a.trace.as_ref().is_some_and(|t| !t.is_empty()));
    assert_eq!(a.trace, b.trace);
    assert_eq!(a, b, "the whole report is reproducible");
    assert_ne!(a.trace, c.trace);
}

#[test]
fn reset_in_the_middle_of_an_operation_is_survived_by_the_lattice() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let plain = run(&sim, EIGHT, Some(CAR), &ussr(), 0);
    // M3's first turn (statement 2) lasts 550 ms: reset M3 200 ms into it.
    let at_ms = start_time(&plain, 2) + 200;
    let mut scenario = ussr();
    scenario.reset.push(Reset {
        module: "M3".into(),
        at_ms,
    });
    let report = run(&sim, EIGHT, Some(CAR), &scenario, 0);
    assert_success(&report);
    assert_eq!(report.count("S2"), 0, "{}", report.summary());
    assert_eq!(report.counters.resets, 1);
    let trace = report.trace.as_deref().unwrap_or_default();
    assert!(trace.contains(" M3     reset "), "{trace}");
    // It re-enters the interrupted statement: while the turn still runs (resume) or, when it
    // hears that #0 is done only after the turn ended, by issuing it again (a no-op).
    assert!(
        trace.lines().map(columns).any(|l| l.module == "M3"
            && (l.event == "resume" || l.event == "reissue")
            && l.detail.starts_with("#2 ")),
        "the reset module re-enters its operation:\n{trace}"
    );
}

#[test]
fn dead_links_slow_the_lattice_down_but_do_not_stop_it() {
    let mut scenario = lossy(0.25);
    scenario.network.dead_link_p = 0.3;
    let report = eight2car(Protocol::Lattice, &scenario, 5);
    assert_success(&report);
    assert!(report.counters.dead > 0, "{}", report.summary());
}

#[test]
fn power_cycle_and_blocked_link_are_survived_by_the_lattice() {
    let mut scenario = Scenario::default();
    scenario.power.push(Power {
        module: "M2".into(),
        off_ms: 5_000,
        on_ms: 9_000,
    });
    scenario.block.push(Block {
        module: "M3".into(),
        connector: 2,
        from_ms: 1_000,
        to_ms: 8_000,
    });
    let report = eight2car(Protocol::Lattice, &scenario, 3);
    assert_success(&report);
    assert_eq!(report.counters.power_cycles, 1);
    assert!(report.counters.blocked > 0, "{}", report.summary());
    assert!(report.counters.off > 0);
}

#[test]
fn faults_stop_at_the_end_of_the_faults_phase() {
    let mut scenario = lossy(0.9);
    scenario.faults_until_ms = Some(10_000);
    let report = eight2car(Protocol::Lattice, &scenario, 2);
    assert_success(&report);
    let trace = report.trace.as_deref().unwrap_or_default();
    let late_loss = trace.lines().any(|l| {
        l.contains(" lost ")
            && l.split('.')
                .next()
                .and_then(|t| t.trim().parse::<u64>().ok())
                >= Some(10_000)
    });
    assert!(!late_loss, "no loss after faults_until_ms");
}

#[test]
fn an_impossible_operation_is_reported_and_the_goal_not_reached() {
    // M2 has nothing facing its connector 4 in the chain.
    let source = "robot atron;\nsequence bad { M2.Connector[4].extend(); }\n";
    let sim = simulator(source, &["bad"], Protocol::Lattice);
    let mut scenario = ussr();
    scenario.timeout_ms = 10_000;
    let report = run(&sim, CHAIN3, None, &scenario, 0);
    assert!(!report.success);
    assert!(!report.refusals.is_empty(), "{}", report.summary());
    assert!(
        report.refusals[0].reason.contains("M2"),
        "{:?}",
        report.refusals
    );
    assert!(report.failures.iter().any(|f| f.contains("timeout")));
}

#[test]
fn scenario_errors_name_the_field() {
    let unknown = Scenario::from_toml_str("[network]\nlos = 0.1\n").map(|_| ());
    let message = unknown.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(message.contains("los"), "{message}");
    // A value checked after parsing: the field, and the span of its value in the text.
    let text = "[network]\nloss = 1.5\n";
    let range = Scenario::from_toml_str(text).expect_err("1.5 is not a probability");
    assert_eq!(range.field, "network.loss");
    assert_eq!(range.span.and_then(|s| text.get(s)), Some("1.5"));
    let text = "faults_until_ms = 1000\n[[reset]]\nmodule = \"M3\"\nat_ms = 2000\n";
    let late = Scenario::from_toml_str(text).expect_err("after the faults");
    assert_eq!(late.field, "reset[0].at_ms");
    assert_eq!(late.span.and_then(|s| text.get(s)), Some("2000"));
    let full = Scenario::from_toml_str(
        "timeout_ms = 60000\nfaults_until_ms = 30000\n[network]\nloss = 0.1\ndead_link_p = 0.05\ndead_loss = 0.98\npreset = \"ussr\"\n[timing]\njoint = \"realistic\"\n[[reset]]\nmodule = \"M3\"\nat_ms = 12000\n[[power]]\nmodule = \"M1\"\noff_ms = 1000\non_ms = 2000\n[[block]]\nmodule = \"M0\"\nconnector = 4\nfrom_ms = 0\nto_ms = 500\n[random_resets]\ninterval_ms = 1000\nprobability = 0.01\n",
    );
    assert!(full.is_ok(), "{full:?}");
}

#[test]
fn unknown_module_in_a_scenario_is_bad_input() {
    let sim = simulator(CHAIN3_DR, &["short"], Protocol::Lattice);
    let mut scenario = ussr();
    scenario.reset.push(Reset {
        module: "M9".into(),
        at_ms: 10,
    });
    let start = config(CHAIN3);
    let result = sim.run(&dynarole_sim::Run {
        start: &start,
        expect: None,
        scenario: &scenario,
        seed: 0,
        trace: false,
    });
    let message = result.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(message.contains("reset[0].module"), "{message}");
}

#[test]
fn the_trace_shows_each_modules_protocol_state() {
    for (protocol, end) in [
        (Protocol::Lattice, "e1 low0 done0 run-"),
        (Protocol::Paper, "s254 "),
    ] {
        let report = eight2car(protocol, &Scenario::default(), 1);
        let trace = report.trace.as_deref().unwrap_or_default();
        let lines: Vec<Line> = trace.lines().map(columns).collect();
        assert!(lines.iter().all(|l| !l.state.is_empty()), "{trace}");
        // Before its first init a module has no state; when it declares the end, its state
        // says so (the lattice's epoch rolled over, the paper's END state).
        let first = lines.iter().find(|l| l.event == "power-on");
        assert_eq!(first.map(|l| l.state), Some("-"), "{trace}");
        let finished: Vec<&Line> = lines.iter().filter(|l| l.event == "finished").collect();
        assert_eq!(finished.len(), 7, "{trace}");
        assert!(finished.iter().all(|l| l.state.starts_with(end)), "{trace}");
        // A module that starts a statement is running it (lattice: `run<statement>`, or in
        // its batch, `run<first>+<others>`).
        if protocol == Protocol::Lattice {
            assert!(lines.iter().filter(|l| l.event == "start").all(|l| {
                let statement = l.detail.split(' ').next().and_then(|s| s.strip_prefix('#'));
                let run = l
                    .state
                    .split(' ')
                    .nth(3)
                    .and_then(|s| s.strip_prefix("run"));
                match (statement.and_then(|s| s.parse().ok()), run) {
                    (Some(s), Some(run)) => runs_statement(run, s),
                    _ => false,
                }
            }));
        }
    }
}

#[test]
fn golden_trace_of_a_short_run() {
    let sim = simulator(CHAIN3_DR, &["short"], Protocol::Lattice);
    let report = run(&sim, CHAIN3, Some(CHAIN3_AFTER), &ussr(), 0);
    assert_success(&report);
    let text = format!(
        "{CHAIN3_DR}\n----- trace (lattice, ussr preset, seed 0) -----\n{}\n----- summary -----\n{}",
        report.trace.as_deref().unwrap_or_default(),
        report.summary()
    );
    insta::assert_snapshot!("chain3_short_trace", text);
}

#[test]
fn random_resets_are_survived_by_the_lattice() {
    let mut scenario = lossy(0.1);
    scenario.faults_until_ms = Some(20_000);
    scenario.random_resets = Some(dynarole_sim::RandomResets {
        interval_ms: 1_000,
        probability: 0.05,
    });
    let report = eight2car(Protocol::Lattice, &scenario, 11);
    assert_success(&report);
    assert!(report.counters.resets > 0, "{}", report.summary());
    assert!(report.violations.is_empty(), "{}", report.summary());
}

#[test]
fn a_reset_first_module_of_the_paper_protocol_reissues_and_s2_catches_it() {
    let mut scenario = ussr();
    scenario.reset.push(Reset {
        module: "M0".into(),
        at_ms: 8_000,
    });
    let report = eight2car(Protocol::Paper, &scenario, 0);
    assert!(!report.success);
    assert!(report.count("S2") >= 1, "{}", report.summary());
    let s2 = report.violations.iter().find(|v| v.check == "S2");
    assert_eq!(
        s2.map(|v| (v.module.as_str(), v.statement)),
        Some(("M0", 0))
    );
}

#[test]
fn operation_durations_vary_when_asked_and_stay_reproducible() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let exact = run(&sim, EIGHT, Some(CAR), &Scenario::default(), 5);
    let mut varied_scenario = Scenario::default();
    varied_scenario.timing.variation = 0.2;
    let varied = run(&sim, EIGHT, Some(CAR), &varied_scenario, 5);
    let again = run(&sim, EIGHT, Some(CAR), &varied_scenario, 5);
    assert_success(&varied);
    assert!(varied.violations.is_empty(), "{}", varied.summary());
    assert_eq!(
        varied.trace, again.trace,
        "the same seed varies them the same way"
    );
    assert_ne!(varied.completion_ms, exact.completion_ms);
    let bad = Scenario::from_toml_str("[timing]\nvariation = 1.5\n").map(|_| ());
    assert!(bad.is_err_and(|e| e.field == "timing.variation"));
}

/// A scenario in which M0 hears, from power-on, what a second robot's M0 running the same
/// program broadcasts once that robot has finished (the end), under robot identity `robot`
/// in execution `execution` (`None`: another launch's).
fn finished_twin_in_range(robot: u16, execution: Option<u32>) -> Scenario {
    let mut scenario = ussr();
    scenario.foreign.push(dynarole_sim::Foreign {
        module: "M0".into(),
        connector: 0,
        robot,
        from_ms: 0,
        to_ms: 20_000,
        interval_ms: 100,
        execution,
    });
    scenario
}

/// eight2car built with a key (`compile --key`) for the launch `execution`.
fn keyed_eight2car(protocol: Protocol, execution: u32) -> dynarole_sim::Simulator {
    let parsed = dynarole_core::parse(EIGHT2CAR);
    let program = dynarole_core::driver::check(&parsed, &dynarole_robots::plugins())
        .unwrap_or_else(|diagnostics| panic!("{diagnostics:?}"));
    let plans = dynarole_core::driver::plans(&program, &["eight2car".to_string()])
        .expect("eight2car exists");
    let options = dynarole_codegen::CompileOptions {
        key: Some(*b"\x00\x11\x22\x33\x44\x55\x66\x77\x88\x99\xaa\xbb\xcc\xdd\xee\xff"),
        execution,
        ..options(protocol)
    };
    dynarole_sim::Simulator::new(&program, &plans, &options).expect("compiles")
}

#[test]
fn packets_of_another_robot_running_the_same_program_are_ignored() {
    let report = eight2car(Protocol::Lattice, &finished_twin_in_range(1, None), 1);
    assert_success(&report);
    assert!(report.counters.foreign >= 100, "{}", report.summary());
    let trace = report.trace.as_deref().unwrap_or_default();
    assert!(
        trace.contains("robot 1 -> M0.C0"),
        "the trace shows the injections"
    );
}

#[test]
fn the_same_packets_under_this_robots_identity_would_end_the_run_early() {
    // What the robot identity and the execution protect against: the other robot's "end",
    // taken as ours, makes the modules stop before the reconfiguration is done (robot 0 and
    // execution 0 are this robot's: a launch that reused the last launch's execution).
    for protocol in [Protocol::Lattice, Protocol::Paper] {
        let report = eight2car(protocol, &finished_twin_in_range(0, Some(0)), 1);
        assert!(!report.success, "{}", report.summary());
        assert!(
            report.statements_done < report.statements,
            "{}",
            report.summary()
        );
    }
}

#[test]
fn a_recorded_end_of_another_launch_is_refused_in_a_keyed_build() {
    // The replay: the end packets of an earlier launch of the same program, sent under this
    // robot's identity with the key (as a recorder in range replays them). The execution the
    // tag covers is another one: every module drops them as foreign and the run is whole.
    for protocol in [Protocol::Lattice, Protocol::Paper] {
        let sim = keyed_eight2car(protocol, 41);
        for execution in [None, Some(40), Some(0)] {
            let scenario = finished_twin_in_range(0, execution);
            let report = run(&sim, EIGHT, Some(CAR), &scenario, 1);
            assert_success(&report);
            assert_eq!(report.statements_done, 25, "{}", report.summary());
            assert!(report.violations.is_empty(), "{}", report.summary());
            assert!(report.counters.foreign >= 100, "{}", report.summary());
            let trace = report.trace.as_deref().unwrap_or_default();
            assert!(
                trace.contains("robot 0 -> M0.C0"),
                "the trace shows the stale packets"
            );
        }
        // The same recording of this very launch (an execution used twice) is taken for
        // ours: the modules declare the end with the reconfiguration not done.
        let report = run(
            &sim,
            EIGHT,
            Some(CAR),
            &finished_twin_in_range(0, Some(41)),
            1,
        );
        assert!(!report.success, "{}", report.summary());
        assert!(
            report.statements_done < report.statements,
            "{}",
            report.summary()
        );
    }
}

#[test]
fn foreign_packets_are_checked_like_the_other_faults() {
    let text = "[[foreign]]\nmodule = \"M0\"\nconnector = 0\nrobot = 1\nfrom_ms = 10\nto_ms = 5\n";
    let error = Scenario::from_toml_str(text).expect_err("to_ms before from_ms");
    assert_eq!(error.field, "foreign[0].to_ms");
    let text = "[[foreign]]\nmodule = \"M0\"\nconnector = 0\nrobot = 1\nfrom_ms = 0\nto_ms = 100000000\ninterval_ms = 1\n";
    let error = Scenario::from_toml_str(text).expect_err("too many packets");
    assert_eq!(error.field, "foreign[0]");
}
