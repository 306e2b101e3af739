//! `simulate` on long runs: a `timeout_ms` above the limit is refused naming the field (exit
//! 1), a run shows its progress in simulated time on stderr, and its trace is written to
//! its file as it goes, with the header and every line up to the timeout.

mod common;

use common::{repo_root, text};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A scenario file of the test's own.
fn scenario(name: &str, contents: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-simulate-long-runs");
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("written");
    path
}

/// eight2car from the eight with `scenario`, progress lines every `progress` seconds.
fn simulate(scenario: &Path, progress: &str, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dynarole"))
        .args([
            "simulate",
            "robots/atron/examples/eight2car.dr",
            "--sequence",
            "eight2car",
        ])
        .args(["--from", "robots/atron/examples/eight.json", "--scenario"])
        .arg(scenario)
        .args(extra)
        .env("DYNAROLE_PROGRESS_SECONDS", progress)
        .current_dir(repo_root())
        .output()
        .expect("dynarole runs")
}

#[test]
fn a_timeout_above_the_limit_is_refused_naming_the_field() {
    let path = scenario("endless.toml", "timeout_ms = 1000000000000\n");
    let out = simulate(&path, "0", &[]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let stderr = text(&out.stderr);
    assert!(stderr.contains("field `timeout_ms`"), "{stderr}");
    assert!(stderr.contains("more than 1000000000 ms"), "{stderr}");
    assert!(text(&out.stdout).is_empty(), "nothing ran");
}

#[test]
fn a_long_run_shows_its_progress_in_simulated_time_and_streams_its_trace() {
    // Every packet lost: the run never ends before its timeout (2,000 simulated seconds).
    let path = scenario("lost.toml", "timeout_ms = 2000000\n[network]\nloss = 1.0\n");
    let trace = path.with_extension("trace");
    let trace_arg = trace.to_str().expect("path");
    let out = simulate(&path, "0.05", &["--trace", trace_arg]);
    assert_eq!(out.status.code(), Some(3), "{}", text(&out.stderr));
    let stderr = text(&out.stderr);
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("simulate: run 1 of 1: "))
        .collect();
    assert!(!lines.is_empty(), "{stderr}");
    assert!(
        lines
            .iter()
            .all(|l| l.contains("of at most 2000.0 simulated s (") && l.contains("x real time")),
        "{stderr}"
    );
    assert!(stderr.contains("simulate: 1 of 1 runs done"), "{stderr}");
    assert!(
        !text(&out.stdout).contains("simulated s ("),
        "progress stays off stdout"
    );
    let written = std::fs::read_to_string(&trace).expect("trace");
    assert!(
        written.starts_with("#    time ms module event"),
        "{written}"
    );
    let last = written.lines().last().unwrap_or_default();
    assert!(
        last.starts_with(" 2000000.000 -") && last.contains("timeout"),
        "{last}"
    );
}
