//! Turns that collide only while they run together: the car's driver turning a quarter while
//! its front axle turns half a turn. Each is fine alone and in either order (the world model
//! accepts both orders and ends alike), so only the search of overlapping motion sees it: the
//! run with `&` gets a `clash` violation at the instant two modules come within the limit,
//! naming both statements; the same turns with `;` never overlap and run clean.

mod common;

use common::*;
use dynarole_codegen::Protocol;
use dynarole_sim::Scenario;

const CAR: &str = include_str!("../../../robots/atron/examples/car.json");

fn source(separator: &str) -> String {
    format!(
        "robot atron;\nsequence s {{\n    M0.Joint.rotateFromToBy(0, 108, true, 150){separator}\n    \
         M6.Joint.rotateFromToBy(108, 324, true, 150);\n}}\n"
    )
}

#[test]
fn turns_that_meet_only_while_both_run_clash_and_in_order_they_do_not() {
    let scenario = Scenario::default();
    let together = simulator(&source(" &"), &["s"], Protocol::Lattice);
    let clashed: Vec<u64> = (1..=8)
        .filter(|seed| {
            let report = run(&together, CAR, None, &scenario, *seed);
            let clashes: Vec<_> = report
                .violations
                .iter()
                .filter(|v| v.check == "clash")
                .collect();
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
    for seed in 1..=8 {
        let report = run(&in_order, CAR, None, &scenario, seed);
        assert!(report.violations.is_empty(), "{}", report.summary());
    }
}
