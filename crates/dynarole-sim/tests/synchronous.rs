//! Synchronous groups in the simulator: on the snake, M3's half turn alone sweeps M0 into M6
//! (the world refuses it at its end when it ends first), and with M4's half turn the other
//! way it does not. Written with `&`, some runs have M3's turn refused; written
//! `sync { ... }`, the two start at one agreed instant (ready bits, then a countdown every
//! module learns with the age of its news) and move at one pace, and every run is clean,
//! with a loss of packets, with durations varied at random, and with a member reset.

mod common;

use common::*;
use dynarole_codegen::Protocol;
use dynarole_core::synchronous::SKEW_PER_HOP_MS;
use dynarole_sim::{Power, Report, Reset, Scenario};

const SNAKE: &str = include_str!("../../../robots/atron/examples/snake.json");

fn source(group: &str) -> String {
    let turns =
        "M3.Joint.rotateFromToBy(0, 216, true, 150) & M4.Joint.rotateFromToBy(0, 216, false, 150)";
    let body = match group {
        "sync" => format!("sync {{ {turns}; }};"),
        _ => format!("{turns};"),
    };
    format!("robot atron;\nsequence s {{\n    {body}\n}}\n")
}

/// Each statement's first start and its completion, in ms, from the trace.
fn start_and_done(report: &Report, statement: usize) -> (f64, f64) {
    let trace = report.trace.as_deref().unwrap_or_default();
    let tag = format!("#{statement} ");
    let time = |event: &str| {
        trace
            .lines()
            .filter(|l| l.contains(&tag))
            .find(|l| l.split_whitespace().nth(2) == Some(event))
            .and_then(|l| l.split_whitespace().next()?.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("no {event} of #{statement}:\n{trace}"))
    };
    (time("start"), time("done"))
}

fn assert_clean(report: &Report) {
    assert!(report.success, "{}", report.summary());
    assert!(report.violations.is_empty(), "{}", report.summary());
    assert_eq!(report.counters.ops_refused, 0, "{}", report.summary());
}

#[test]
fn a_synchronous_pair_runs_clean_where_the_same_turns_joined_by_and_are_refused() {
    let parallel = simulator(&source("&"), &["s"], Protocol::Lattice);
    let refused = (1..=12)
        .filter(|&seed| {
            run(&parallel, SNAKE, None, &Scenario::default(), seed)
                .counters
                .ops_refused
                > 0
        })
        .count();
    assert!(refused > 0, "no run of the `&` form had M3's turn refused");
    let sync = simulator(&source("sync"), &["s"], Protocol::Lattice);
    for loss in [0.0, 0.3] {
        let mut scenario = Scenario::default();
        scenario.network.loss = loss;
        for seed in 1..=12 {
            let report = run(&sync, SNAKE, None, &scenario, seed);
            assert_clean(&report);
            // M3 and M4 are neighbours: one hop.
            let spread = report.synchronous_spread_ms.expect("a synchronous group");
            assert!(
                spread <= SKEW_PER_HOP_MS as f64,
                "loss {loss} seed {seed}: {spread} ms"
            );
        }
    }
}

#[test]
fn the_turns_of_a_synchronous_group_keep_one_pace_when_durations_vary() {
    let sync = simulator(&source("sync"), &["s"], Protocol::Lattice);
    let mut scenario = Scenario::default();
    scenario.timing.variation = 0.5;
    for seed in 1..=6 {
        let report = run(&sync, SNAKE, None, &scenario, seed);
        assert_clean(&report);
        let (start3, done3) = start_and_done(&report, 0);
        let (start4, done4) = start_and_done(&report, 1);
        let (took3, took4) = (done3 - start3, done4 - start4);
        assert!(
            (took3 - took4).abs() < 1e-6,
            "seed {seed}: {took3} ms and {took4} ms"
        );
    }
}

#[test]
fn a_member_reset_before_or_during_the_group_does_not_stop_it() {
    let sync = simulator(&source("sync"), &["s"], Protocol::Lattice);
    // About 300 ms in, M4 is ready and counting down; at 900 ms it is turning.
    for at_ms in [300, 900] {
        let mut scenario = Scenario::default();
        scenario.reset.push(Reset {
            module: "M4".into(),
            at_ms,
        });
        for seed in 1..=4 {
            let report = run(&sync, SNAKE, None, &scenario, seed);
            assert!(report.success, "reset at {at_ms} ms: {}", report.summary());
            assert_eq!(report.counters.resets, 1, "{}", report.summary());
            let ordering: Vec<_> = (report.violations.iter())
                .filter(|v| v.check.starts_with('S'))
                .collect();
            assert!(ordering.is_empty(), "{ordering:?}");
        }
    }
}

/// A power cut stops a member's turn where it is, and the others go on: lock-step is lost,
/// which the runtime cannot prevent. The simulator searches a synchronous group's turns with
/// every pair of points while any of them runs, so the collision that follows is reported.
#[test]
fn a_member_losing_power_mid_turn_breaks_lock_step_and_the_clash_is_reported() {
    let sync = simulator(&source("sync"), &["s"], Protocol::Lattice);
    let mut scenario = Scenario::default();
    scenario.power.push(Power {
        module: "M4".into(),
        off_ms: 700,
        on_ms: 1000,
    });
    let report = run(&sync, SNAKE, None, &scenario, 1);
    let clashes: Vec<_> = report
        .violations
        .iter()
        .filter(|v| v.check == "clash")
        .collect();
    assert!(!clashes.is_empty(), "{}", report.summary());
    assert!(
        clashes.iter().all(|c| c.message.contains("M0 and M6")),
        "{clashes:?}"
    );
}

/// Every joint of the original authors' chain of 15 in one group: the ends are 14 hops
/// apart. On the ATRON preset, a module between two neighbours can miss the countdown while
/// their answers to it collide at its half-duplex side, again and again; the countdown is
/// therefore sent again until the start (DR_CONF_SYNC_REPEAT_MS). Sent only once, 4 of these
/// 200 lossless runs had a member hear it only after its neighbours had started, and start
/// seconds late.
#[test]
fn every_member_of_a_long_chain_hears_the_countdown_in_time_without_loss() {
    const CHAIN: &str = include_str!("../../../robots/atron/examples/rotation-chain-15.json");
    let turns: Vec<String> = (0..15)
        .map(|k| format!("M{k}.Joint.rotateFromToBy(0, 216, true, 150)"))
        .collect();
    let source = format!(
        "robot atron;\nsequence s {{\n    sync {{ {}; }};\n}}\n",
        turns.join(" & ")
    );
    let sync = simulator(&source, &["s"], Protocol::Lattice);
    let bound = 14.0 * SKEW_PER_HOP_MS as f64;
    for seed in 1..=200 {
        let report = run(&sync, CHAIN, None, &Scenario::default(), seed);
        assert_clean(&report);
        let spread = report.synchronous_spread_ms.expect("a synchronous group");
        assert!(spread <= bound, "seed {seed}: {spread} ms");
    }
}
