//! How long an operation takes (crates/dynarole-sim/SCENARIO.md, `[timing]`): as the robot's
//! timing preset the scenario names says (ATRON's `ussr` and `realistic`), the scenario's
//! `extend_ms` and `retract_ms` in place of the preset's; a turn by the number of quarter turns
//! it makes, and no time at all when the joint is already at the target, as when a turn is
//! issued again after it completed.

mod common;

use common::{config, run, simulator, CAR, EIGHT, EIGHT2CAR};
use dynarole_codegen::Protocol;
use dynarole_sim::{Report, Reset, Run, Scenario, SimError};

const CHAIN3: &str = include_str!("data/chain3.json");
const CHAIN3_DR: &str = include_str!("data/chain3.dr");

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

/// How long each statement took, in ms.
fn took(report: &Report, statements: usize) -> Vec<f64> {
    (start_and_done(report, statements).iter())
        .map(|(start, done)| (done - start).round())
        .collect()
}

/// A scenario read from its text, as `--scenario` reads it.
fn scenario(text: &str) -> Scenario {
    Scenario::from_toml_str(text).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_turn_to_the_angle_the_joint_has_takes_no_time() {
    let sim = simulator(TURNS, &["turns"], Protocol::Lattice);
    // ATRON's presets by name, its first without one, and the older field name `joint`.
    for (timing, quarter, half) in [
        ("", 550.0, 860.0),
        ("[timing]\npreset = \"ussr\"\n", 550.0, 860.0),
        ("[timing]\npreset = \"realistic\"\n", 2_100.0, 3_600.0),
        ("[timing]\njoint = \"realistic\"\n", 2_100.0, 3_600.0),
    ] {
        let scenario = scenario(timing);
        let report = run(&sim, CHAIN3, None, &scenario, 1);
        assert!(report.success, "{}", report.summary());
        assert!(report.violations.is_empty(), "{}", report.summary());
        assert_eq!(took(&report, 4), vec![0.0, quarter, 0.0, half], "{timing}");
    }
}

/// chain3's `short`: #0 a retract, #1 an extend, #2 a half turn. The scenario's `extend_ms`
/// and `retract_ms` replace the preset's; the preset's turn stays.
#[test]
fn extend_ms_and_retract_ms_replace_the_presets() {
    let sim = simulator(CHAIN3_DR, &["short"], Protocol::Lattice);
    let plain = run(&sim, CHAIN3, None, &Scenario::default(), 0);
    assert_eq!(took(&plain, 3), vec![2_000.0, 3_000.0, 860.0]);
    let text = "[timing]\npreset = \"realistic\"\nextend_ms = 1234\nretract_ms = 567\n";
    let report = run(&sim, CHAIN3, None, &scenario(text), 0);
    assert!(report.success, "{}", report.summary());
    assert_eq!(took(&report, 3), vec![567.0, 1_234.0, 3_600.0]);
    let durations = sim.durations(&scenario(text).timing).expect("known");
    assert_eq!(
        (durations.extend_ms, durations.retract_ms),
        (1234, 567),
        "the critical path weighs the same"
    );
    let path = sim.critical_path(&durations);
    assert_eq!(path.duration_ms, 567 + 3_600);
}

/// A preset the robot does not have is refused at `timing.preset`, naming the robot's, before
/// any run; a run asked for anyway is bad input, never one with some other durations.
#[test]
fn an_unknown_timing_preset_is_refused_at_its_field() {
    let sim = simulator(CHAIN3_DR, &["short"], Protocol::Lattice);
    let text = "[timing]\npreset = \"realistc\"\n";
    let scenario = scenario(text);
    let start = config(CHAIN3);
    let error = sim.check_scenario(&scenario, &start).expect_err("unknown");
    assert_eq!(error.field, "timing.preset");
    assert_eq!(
        error.message,
        "unknown timing preset `realistc`; robot `atron` has `ussr` and `realistic`"
    );
    assert_eq!(error.hint.as_deref(), Some("did you mean `realistic`?"));
    let located = error.locate(text);
    assert_eq!(located.span.and_then(|s| text.get(s)), Some("\"realistc\""));
    let refused = sim.run(&Run {
        start: &start,
        expect: None,
        scenario: &scenario,
        seed: 0,
        trace: false,
    });
    match refused {
        Err(SimError::Input(message)) => assert!(message.contains("`timing.preset`"), "{message}"),
        other => panic!("not refused as bad input: {:?}", other.map(|r| r.summary())),
    }
    assert!(sim.durations(&scenario.timing).is_err());
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
