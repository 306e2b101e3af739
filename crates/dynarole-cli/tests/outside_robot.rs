//! A robot from outside the tree (issue 27): the `hinged_cubes` example is a program that
//! embeds dynarole with a robot kind of its own (`examples/hinged_cubes/robot/`), and every
//! command runs on it: check, reverse, fmt, replay, simulate, compile, verify, parallelise,
//! show, view and campaign, with its data files read and written, and bad input refused.

mod common;

use common::text;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The example's folder: its `.dr`, data files, scenario and campaign.
fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hinged_cubes")
}

/// The example program, which Cargo builds beside the test executables for `cargo test`.
fn program() -> PathBuf {
    let test = std::env::current_exe().expect("the test executable's path");
    let deps = test.parent().expect("the test executable's folder");
    let name = format!("hinged_cubes{}", std::env::consts::EXE_SUFFIX);
    let program = deps.join("../examples").join(name);
    assert!(
        program.is_file(),
        "{} is missing: build it with `cargo build --example hinged_cubes` (cargo test builds \
         it unless examples are left out)",
        program.display()
    );
    program
}

/// The example program run with `args` in its folder.
fn cubes(args: &[&str]) -> Output {
    Command::new(program())
        .args(args)
        .current_dir(folder())
        .output()
        .expect("the example program runs")
}

/// Exit code, and stdout and stderr together.
fn run(args: &[&str]) -> (Option<i32>, String) {
    let out = cubes(args);
    let all = format!("{}{}", text(&out.stdout), text(&out.stderr));
    (out.status.code(), all)
}

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("outside-robot")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// `contents` written to `name` in `dir`, as an argument.
fn write(dir: &Path, name: &str, contents: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("scratch file");
    arg(&path)
}

fn arg(path: &Path) -> String {
    path.to_str().expect("a UTF-8 path").to_string()
}

fn line4() -> String {
    std::fs::read_to_string(folder().join("line4.json")).expect("line4.json")
}

#[test]
fn check_takes_the_program_alone_and_on_a_configuration() {
    let (code, out) = run(&["check", "ring.dr"]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("ok: ring.dr"), "{out}");
    let (code, out) = run(&["check", "ring.dr", "--from", "line4.json"]);
    assert_eq!(code, Some(0), "{out}");
    // On the ring every hinge is at 90 already: the first bend (from 0) is refused.
    let (code, out) = run(&[
        "check",
        "ring.dr",
        "--sequence",
        "ring",
        "--from",
        "ring4.json",
    ]);
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("M0's joint is at 90, not at 0"), "{out}");
}

#[test]
fn reverse_prints_the_unfolding_which_checks() {
    let out = cubes(&["reverse", "ring.dr", "ring"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let reversed = text(&out.stdout);
    assert!(reversed.contains("robot hinged;"), "{reversed}");
    let unlatch = reversed.find("M3.Connector[$FRONT].unlatch();");
    let unbend = reversed.find("M0.Hinge.bend(90, 0, false, 100);");
    assert!(
        unlatch.is_some() && unbend.is_some() && unlatch < unbend,
        "the latch undone first, M0's hinge last:\n{reversed}"
    );
    let dir = scratch("reverse");
    let file = write(&dir, "open.dr", &reversed);
    let (code, out) = run(&["check", &file]);
    assert_eq!(code, Some(0), "{out}");
}

#[test]
fn fmt_check_accepts_the_example_and_refuses_a_badly_laid_out_copy() {
    let (code, out) = run(&["fmt", "--check", "ring.dr"]);
    assert_eq!(code, Some(0), "{out}");
    let source = std::fs::read_to_string(folder().join("ring.dr")).expect("ring.dr");
    let dir = scratch("fmt");
    let messy = write(
        &dir,
        "messy.dr",
        &source.replace("    M1.Hinge", "M1.Hinge"),
    );
    let (code, out) = run(&["fmt", "--check", &messy]);
    assert_ne!(code, Some(0), "{out}");
}

#[test]
fn replay_reaches_the_ring_and_its_reverse_the_line() {
    let ring = [
        "replay",
        "ring.dr",
        "--sequence",
        "ring",
        "--from",
        "line4.json",
    ];
    let (code, out) = run(&[&ring[..], &["--expect", "ring4.json"]].concat());
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("5 statements, 0 rejected"), "{out}");
    assert!(out.contains("matches ring4.json"), "{out}");
    let open = [
        "replay",
        "ring.dr",
        "--sequence",
        "open",
        "--from",
        "ring4.json",
    ];
    let (code, out) = run(&[&open[..], &["--expect", "line4.json"]].concat());
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("matches line4.json"), "{out}");
    let (code, out) = run(&[&ring[..], &["--expect", "line4.json"]].concat());
    assert_eq!(code, Some(1), "the ring is not the line: {out}");
    assert!(out.contains("does NOT match line4.json"), "{out}");
    assert!(out.contains("connection M3.C0-M0.C1"), "{out}");
}

/// The ring turned a quarter turn and moved: the same up to a rigid motion.
const RING_MOVED: &str = r#"{
  "name": "ring4 moved",
  "robot": "HINGED",
  "modules": [
    {"name": "M0", "id": 0, "cell": [5, 5], "heading": [0, 1], "hinge": 90},
    {"name": "M1", "id": 1, "cell": [4, 5], "heading": [-1, 0], "hinge": 90},
    {"name": "M2", "id": 2, "cell": [4, 4], "heading": [0, -1], "hinge": 90},
    {"name": "M3", "id": 3, "cell": [5, 4], "heading": [1, 0], "hinge": 90}
  ],
  "connections": [["M0", 0, "M1", 1], ["M1", 0, "M2", 1], ["M2", 0, "M3", 1], ["M3", 0, "M0", 1]]
}"#;

/// The ring mirrored (the ring folded the other way): the ring turned over in space, but
/// with its hinges at -90, so no rigid motion makes it the ring.
const RING_MIRRORED: &str = r#"{
  "name": "ring4 mirrored",
  "robot": "HINGED",
  "modules": [
    {"name": "M0", "id": 0, "cell": [0, 0], "heading": [1, 0], "hinge": -90},
    {"name": "M1", "id": 1, "cell": [0, -1], "heading": [0, -1], "hinge": -90},
    {"name": "M2", "id": 2, "cell": [-1, -1], "heading": [-1, 0], "hinge": -90},
    {"name": "M3", "id": 3, "cell": [-1, 0], "heading": [0, 1], "hinge": -90}
  ],
  "connections": [["M0", 0, "M1", 1], ["M1", 0, "M2", 1], ["M2", 0, "M3", 1], ["M3", 0, "M0", 1]]
}"#;

#[test]
fn expect_compares_up_to_a_rigid_motion_of_the_plane_in_space() {
    let dir = scratch("rigid");
    let moved = write(&dir, "moved.json", RING_MOVED);
    let mirrored = write(&dir, "mirrored.json", RING_MIRRORED);
    let ring = [
        "replay",
        "ring.dr",
        "--sequence",
        "ring",
        "--from",
        "line4.json",
    ];
    let (code, out) = run(&[&ring[..], &["--expect", &moved]].concat());
    assert_eq!(code, Some(0), "{out}");
    let (code, out) = run(&[&ring[..], &["--expect", &mirrored]].concat());
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("joint of M0: expected [-90], reached [90]"),
        "{out}"
    );
}

#[test]
fn replay_writes_a_data_file_that_reads_back() {
    let dir = scratch("round-trip");
    let written = dir.join("ring-reached.json");
    let (code, out) = run(&[
        "replay",
        "ring.dr",
        "--sequence",
        "ring",
        "--from",
        "line4.json",
        "--out",
        &arg(&written),
    ]);
    assert_eq!(code, Some(0), "{out}");
    let json = std::fs::read_to_string(&written).expect("the final configuration");
    assert!(json.contains(r#""robot": "HINGED""#), "{json}");
    assert!(
        json.contains(
            r#"{"name": "M2", "id": 2, "cell": [-1, 1], "heading": [-1, 0], "hinge": 90}"#
        ),
        "{json}"
    );
    let (code, out) = run(&[
        "replay",
        "ring.dr",
        "--sequence",
        "open",
        "--from",
        &arg(&written),
        "--expect",
        "line4.json",
    ]);
    assert_eq!(code, Some(0), "{out}");
    // Unfolded again and written: the cubes and latches as line4.json has them, line by line.
    let unfolded = dir.join("line-reached.json");
    let (code, out) = run(&[
        "replay",
        "ring.dr",
        "--sequence",
        "open",
        "--from",
        &arg(&written),
        "--out",
        &arg(&unfolded),
    ]);
    assert_eq!(code, Some(0), "{out}");
    let body = |json: &str| {
        let start = json.find("\"modules\"").expect("modules");
        let end = json.find("\"note\"").expect("note");
        json[start..end].to_string()
    };
    let again = std::fs::read_to_string(&unfolded).expect("the unfolded configuration");
    assert_eq!(body(&again), body(&line4()));
}

#[test]
fn simulate_folds_the_ring_with_and_without_loss() {
    let ring = [
        "simulate",
        "ring.dr",
        "--sequence",
        "ring",
        "--from",
        "line4.json",
        "--seed",
        "1",
    ];
    let (code, out) = run(&[&ring[..], &["--expect", "ring4.json"]].concat());
    assert_eq!(code, Some(0), "{out}");
    assert!(
        out.contains("SUCCESS") && out.contains("5 of 5 statements done"),
        "{out}"
    );
    let lossy = [
        &ring[..],
        &["--expect", "ring4.json", "--scenario", "lossy.toml"],
    ]
    .concat();
    let (code, out) = run(&lossy);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("SUCCESS"), "{out}");
    assert!(
        !out.contains("(lost 0,"),
        "the scenario loses packets: {out}"
    );
    let (code, out) = run(&[&ring[..], &["--expect", "line4.json"]].concat());
    assert_eq!(code, Some(3), "the ring is not the line: {out}");
    assert!(out.contains("not the expected one"), "{out}");
}

#[test]
fn compile_writes_c_that_builds() {
    let dir = scratch("compile").join("ring");
    let (code, out) = run(&["compile", "ring.dr", "--sequence", "ring", "-o", &arg(&dir)]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("5 statements, 4 modules"), "{out}");
    for file in ["Makefile", "dr_program.c", "dr_program.h", "dr_hal.h"] {
        assert!(dir.join(file).is_file(), "{file} missing");
    }
    let make = Command::new("make")
        .arg("-s")
        .current_dir(&dir)
        .output()
        .expect("make runs");
    assert!(make.status.success(), "{}", text(&make.stderr));
}

#[test]
fn verify_proves_the_ring_with_spin() {
    let (code, out) = run(&["verify", "ring.dr", "--from", "line4.json"]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("4 modules"), "{out}");
    assert!(out.contains("result: verified"), "{out}");
}

#[test]
fn parallelise_runs_the_first_and_last_bend_together() {
    let args = [
        "parallelise",
        "ring.dr",
        "--sequence",
        "ring",
        "--from",
        "line4.json",
    ];
    let (code, out) = run(&args);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("sequence ring_parallel"), "{out}");
    assert!(out.contains("robot hinged;"), "{out}");
    assert!(out.contains("checked on the model"), "{out}");
    assert!(
        out.contains("M0.Hinge.bend(0, 90, true, 100) &\n    M3.Hinge.bend(0, 90, true, 100);"),
        "M3 does not move when M0 bends, nor M0 when M3 does: {out}"
    );
}

#[test]
fn show_draws_every_cube() {
    let dir = scratch("show");
    let svg = dir.join("x.svg");
    let (code, out) = run(&["show", "ring4.json", "-o", &arg(&svg)]);
    assert_eq!(code, Some(0), "{out}");
    let picture = std::fs::read_to_string(&svg).expect("the SVG");
    assert!(picture.contains("<svg"), "{picture}");
    for cube in ["M0", "M1", "M2", "M3"] {
        assert!(picture.contains(cube), "{cube} is not named in the picture");
    }
}

#[test]
fn view_writes_the_page_of_a_recorded_run() {
    let dir = scratch("view");
    let recording = dir.join("run.json");
    let (code, out) = run(&[
        "simulate",
        "ring.dr",
        "--sequence",
        "ring",
        "--from",
        "line4.json",
        "--seed",
        "1",
        "--record",
        &arg(&recording),
    ]);
    assert_eq!(code, Some(0), "{out}");
    let page = dir.join("run.html");
    let (code, out) = run(&["view", &arg(&recording), "-o", &arg(&page)]);
    assert_eq!(code, Some(0), "{out}");
    let html = std::fs::read_to_string(&page).expect("the page");
    assert!(
        html.contains("<html") || html.contains("<!DOCTYPE"),
        "not a page"
    );
    assert!(
        html.contains("cube body"),
        "the robot's own drawing is in the page"
    );
    let (code, out) = run(&["view", &arg(&recording), "--poses-at", "0"]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains(r#""name":"M3""#), "{out}");
}

#[test]
fn campaign_sweeps_loss_over_two_seeds() {
    let dir = scratch("campaign");
    let (code, out) = run(&["campaign", "campaign.toml", "-o", &arg(&dir)]);
    assert_eq!(code, Some(0), "{out}");
    let runs = std::fs::read_to_string(dir.join("runs.csv")).expect("runs.csv");
    assert_eq!(
        runs.lines().count(),
        5,
        "a header and 2 losses x 2 seeds:\n{runs}"
    );
    let summary = std::fs::read_to_string(dir.join("summary.csv")).expect("summary.csv");
    let rows: Vec<&str> = summary.lines().skip(1).collect();
    assert_eq!(rows.len(), 2, "{summary}");
    assert!(
        rows.iter()
            .all(|r| r.starts_with("loss,") && r.contains(",lattice,2,2,1.0,")),
        "every run folds the ring:\n{summary}"
    );
    assert!(dir.join("success-loss.svg").is_file());
}

/// `line4.json` with `from` replaced by `to` (which must be there).
fn broken(from: &str, to: &str) -> String {
    let text = line4();
    assert!(text.contains(from), "{from} is in line4.json");
    text.replacen(from, to, 1)
}

#[test]
fn a_malformed_cubes_file_names_the_field() {
    let first = r#"{"name": "M0", "id": 0, "cell": [0, 0], "heading": [1, 0], "hinge": 0}"#;
    let cases = [
        (
            broken(r#""hinge": 0}"#, r#""hinge": 45}"#),
            "modules[0].hinge",
        ),
        (
            broken(r#""heading": [1, 0]"#, r#""heading": [1, 1]"#),
            "modules[0].heading",
        ),
        (
            broken(r#""cell": [1, 0]"#, r#""cell": [0, 0]"#),
            "modules[1].cell",
        ),
        (
            broken(r#""cell": [2, 0]"#, r#""cell": [2]"#),
            "modules[2].cell",
        ),
        (
            broken(r#""name": "M3""#, r#""name": "M2""#),
            "modules[3].name",
        ),
        (broken(r#""id": 3"#, r#""id": 70000"#), "modules[3].id"),
        (
            broken(
                first,
                r#"{"name": "M0", "cell": [0, 0], "heading": [1, 0]}"#,
            ),
            "modules[0].hinge",
        ),
        (
            broken(r#""hinge": 0}"#, r#""hinge": 0, "colour": "red"}"#),
            "modules[0].colour",
        ),
        (
            broken(r#"["M0", 0, "M1", 1]"#, r#"["M0", 0, "M9", 1]"#),
            "connections[0][2]",
        ),
        (
            broken(r#"["M0", 0, "M1", 1]"#, r#"["M0", 0, "M2", 1]"#),
            "connections[0]",
        ),
        (
            broken(r#"["M0", 0, "M1", 1]"#, r#"["M0", 1, "M1", 1]"#),
            "connections[0]",
        ),
        (
            broken(r#"["M0", 0, "M1", 1]"#, r#"["M0", 2, "M1", 1]"#),
            "connections[0][1]",
        ),
        (
            broken(r#""robot": "HINGED""#, r#""robot": "CUBE""#),
            "robot",
        ),
    ];
    let dir = scratch("malformed");
    for (k, (json, path)) in cases.iter().enumerate() {
        let file = write(&dir, &format!("bad{k}.json"), json);
        for args in [
            vec!["check", "ring.dr", "--from", &file],
            vec!["show", &file, "-o", "unused.svg"],
        ] {
            let (code, out) = run(&args);
            assert_eq!(code, Some(1), "{args:?}: {out}");
            assert!(
                out.contains(&format!("{file}: {path}: ")),
                "{path} named: {out}"
            );
        }
    }
    assert!(!folder().join("unused.svg").exists(), "nothing is drawn");
}

/// Four ATRON modules in a line (enough for the ring's M0..M3).
const ATRON_LINE4: &str = r#"{
  "name": "atron line4",
  "robot": "ATRON",
  "modules": [
    {"name": "M0", "id": 0, "position": [0, 0, 0], "orientation": "NS", "joint": 0},
    {"name": "M1", "id": 1, "position": [-1, 0, -1], "orientation": "EW", "joint": 0},
    {"name": "M2", "id": 2, "position": [-2, 0, 0], "orientation": "NS", "joint": 0},
    {"name": "M3", "id": 3, "position": [-3, 0, -1], "orientation": "EW", "joint": 0}
  ],
  "connections": [["M0", 0, "M1", 5], ["M2", 2, "M1", 1], ["M2", 0, "M3", 5]]
}"#;

/// Three ATRON modules: the ring's M3 is missing as well.
const ATRON_LINE3: &str = r#"{
  "name": "atron line3",
  "robot": "ATRON",
  "modules": [
    {"name": "M0", "id": 0, "position": [0, 0, 0], "orientation": "NS", "joint": 0},
    {"name": "M1", "id": 1, "position": [-1, 0, -1], "orientation": "EW", "joint": 0},
    {"name": "M2", "id": 2, "position": [-2, 0, 0], "orientation": "NS", "joint": 0}
  ],
  "connections": [["M0", 0, "M1", 5], ["M2", 2, "M1", 1]]
}"#;

#[test]
fn a_cubes_sequence_on_an_atron_configuration_is_refused() {
    let dir = scratch("other-robot");
    for (name, json) in [("line4.json", ATRON_LINE4), ("line3.json", ATRON_LINE3)] {
        let atron = write(&dir, name, json);
        let (code, out) = run(&["show", &atron, "-o", &arg(&dir.join("atron.svg"))]);
        assert_eq!(code, Some(0), "the ATRON file is valid: {out}");
        let on = ["--sequence", "ring", "--from", &atron];
        for command in ["check", "replay", "simulate", "parallelise", "verify"] {
            let (code, out) = run(&[&[command, "ring.dr"][..], &on].concat());
            assert_eq!(code, Some(1), "{command} on {name}: {out}");
            assert!(
                out.contains(
                    "the sequence is for robot `hinged` but the configuration is an ATRON robot"
                ),
                "{command} on {name}: {out}"
            );
        }
    }
}
