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
