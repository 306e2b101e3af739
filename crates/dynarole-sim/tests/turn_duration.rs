//! How long a joint turn takes (crates/dynarole-sim/SCENARIO.md, `[timing]`): by the number of
//! quarter turns it makes, and no time at all when the joint is already at the target, as
//! when a turn is issued again after it completed.

mod common;

use common::{run, simulator, CAR, EIGHT, EIGHT2CAR};
use dynarole_codegen::Protocol;
use dynarole_sim::{JointModel, Report, Reset, Scenario};

const CHAIN3: &str = include_str!("data/chain3.json");

/// M0 of the chain starts at angle 0. #0 says it turns from 108 to 0 (the joint is at 0
/// already), #1 makes a quarter turn to 108, #2 turns to 108 (there already), #3 a half turn
/// (108 to 324 upwards: two quarters).
const TURNS: &str = "robot atron;\nsequence turns {\n    M0.Joint.rotateFromToBy(108, 0, true, 150);\n    M0.Joint.rotateFromToBy(0, 108, true, 150);\n    M0.Joint.rotateToBy(108, true, 150);\n    M0.Joint.rotateFromToBy(108, 324, true, 150);\n}\n";

/// (start, done) of each statement on the trace, in ms.
fn start_and_done(report: &Report, statements: usize) -> Vec<(f64, f64)> {
    let trace = report.trace.as_deref().unwrap_or_default();
    let when = |event: &str, s: usize| {
        let tag = format!("#{s} ");
        trace
            .lines()
            .find(|line| {
                let mut words = line.split_whitespace().skip(2);
                words.next() == Some(event) && line.contains(&tag)
            })
            .and_then(|line| line.split_whitespace().next()?.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("no {event} of #{s}:\n{trace}"))
    };
    (0..statements)
        .map(|s| (when("start", s), when("done", s)))
        .collect()
}

#[test]
fn a_turn_to_the_angle_the_joint_has_takes_no_time() {
    let sim = simulator(TURNS, &["turns"], Protocol::Lattice);
    for (joint, quarter, half) in [
        (JointModel::Ussr, 550.0, 860.0),
        (JointModel::Realistic, 2_100.0, 3_600.0),
    ] {
        let mut scenario = Scenario::default();
        scenario.timing.joint = joint;
        let report = run(&sim, CHAIN3, None, &scenario, 1);
        assert!(report.success, "{}", report.summary());
        assert!(report.violations.is_empty(), "{}", report.summary());
        let times = start_and_done(&report, 4);
        let took: Vec<f64> = times
            .iter()
            .map(|(start, done)| (done - start).round())
            .collect();
        assert_eq!(took, vec![0.0, quarter, 0.0, half], "{times:?}");
    }
}

/// M3 is reset 5 ms before its first turn (statement 2, a quarter turn: 550 ms) ends. The turn
/// completes; M3's runtime, which restored "#2 started, not done" from its NV record, issues
/// it again after that, and the joint is already at the target: done at once.
#[test]
fn a_turn_issued_again_after_it_completed_takes_no_time() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let mut scenario = Scenario::default();
    scenario.network.preset = dynarole_sim::PresetName::named(dynarole_sim::USSR.name);
    let plain = run(&sim, EIGHT, Some(CAR), &scenario, 0);
    let (start, done) = start_and_done(&plain, 3)[2];
    assert_eq!((done - start).round(), 550.0);
    scenario.reset.push(Reset {
        module: "M3".into(),
        at_ms: start as u64 + 545,
    });
    let report = run(&sim, EIGHT, Some(CAR), &scenario, 0);
    assert!(report.success, "{}", report.summary());
    assert!(report.violations.is_empty(), "{}", report.summary());
    assert_eq!(report.counters.ops_reissued, 1, "{}", report.summary());
    let trace = report.trace.as_deref().unwrap_or_default();
    let of_2: Vec<(f64, &str)> = trace
        .lines()
        .filter(|line| line.contains("#2 "))
        .filter_map(|line| {
            let mut words = line.split_whitespace();
            let ms = words.next()?.parse::<f64>().ok()?;
            let event = words.nth(1)?;
            ["reissue", "done"].contains(&event).then_some((ms, event))
        })
        .collect();
    let reissued = of_2
        .iter()
        .position(|(_, event)| *event == "reissue")
        .unwrap_or_else(|| panic!("#2 not issued again:\n{trace}"));
    assert!(
        of_2[..reissued].iter().any(|(_, e)| *e == "done"),
        "{of_2:?}"
    );
    let (at, _) = of_2[reissued];
    assert_eq!(of_2.get(reissued + 1), Some(&(at, "done")), "{of_2:?}");
}
