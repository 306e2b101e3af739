//! Operation faults of the scenario file on eight2car: transient failures drawn per attempt
//! (`[faults]`), stuck parts (`[[stuck]]`) and modules that die in place (`[[dead]]`). A
//! failed attempt ends without effect and leaves its statement failed; scenarios without
//! these faults give the very same trace as before.

mod common;

use common::*;
use dynarole_codegen::Protocol;
use dynarole_sim::{Report, Run, Scenario, Simulator};

fn eight2car_sim() -> Simulator {
    simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice)
}

fn scenario(text: &str) -> Scenario {
    Scenario::from_toml_str(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn run_text(sim: &Simulator, text: &str, seed: u64) -> Report {
    run(sim, EIGHT, Some(CAR), &scenario(text), seed)
}

fn trace(report: &Report) -> &str {
    report.trace.as_deref().unwrap_or_default()
}

/// One trace line's columns: time (ms), module, event, and the whole line.
struct Line<'a> {
    ms: f64,
    module: &'a str,
    event: &'a str,
    text: &'a str,
}

fn lines(report: &Report) -> Vec<Line<'_>> {
    trace(report)
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|text| {
            Some(Line {
                ms: text.get(0..12)?.trim().parse().ok()?,
                module: text.get(13..19)?.trim(),
                event: text.get(20..30)?.trim(),
                text,
            })
        })
        .collect()
}

/// Events that begin a physical attempt.
fn begins(event: &str) -> bool {
    matches!(event, "start" | "retry" | "reissue")
}

#[test]
fn every_turn_fails_at_probability_one_and_nothing_else_does() {
    let sim = eight2car_sim();
    let text = "timeout_ms = 40000\n[faults.operation_failure]\nturn = 1.0\n";
    let report = run_text(&sim, text, 1);
    let lines = lines(&report);
    let turn = |l: &Line| l.text.contains(".Joint.rotate");
    let attempts = lines.iter().filter(|l| begins(l.event) && turn(l)).count();
    let failed: Vec<&Line> = lines.iter().filter(|l| l.event == "failed").collect();
    assert!(!failed.is_empty(), "{}", trace(&report));
    assert!(failed
        .iter()
        .all(|l| turn(l) && l.text.ends_with(": transient")));
    let ended = failed.len() + lines.iter().filter(|l| l.event == "interrupt").count();
    // Every turn attempt failed (the last may still run when the run stops).
    assert!(
        attempts == ended || attempts == ended + 1,
        "{}",
        trace(&report)
    );
    assert!(!lines.iter().any(|l| l.event == "done" && turn(l)));
    assert!(
        lines.iter().any(|l| l.event == "done"),
        "other kinds do not fail"
    );
    assert!(!report.success, "{}", report.summary());
}

#[test]
fn probability_zero_gives_the_trace_of_no_faults_byte_for_byte() {
    let sim = eight2car_sim();
    let clean = run_text(&sim, "", 3);
    assert!(clean.success, "{}", clean.summary());
    for text in [
        "[faults]\noperation_failure = 0.0\n",
        "[faults]\noperation_failure = 0\n",
        "[faults.operation_failure]\nturn = 0.0\nextend = 0.0\n",
    ] {
        let report = run_text(&sim, text, 3);
        assert_eq!(trace(&report), trace(&clean), "{text}");
        assert_eq!(report.counters, clean.counters, "{text}");
    }
}

#[test]
fn the_same_seed_gives_the_same_failures_and_another_seed_others() {
    let sim = eight2car_sim();
    let text = "timeout_ms = 120000\n[faults]\noperation_failure = 0.2\n";
    let first = run_text(&sim, text, 5);
    let again = run_text(&sim, text, 5);
    assert_eq!(trace(&first), trace(&again));
    assert!(trace(&first).contains(" failed "), "{}", trace(&first));
    let other = run_text(&sim, text, 6);
    assert_ne!(trace(&first), trace(&other));
}

#[test]
fn no_attempt_fails_after_the_faults_on_phase() {
    let sim = eight2car_sim();
    let text = "faults_until_ms = 5000\n[faults.operation_failure]\nturn = 1.0\n";
    let report = run_text(&sim, text, 1);
    let lines = lines(&report);
    let failed: Vec<f64> = lines
        .iter()
        .filter(|l| l.event == "failed")
        .map(|l| l.ms)
        .collect();
    assert!(!failed.is_empty(), "{}", trace(&report));
    // A turn takes at most a few seconds: only attempts begun before 5 s may fail.
    assert!(failed.iter().all(|ms| *ms < 8_000.0), "{failed:?}");
}

#[test]
fn a_stuck_part_fails_its_statements_from_its_time_and_not_before() {
    let sim = eight2car_sim();
    let clean = run_text(&sim, "", 1);
    // M3's joint turns in #2 (from about 2.1 s) and in #20 (from about 21.5 s).
    let stuck = |from_ms: u64| {
        format!(
            "timeout_ms = 60000\nfaults_until_ms = 5000\n\
             [[stuck]]\nmodule = \"M3\"\npart = \"Joint\"\nfrom_ms = {from_ms}\n"
        )
    };
    let report = run_text(&sim, &stuck(10_000), 1);
    let lines = lines(&report);
    let failed: Vec<&Line> = lines.iter().filter(|l| l.event == "failed").collect();
    assert!(!failed.is_empty(), "{}", trace(&report));
    for l in &failed {
        assert_eq!(l.module, "M3");
        assert!(l.text.contains("#20 M3.Joint") && l.text.ends_with(": stuck Joint"));
    }
    assert!(lines
        .iter()
        .any(|l| l.event == "done" && l.text.contains("#2 M3.Joint")));
    assert!(!lines
        .iter()
        .any(|l| l.event == "done" && l.text.contains("#20 ")));
    assert!(!report.success, "{}", report.summary());
    // Nothing differs before the part breaks.
    let before = |r: &Report| -> Vec<String> {
        let all = self::lines(r);
        let early = all.into_iter().filter(|l| l.ms < 10_000.0);
        early.map(|l| l.text.to_string()).collect()
    };
    assert_eq!(before(&report), before(&clean));
    // A part that breaks after the run has ended changes nothing.
    let late = run_text(&sim, &stuck(100_000).replace("60000", "300000"), 1);
    assert_eq!(trace(&late), trace(&clean));
    assert!(late.success, "{}", late.summary());
}

#[test]
fn a_stuck_connector_fails_from_the_start() {
    let sim = eight2car_sim();
    let text =
        "timeout_ms = 30000\n[[stuck]]\nmodule = \"M3\"\npart = \"Connector[4]\"\nfrom_ms = 0\n";
    let report = run_text(&sim, text, 1);
    let lines = lines(&report);
    let failed: Vec<&Line> = lines.iter().filter(|l| l.event == "failed").collect();
    assert!(!failed.is_empty(), "{}", trace(&report));
    assert!(failed
        .iter()
        .all(|l| l.text.contains("#1 M3.Connector[4].retract()")
            && l.text.ends_with(": stuck Connector[4]")));
    assert!(!report.success);
}

/// A module that dies is a power-off that never ends: the same run, but its `dead` line.
#[test]
fn a_dead_module_stops_where_it_is_and_is_silent() {
    let sim = eight2car_sim();
    // M6's retract of Connector[2] runs from about 3.26 s to 5.26 s: it dies during it.
    let at_ms = 3_500u64;
    let dead = format!(
        "timeout_ms = 20000\nfaults_until_ms = 1000\n[[dead]]\nmodule = \"M6\"\nat_ms = {at_ms}\n"
    );
    let report = run_text(&sim, &dead, 1);
    let lines = lines(&report);
    let died: Vec<&Line> = lines.iter().filter(|l| l.event == "dead").collect();
    assert_eq!(died.len(), 1, "{}", trace(&report));
    assert_eq!((died[0].module, died[0].ms), ("M6", at_ms as f64));
    let after = || {
        lines
            .iter()
            .filter(|l| l.module == "M6" && l.ms >= at_ms as f64)
    };
    let interrupted: Vec<&Line> = after().filter(|l| l.event == "interrupt").collect();
    assert_eq!(interrupted.len(), 1, "{}", trace(&report));
    assert!(interrupted[0].text.contains("#6 M6.Connector[2].retract()"));
    assert!(!after().any(|l| begins(l.event) || l.event == "resume" || l.event == "failed"));
    assert!(
        !lines.iter().any(|l| l.event == "failed"),
        "no injected failure"
    );
    let m6 = report
        .modules
        .iter()
        .position(|m| m.name == "M6")
        .expect("M6");
    let recorded = report.recorded.as_ref().expect("a traced run records");
    let sent_after = (recorded.packets.iter())
        .filter(|p| p.from[0] == m6 && p.start_us >= at_ms * 1000)
        .count();
    assert_eq!(sent_after, 0);
    assert!(!report.success);
    // The same as powering it off for longer than the run: nothing else differs.
    let off = format!(
        "timeout_ms = 20000\nfaults_until_ms = 4000\n\
         [[power]]\nmodule = \"M6\"\noff_ms = {at_ms}\non_ms = 30000\n"
    );
    let powered_off = run_text(&sim, &off, 1);
    // The line of the death in the one is the power-off's in the other, at the same place.
    let without = |r: &Report, event: &str| -> (Vec<String>, Option<usize>) {
        let all: Vec<&str> = trace(r).lines().collect();
        let of_m6 = |l: &&str| l.get(13..30) == Some(&format!("M6     {event:<10}")[..]);
        let at = all.iter().position(&of_m6);
        let rest = all.iter().filter(|l| !of_m6(l)).map(|l| l.to_string());
        (rest.collect(), at)
    };
    let (dead_rest, dead_at) = without(&report, "dead");
    let (off_rest, off_at) = without(&powered_off, "power-off");
    assert!(
        dead_at.is_some() && dead_at == off_at,
        "{dead_at:?} {off_at:?}"
    );
    assert_eq!(dead_rest, off_rest);
    let (Some(end), Some(off_end)) = (
        &report.final_configuration,
        &powered_off.final_configuration,
    ) else {
        panic!("eight2car ends in a configuration");
    };
    assert!(dynarole_world::compare_with_expected(end, off_end).is_ok());
}

#[test]
fn a_dead_module_is_not_powered_on_again() {
    let sim = eight2car_sim();
    let text = "timeout_ms = 20000\n\
        [[power]]\nmodule = \"M6\"\noff_ms = 3000\non_ms = 6000\n\
        [[dead]]\nmodule = \"M6\"\nat_ms = 4000\n";
    let report = run_text(&sim, text, 1);
    let lines = lines(&report);
    let m6 = |event: &str| {
        let of_m6 = lines
            .iter()
            .filter(|l| l.module == "M6" && l.event == event);
        of_m6.map(|l| l.ms).collect::<Vec<f64>>()
    };
    assert_eq!(m6("dead"), vec![4000.0]);
    assert!(
        m6("power-on").iter().all(|ms| *ms < 3000.0),
        "{}",
        trace(&report)
    );
    assert!(!lines
        .iter()
        .any(|l| l.module == "M6" && l.ms > 3000.0 && begins(l.event)));
}

/// The error of `text` when it is read, or checked against eight2car's configuration.
fn error_of(text: &str) -> dynarole_sim::ScenarioError {
    match Scenario::from_toml_str(text) {
        Err(e) => e,
        Ok(s) => (eight2car_sim().check_scenario(&s, &config(EIGHT))).expect_err(text),
    }
}

#[test]
fn bad_probabilities_are_refused_at_their_field() {
    for (text, field) in [
        (
            "[faults]\noperation_failure = 1.5\n",
            "faults.operation_failure",
        ),
        (
            "[faults]\noperation_failure = nan\n",
            "faults.operation_failure",
        ),
        (
            "[faults.operation_failure]\nturn = -0.1\n",
            "faults.operation_failure.turn",
        ),
        (
            "[faults.operation_failure]\nmove = 2\n",
            "faults.operation_failure.move",
        ),
    ] {
        let e = Scenario::from_toml_str(text).expect_err(text);
        assert_eq!(e.field, field, "{text}");
        assert!(e.message.contains("is not a probability (0 to 1)"), "{e}");
        assert!(e.span.is_some(), "{text}");
    }
}

#[test]
fn an_unknown_kind_is_refused_naming_it_and_the_kinds() {
    let text = "[faults.operation_failure]\nturns = 0.1\n";
    let e = Scenario::from_toml_str(text).expect_err("unknown kind");
    assert!(e.message.contains("unknown field `turns`"), "{e}");
    for kind in ["extend", "retract", "turn", "move", "other"] {
        assert!(e.message.contains(&format!("`{kind}`")), "{e}");
    }
    assert_eq!(e.hint.as_deref(), Some("did you mean `turn`?"));
    let e = Scenario::from_toml_str("[faults]\noperation_failure = \"often\"\n").expect_err("");
    assert!(e.message.contains("a probability, or a table"), "{e}");
}

#[test]
fn unknown_modules_are_refused_at_their_field() {
    let stuck = "[[stuck]]\nmodule = \"M9\"\npart = \"Joint\"\nfrom_ms = 0\n";
    let e = error_of(stuck);
    assert_eq!(e.field, "stuck[0].module");
    assert_eq!(e.message, "no module named `M9` in the configuration");
    let dead = "[[dead]]\nmodule = \"M0\"\nat_ms = 1\n[[dead]]\nmodule = \"M7\"\nat_ms = 1\n";
    let e = error_of(dead);
    assert_eq!(e.field, "dead[1].module");
    assert_eq!(e.message, "no module named `M7` in the configuration");
}

#[test]
fn parts_the_robot_does_not_have_are_refused_at_their_field() {
    let stuck =
        |part: &str| format!("[[stuck]]\nmodule = \"M0\"\npart = \"{part}\"\nfrom_ms = 0\n");
    for (part, says) in [
        (
            "Wheel",
            "robot `atron` has no part `Wheel`; its parts are `Connector`, `Joint`",
        ),
        (
            "Connector[8]",
            "`Connector[8]` is out of range: robot `atron` has `Connector[0]` to `Connector[7]`",
        ),
        ("Joint[0]", "`Joint` takes no index: write `Joint`"),
        (
            "Connector",
            "`Connector` needs an index, as in `Connector[0]`",
        ),
    ] {
        let e = error_of(&stuck(part));
        assert_eq!(e.field, "stuck[0].part", "{part}");
        assert_eq!(e.message, says, "{part}");
    }
    assert_eq!(
        error_of(&stuck("Jiont")).hint.as_deref(),
        Some("did you mean `Joint`?")
    );
    for part in [
        "Connector[",
        "Connector[x]",
        "Connector[-1]",
        "",
        "[0]",
        "Joint]",
        "Con nector",
    ] {
        let e = Scenario::from_toml_str(&stuck(part)).expect_err(part);
        assert_eq!(e.field, "stuck[0].part", "{part}");
        assert!(
            e.message.contains("is not a part: expected a part name"),
            "{e}"
        );
        assert!(e.span.is_some(), "{part}");
    }
}

#[test]
fn a_scenario_without_operation_faults_writes_none() {
    let written = serde_json::to_value(Scenario::default()).expect("serialises");
    for key in ["faults", "stuck", "dead"] {
        assert!(written.get(key).is_none(), "{key}");
    }
    let text = "[faults.operation_failure]\nturn = 0.5\n[[dead]]\nmodule = \"M0\"\nat_ms = 5\n";
    let written = serde_json::to_value(scenario(text)).expect("serialises");
    assert_eq!(written["faults"]["operation_failure"]["turn"], 0.5);
    assert_eq!(written["dead"][0]["at_ms"], 5);
}

/// The viewer's recording ends a failed attempt's bar as `failed`, with no effect on the
/// world, and marks it as a refused or failed operation; a death is a power marker.
#[test]
fn the_recording_shows_failed_attempts_and_deaths() {
    let sim = eight2car_sim();
    let text = "timeout_ms = 12000
[[stuck]]
module = \"M3\"
part = \"Joint\"
from_ms = 0
\
        [[dead]]
module = \"M6\"
at_ms = 3000
";
    let scenario = scenario(text);
    let (start, expect) = (config(EIGHT), config(CAR));
    let run = Run {
        start: &start,
        expect: Some(&expect),
        scenario: &scenario,
        seed: 1,
        trace: true,
    };
    let report = sim.run(&run).expect("runs");
    let recording = sim
        .recording(&run, &report, "faults", None)
        .expect("records");
    let failed: Vec<_> = (recording.motions.iter())
        .filter(|m| m.outcome == "failed")
        .collect();
    assert!(!failed.is_empty(), "{}", trace(&report));
    for m in failed {
        assert_eq!(m.statement, 2);
        assert!(m.end_ms > m.start_ms && m.after.is_empty() && m.latched.is_empty());
    }
    let marked = |kind: &str, label: &str| {
        (recording.markers.iter()).any(|m| m.kind == kind && m.label.starts_with(label))
    };
    assert!(
        marked("refused", "failed on M3: #2 "),
        "{:?}",
        recording.markers
    );
    assert!(marked("power", "dead on M6"), "{:?}", recording.markers);
}
