//! The failure policy end to end: eight2car with injected operation failures, simulated with
//! `--on-failure stop` and `retry`, read back from `--json` (outcome, stops, counters), and the
//! flags' usage errors.

mod common;

use common::{dynarole, ok, text};
use serde_json::Value;
use std::path::{Path, PathBuf};

const PROGRAM: &str = "robots/atron/examples/eight2car.dr";
const FROM: &str = "robots/atron/examples/eight.json";
const EXPECT: &str = "robots/atron/examples/car.json";

/// A scenario in a fresh directory: every operation fails with probability `p`.
fn scenario(name: &str, p: f64) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dynarole-failure-policy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let path = dir.join(format!("{name}.toml"));
    let text = format!("[network]\nloss = 0.3\n[faults]\noperation_failure = {p}\n");
    std::fs::write(&path, text).expect("the scenario is written");
    path
}

/// `simulate --json` of eight2car with `scenario`, `seed` and `flags`, expecting `code`.
fn report(scenario: &Path, seed: &str, flags: &[&str], code: i32) -> Value {
    let scenario = scenario.to_str().expect("a UTF-8 path");
    let mut args = vec![
        "simulate",
        PROGRAM,
        "--from",
        FROM,
        "--expect",
        EXPECT,
        "--scenario",
        scenario,
        "--seed",
        seed,
        "--json",
    ];
    args.extend_from_slice(flags);
    serde_json::from_str(&ok(&args, code)).expect("the report is JSON")
}

#[test]
fn an_operation_that_always_fails_stops_its_module_and_the_run_says_which() {
    let always = scenario("always", 1.0);
    let stopped = report(&always, "1", &["--on-failure", "stop"], 3);
    assert_eq!(stopped["outcome"], "stopped");
    assert_eq!(stopped["final_matches_start"], true, "nothing took effect");
    let stops = stopped["stopped"].as_array().expect("the stops");
    assert!(!stops.is_empty());
    for stop in stops {
        assert!(
            stop["text"].as_str().is_some_and(|t| !t.is_empty()),
            "{stop}"
        );
    }
    // Stop gives up at the first failure: each stopped module tried once.
    let failed = stopped["counters"]["ops_failed"]
        .as_u64()
        .expect("failures counted");
    assert_eq!(failed, stops.len() as u64);
    // Retry 2: each stopped module tried three times.
    let retried = report(&always, "1", &["--retries", "2"], 3);
    assert_eq!(retried["outcome"], "stopped");
    let stops = retried["stopped"].as_array().expect("the stops").len() as u64;
    assert_eq!(retried["counters"]["ops_failed"].as_u64(), Some(3 * stops));
}

#[test]
fn retries_reach_the_goal_where_stopping_does_not() {
    let sometimes = scenario("sometimes", 0.05);
    // Seeds where some operation fails: stop leaves the robot half-way, retry finishes.
    let mut compared = 0;
    for seed in 1..=12 {
        let seed = seed.to_string();
        let stop = dynarole(&[
            "simulate",
            PROGRAM,
            "--from",
            FROM,
            "--expect",
            EXPECT,
            "--scenario",
            sometimes.to_str().expect("a UTF-8 path"),
            "--seed",
            &seed,
            "--json",
            "--on-failure",
            "stop",
        ]);
        let stop: Value = serde_json::from_str(&text(&stop.stdout)).expect("JSON");
        if stop["outcome"] != "stopped" {
            continue;
        }
        compared += 1;
        assert_eq!(stop["final_matches_start"], false, "it stopped half-way");
        let retry = report(&sometimes, &seed, &[], 0);
        assert_eq!(retry["outcome"], "success");
        assert!(retry["counters"]["ops_failed"].as_u64() > Some(0));
    }
    assert!(compared >= 3, "only {compared} of 12 seeds had a failure");
}

/// `compile` of eight2car with `flags` is a usage error (exit 2) saying `message`.
fn refused(flags: &[&str], message: &str) {
    let mut args = vec!["compile", PROGRAM, "-o", "target/failure-policy-refused"];
    args.extend_from_slice(flags);
    let out = dynarole(&args);
    assert_eq!(out.status.code(), Some(2), "{flags:?}");
    assert!(
        text(&out.stderr).contains(message),
        "{flags:?}: {}",
        text(&out.stderr)
    );
}

#[test]
fn the_policy_flags_are_refused_where_they_mean_nothing() {
    refused(
        &["--protocol", "paper", "--on-failure", "stop"],
        "--on-failure stop applies to the lattice protocol only",
    );
    refused(
        &["--on-failure", "stop", "--retries", "2"],
        "--retries 2 applies to --on-failure retry",
    );
    refused(&["--retries", "101"], "101 is not in 0..=100");
}

#[test]
fn the_generated_configuration_names_a_policy_other_than_the_default() {
    let dir = std::env::temp_dir().join(format!("dynarole-policy-c-{}", std::process::id()));
    let out = dir.to_str().expect("a UTF-8 path");
    ok(&["compile", PROGRAM, "--on-failure", "stop", "-o", out], 0);
    let conf = std::fs::read_to_string(dir.join("dr_program_conf.h")).expect("the header");
    assert!(conf.contains("#define DR_CONF_ON_FAILURE DR_ON_FAILURE_STOP /* stop */"));
    ok(&["compile", PROGRAM, "--retries", "5", "-o", out], 0);
    let conf = std::fs::read_to_string(dir.join("dr_program_conf.h")).expect("the header");
    assert!(conf.contains("#define DR_CONF_RETRIES 5"));
    ok(&["compile", PROGRAM, "-o", out], 0);
    let conf = std::fs::read_to_string(dir.join("dr_program_conf.h")).expect("the header");
    assert!(!conf.contains("DR_CONF_ON_FAILURE") && !conf.contains("DR_CONF_RETRIES"));
}
