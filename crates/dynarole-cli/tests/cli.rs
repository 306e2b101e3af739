//! The `dynarole` binary end to end: exit codes, output, and files it writes.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn dynarole(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dynarole"))
        .args(args)
        .current_dir(repo_root())
        .output()
        .expect("the dynarole binary runs")
}

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn scratch(name: &str, contents: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-tests");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("scratch file");
    path
}

#[test]
fn check_accepts_the_examples() {
    let out = dynarole(&["check", "examples/atron/eight2car.dr"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("ok: examples/atron/eight2car.dr"));
}

#[test]
fn check_reports_file_line_and_column_and_exits_1() {
    let path = scratch(
        "bad.dr",
        "robot atron;\nsequence s {\n    MO.Connector[$CONNECTOR_0].retract();\n}\n",
    );
    let out = dynarole(&["check", path.to_str().expect("utf-8 path")]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = text(&out.stderr);
    assert!(stderr.contains("bad.dr:3:5"), "{stderr}");
    assert!(stderr.contains("unknown label `MO`"), "{stderr}");
    assert!(stderr.contains("did you mean `M0`?"), "{stderr}");
}

#[test]
fn usage_errors_exit_2() {
    assert_eq!(dynarole(&["check"]).status.code(), Some(2));
    assert_eq!(dynarole(&["frobnicate"]).status.code(), Some(2));
    assert_eq!(
        dynarole(&["check", "--protocol", "token", "x.dr"])
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn missing_file_is_bad_input() {
    let out = dynarole(&["check", "no/such/file.dr"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("cannot read no/such/file.dr"));
}

#[test]
fn reverse_prints_a_file_that_checks_and_reverses_back() {
    let out = dynarole(&["reverse", "examples/atron/eight2car.dr", "eight2car"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let reversed = text(&out.stdout);
    assert!(reversed.starts_with(
        "robot atron;\n\nsequence car2eight {\n    M1.Joint.rotateFromToBy(216, 108, false, 150);"
    ));
    let path = scratch("car2eight.dr", &reversed);
    let path = path.to_str().expect("utf-8 path");
    assert_eq!(dynarole(&["check", path]).status.code(), Some(0));
    let back = dynarole(&["reverse", path, "car2eight", "--name", "eight2car"]);
    let original = dynarole(&["reverse", "examples/atron/eight2car.dr", "car2eight"]);
    assert_eq!(text(&back.stdout), text(&original.stdout));
}

#[test]
fn reverse_of_an_unknown_sequence_is_bad_input() {
    let out = dynarole(&["reverse", "examples/atron/eight2car.dr", "nope"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("no sequence named `nope`"));
}

#[test]
fn fmt_check_then_fmt_then_check_again() {
    let path = scratch(
        "messy.dr",
        "robot atron;sequence s{M0.Connector[0].retract()&M3.Connector[4].retract();}\n",
    );
    let path = path.to_str().expect("utf-8 path");
    let before = dynarole(&["fmt", "--check", path]);
    assert_eq!(before.status.code(), Some(1));
    assert!(text(&before.stdout).contains("not formatted"));
    assert_eq!(dynarole(&["fmt", path]).status.code(), Some(0));
    assert_eq!(dynarole(&["fmt", "--check", path]).status.code(), Some(0));
    let formatted = std::fs::read_to_string(path).expect("formatted file");
    assert_eq!(formatted, "robot atron;\n\nsequence s {\n    M0.Connector[0].retract() &\n    M3.Connector[4].retract();\n}\n");
}

#[test]
fn examples_are_formatted() {
    let out = dynarole(&["fmt", "--check", "examples/atron/eight2car.dr"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stdout));
}

#[test]
fn a_broken_plugin_names_the_field() {
    let plugin = scratch(
        "broken.robot.toml",
        "name = \"broken\"\n[[part]]\nname = \"Arm\"\ncount = 300\n",
    );
    let source = scratch(
        "uses_broken.dr",
        "robot broken;\nsequence s { M0.Arm[0].wave(); }\n",
    );
    let out = dynarole(&[
        "check",
        "--plugin",
        plugin.to_str().expect("path"),
        source.to_str().expect("path"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("broken.robot.toml: field `part[0].count`: expected 1 to 255, found 300"),
        "{stderr}"
    );
}

#[test]
fn paper_protocol_reports_nested_blocks() {
    let path = scratch("nested.dr", "robot atron;\nsequence s {\n    { M0.Connector[0].retract(); M0.Connector[0].extend(); } & M3.Connector[4].retract();\n}\n");
    let path = path.to_str().expect("utf-8 path");
    assert_eq!(dynarole(&["check", path]).status.code(), Some(0));
    let paper = dynarole(&["check", "--protocol", "paper", path]);
    assert_eq!(paper.status.code(), Some(1));
    assert!(text(&paper.stderr).contains("not supported by the paper protocol"));
}
