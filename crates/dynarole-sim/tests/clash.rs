//! Turns that collide only while they run together: the car's driver turning a quarter while
//! its front axle turns half a turn. Each is fine alone and in either order (the world model
//! accepts both orders and ends alike), so only the search of overlapping motion sees it: the
//! run with `&` gets a `clash` violation at the instant two modules come within the limit,
//! naming both statements; the same turns with `;` never overlap and run clean.

mod common;

use common::*;
use dynarole_codegen::Protocol;
use dynarole_sim::{Report, Scenario, Simulator, Violation};

const CAR: &str = include_str!("../../../robots/atron/examples/car.json");

fn source(separator: &str) -> String {
    format!(
        "robot atron;\nsequence s {{\n    M0.Joint.rotateFromToBy(0, 108, true, 150){separator}\n    \
         M6.Joint.rotateFromToBy(108, 324, true, 150);\n}}\n"
    )
}

/// The run's `clash` violations.
fn clashes(report: &Report) -> Vec<&Violation> {
    (report.violations.iter())
        .filter(|v| v.check == "clash")
        .collect()
}

/// Seeds 1 to 8 of `sim` from `start` have no violation.
fn assert_clean(sim: &Simulator, start: &str, scenario: &Scenario) {
    for seed in 1..=8 {
        let report = run(sim, start, None, scenario, seed);
        assert!(report.violations.is_empty(), "{}", report.summary());
    }
}

#[test]
fn turns_that_meet_only_while_both_run_clash_and_in_order_they_do_not() {
    let scenario = Scenario::default();
    let together = simulator(&source(" &"), &["s"], Protocol::Lattice);
    let clashed: Vec<u64> = (1..=8)
        .filter(|seed| {
            let report = run(&together, CAR, None, &scenario, *seed);
            let clashes = clashes(&report);
            for clash in &clashes {
                assert_eq!(clash.involved.len(), 1, "{clash:?}");
                let pair = [clash.statement, clash.involved[0]];
                assert!(pair.contains(&0) && pair.contains(&1), "{clash:?}");
                assert!(clash
                    .message
                    .contains("closer than the limit (1.2 lattice units)"));
                let trace = report.trace.as_deref().unwrap_or_default();
                assert!(
                    trace.lines().any(|l| l.contains(" clash ")),
                    "no clash line in the trace"
                );
            }
            !clashes.is_empty()
        })
        .collect();
    assert!(!clashed.is_empty(), "no seed of 8 caught the clash");
    let in_order = simulator(&source(";"), &["s"], Protocol::Lattice);
    assert_clean(&in_order, CAR, &scenario);
}

const SNAKE: &str = include_str!("../../../robots/atron/examples/snake.json");

/// Three joints of the snake (the CLI's golden case `check_from_three_turns_meet_only_together`):
/// every two of them are clear together from the start, all three are not: with M3 and M6 done
/// first, M4's turn sweeps M5 into M0. Durations varied by half either way give some runs that
/// timing; the running turns are searched again whenever one ends (the configuration then
/// holds it), so those runs clash, M4's turn among those named. With `;` the runs are clean.
#[test]
fn three_turns_that_meet_only_when_all_three_run_clash() {
    let source = |separator: &str| {
        format!(
            "robot atron;\nsequence s {{\n    M3.Joint.rotateFromToBy(0, 108, true, 150){separator}\n    \
             M4.Joint.rotateFromToBy(0, 108, true, 150){separator}\n    \
             M6.Joint.rotateFromToBy(216, 0, true, 150);\n}}\n"
        )
    };
    let mut scenario = Scenario::default();
    scenario.timing.variation = 0.5;
    let together = simulator(&source(" &"), &["s"], Protocol::Lattice);
    let clashed: Vec<u64> = (1..=16)
        .filter(|seed| {
            let report = run(&together, SNAKE, None, &scenario, *seed);
            let clashes = clashes(&report);
            for clash in &clashes {
                let mut named = clash.involved.clone();
                named.push(clash.statement);
                assert!(named.contains(&1) && named.len() >= 2, "{clash:?}");
            }
            !clashes.is_empty()
        })
        .collect();
    assert!(!clashed.is_empty(), "no seed of 16 caught the clash");
    let in_order = simulator(&source(";"), &["s"], Protocol::Lattice);
    assert_clean(&in_order, SNAKE, &scenario);
}
