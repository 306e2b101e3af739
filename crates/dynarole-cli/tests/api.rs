//! The library API (`dynarole_cli::api`) gives what the command line prints, value for value:
//! simulation reports as `simulate --json`, the reverse as `reverse`, diagnostics located as
//! the rendered ones.

mod common;

use common::{arg, dynarole, repo_root, text};
use dynarole_cli::api::{self, Failure};

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

#[test]
fn simulate_gives_the_reports_simulate_json_prints() {
    let examples = repo_root().join("robots/atron/examples");
    let program = examples.join("eight2car.dr");
    let (from, expect) = (examples.join("eight.json"), examples.join("car.json"));
    let args = [
        arg(&program),
        "--from",
        arg(&from),
        "--expect",
        arg(&expect),
        "--loss",
        "0.3",
        "--seed",
        "7",
        "--repeat",
        "3",
    ];
    let mut reports = Vec::new();
    api::simulate(&strings(&args), &mut |value| {
        reports.push(value);
        Ok(())
    })
    .expect("the simulation runs");
    let mut cli_args = vec!["simulate"];
    cli_args.extend(args);
    cli_args.push("--json");
    let out = dynarole(&cli_args);
    let printed: Vec<serde_json::Value> = text(&out.stdout)
        .lines()
        .map(|line| serde_json::from_str(line).expect("one JSON report per line"))
        .collect();
    assert_eq!(reports.len(), 3);
    assert_eq!(reports, printed);
}

#[test]
fn an_interrupt_between_runs_ends_the_simulation() {
    let examples = repo_root().join("robots/atron/examples");
    let program = examples.join("eight2car.dr");
    let from = examples.join("eight.json");
    let args = [arg(&program), "--from", arg(&from), "--repeat", "5"];
    let mut seen = 0;
    let result = api::simulate(&strings(&args), &mut |_| {
        seen += 1;
        Err(Failure::Usage("interrupted".into()))
    });
    assert!(matches!(result, Err(Failure::Usage(m)) if m == "interrupted"));
    assert_eq!(seen, 1);
}

#[test]
fn reverse_gives_the_text_reverse_prints() {
    let program = repo_root().join("robots/atron/examples/eight2car.dr");
    let text_api = api::reverse(&program, "eight2car", None, &[]).expect("it reverses");
    let out = dynarole(&["reverse", arg(&program), "eight2car"]);
    assert_eq!(text_api, text(&out.stdout));
}

#[test]
fn a_refused_file_is_a_failure_holding_its_located_diagnostics() {
    let dir = tempfile::tempdir().expect("a scratch folder");
    let path = dir.path().join("bad.dr");
    std::fs::write(
        &path,
        "robot atron;\n\nsequence s {\n    M0.Joint.spin();\n}\n",
    )
    .expect("written");
    match api::check(&strings(&[arg(&path)])) {
        Err(Failure::Checked {
            path: shown,
            source,
            diagnostics,
            ..
        }) => {
            let located = api::locate(&shown, &source, &diagnostics);
            let first = &located[0];
            assert_eq!(first.line, 4, "{first:?}");
            assert_eq!(first.severity, "error");
            let out = dynarole(&["check", arg(&path)]);
            let rendered = text(&out.stderr);
            assert!(rendered.contains(first.code), "{rendered}");
            let place = format!("bad.dr:{}:{}", first.line, first.column);
            assert!(rendered.contains(&place), "{place} in {rendered}");
        }
        other => panic!("expected the file's diagnostics, got {other:?}"),
    }
}

#[test]
fn options_are_checked_by_the_command_lines_definitions() {
    let result = api::simulate(&strings(&["x.dr", "--repeat", "0"]), &mut |_| Ok(()));
    match result {
        Err(Failure::Usage(message)) => assert!(message.contains("at least 1"), "{message}"),
        other => panic!("expected a usage error, got {other:?}"),
    }
}

#[test]
fn replay_gives_the_configuration_replay_writes() {
    let examples = repo_root().join("robots/atron/examples");
    let program = examples.join("eight2car.dr");
    let (from, expect) = (examples.join("eight.json"), examples.join("car.json"));
    let args = [
        arg(&program),
        "--sequence",
        "eight2car",
        "--from",
        arg(&from),
        "--expect",
        arg(&expect),
    ];
    let value = api::replay(&strings(&args)).expect("it replays");
    let dir = tempfile::tempdir().expect("a scratch folder");
    let out = dir.path().join("final.json");
    let mut cli_args = vec!["replay"];
    cli_args.extend(args);
    cli_args.extend(["--out", arg(&out)]);
    assert!(dynarole(&cli_args).status.success());
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("written")).expect("JSON");
    assert_eq!(value["final_configuration"], written);
    assert_eq!(value["matches_expected"], true);
    assert_eq!(value["rejected"], 0);
    assert_eq!(value["steps"].as_array().map(Vec::len), Some(25));
}

#[test]
fn parallelise_gives_the_file_parallelise_prints() {
    let examples = repo_root().join("robots/atron/examples");
    let program = examples.join("eight2car.dr");
    let from = examples.join("eight.json");
    let args = [
        arg(&program),
        "--sequence",
        "eight2car",
        "--from",
        arg(&from),
    ];
    let value = api::parallelise(&strings(&args)).expect("it parallelises");
    let mut cli_args = vec!["parallelise"];
    cli_args.extend(args);
    let out = dynarole(&cli_args);
    assert_eq!(value["text"], text(&out.stdout));
    let groups = format!("{} groups", value["groups"]);
    assert!(text(&out.stderr).contains(&groups), "{groups}");
}

/// A caller's stop request, asked before every run.
struct StopAfter(std::sync::atomic::AtomicU64);

impl api::Progress for StopAfter {
    fn advanced(&self) {
        self.0.fetch_sub(1, std::sync::atomic::Ordering::Relaxed);
    }

    fn stop_requested(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed) == 0
    }
}

#[test]
fn a_campaign_stopped_by_its_caller_keeps_the_runs_recorded() {
    let campaign = repo_root().join("examples/campaigns/smoke.toml");
    let dir = tempfile::tempdir().expect("a scratch folder");
    let args = [
        arg(&campaign),
        "-o",
        arg(dir.path()),
        "-j",
        "1",
        "--no-plots",
    ];
    let mut stop = StopAfter(std::sync::atomic::AtomicU64::new(3));
    match api::campaign(&strings(&args), &mut stop) {
        Err(Failure::Input(message)) => assert!(message.contains("interrupted"), "{message}"),
        other => panic!("expected the interrupt, got {other:?}"),
    }
    let rows = std::fs::read_to_string(dir.path().join("runs.csv")).expect("runs.csv");
    // The header and the three runs done before the stop.
    assert_eq!(rows.lines().count(), 4, "{rows}");
    let done = api::campaign(&strings(&args), &mut dynarole_campaign::Quiet).expect("it resumes");
    assert_eq!(done["already"], 3);
}
