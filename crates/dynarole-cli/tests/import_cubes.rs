//! `dynarole import` and `export scen` end to end on the cube scenarios of
//! `robots/cubes/examples/`: each imports, replays to where its moves end, reverses back to
//! its start, simulates to its end at 30 % loss and under every fault kind, and comes back
//! from `export scen` as the same sequence; `parallelise` of a scenario written one move at a
//! time gives back its sets.

mod common;

use common::{arg, dynarole, ok, repo_root, simulate, text};
use std::path::{Path, PathBuf};

/// The example scenarios, each with its sequence's name.
const SCENARIOS: [(&str, &str); 6] = [
    ("slide", "slide"),
    ("corner-slide", "corner_slide"),
    ("pivot", "pivot"),
    ("pivot180", "pivot180"),
    ("four-slides", "four_slides"),
    ("monkey", "monkey"),
];

/// Imports `plan` into `dir`: what it printed, and the program and the two configurations.
fn import(plan: &Path, dir: &Path) -> (String, [PathBuf; 3]) {
    let printed = ok(&["import", arg(plan), "-o", arg(dir)], 0);
    let stem = plan.file_stem().and_then(|s| s.to_str()).expect("a stem");
    let files = ["dr", "from.json", "expect.json"].map(|ext| dir.join(format!("{stem}.{ext}")));
    (printed, files)
}

fn example(stem: &str) -> PathBuf {
    repo_root().join(format!("robots/cubes/examples/{stem}.scen"))
}

/// The program's statements, without its comments and the sequence's name.
fn statements(program: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(program).expect("the program reads");
    (text.lines())
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("//") && !l.starts_with("sequence"))
        .map(String::from)
        .collect()
}

#[test]
fn every_example_scenario_imports_replays_reverses_and_simulates_at_30_percent_loss() {
    for (stem, sequence) in SCENARIOS {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let (printed, [program, from, expect]) = import(&example(stem), dir.path());
        assert!(
            printed.contains(&format!("sequence `{sequence}`")),
            "{printed}"
        );
        assert!(
            printed.contains("replays to the plan's last configuration"),
            "{printed}"
        );
        let reverse = ok(&["reverse", arg(&program), sequence], 0);
        let reversed = dir.path().join("reverse.dr");
        std::fs::write(&reversed, reverse).expect("written");
        let back = ok(
            &[
                "replay",
                arg(&reversed),
                "--from",
                arg(&expect),
                "--expect",
                arg(&from),
            ],
            0,
        );
        assert!(
            back.contains("0 rejected") && back.contains("(in place)"),
            "{back}"
        );
        for seed in ["1", "2"] {
            let simulated = simulate(&program, &from, &expect, &["--loss", "0.3", "--seed", seed]);
            assert!(simulated.starts_with("SUCCESS"), "{stem}: {simulated}");
        }
    }
}

/// Every fault kind (`examples/faults.toml`: loss, dead links, a reset, a power cycle, a
/// blocked face, spontaneous resets, a second robot, varied durations): the generated C
/// still brings the cubes to where the scenario's moves end.
#[test]
fn every_example_scenario_reaches_its_end_under_every_fault_kind() {
    let scenario = repo_root().join("robots/cubes/examples/faults.toml");
    for (stem, _) in SCENARIOS {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let (_, [program, from, expect]) = import(&example(stem), dir.path());
        for seed in ["1", "2", "3"] {
            let simulated = simulate(
                &program,
                &from,
                &expect,
                &["--scenario", arg(&scenario), "--seed", seed],
            );
            assert!(
                simulated.starts_with("SUCCESS"),
                "{stem} seed {seed}: {simulated}"
            );
        }
    }
}

#[test]
fn an_exported_scenario_imports_as_the_same_sequence() {
    for (stem, sequence) in SCENARIOS {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let (_, [program, from, _]) = import(&example(stem), &dir.path().join("first"));
        let exported = dir.path().join(format!("{stem}.scen"));
        let args = [
            "export",
            "scen",
            arg(&program),
            "--sequence",
            sequence,
            "--from",
            arg(&from),
            "-o",
            arg(&exported),
        ];
        ok(&args, 0);
        let (_, [again, _, _]) = import(&exported, &dir.path().join("again"));
        assert_eq!(statements(&program), statements(&again), "{stem}");
    }
}

#[test]
fn parallelise_of_a_scenario_written_one_move_at_a_time_gives_back_its_sets() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let (_, [program, from, _]) = import(&example("four-slides"), dir.path());
    // The same moves, one per step.
    let source = std::fs::read_to_string(&program).expect("the program reads");
    let one_at_a_time = source.replace(" & ", ";\n    ");
    let serial = dir.path().join("serial.dr");
    std::fs::write(&serial, one_at_a_time).expect("written");
    let out = dir.path().join("parallel.dr");
    let args = [
        "parallelise",
        arg(&serial),
        "--sequence",
        "four_slides",
        "--from",
        arg(&from),
        "-o",
        arg(&out),
    ];
    let run = dynarole(&args);
    let said = text(&run.stderr);
    assert_eq!(run.status.code(), Some(0), "{said}");
    assert!(said.contains("8 statements, 2 groups"), "{said}");
    // The parallel form replays to the same end.
    let expect = dir.path().join("four-slides.expect.json");
    let replayed = ok(
        &[
            "replay",
            arg(&out),
            "--from",
            arg(&from),
            "--expect",
            arg(&expect),
        ],
        0,
    );
    assert!(replayed.contains("0 rejected"), "{replayed}");
}

#[test]
fn a_simulated_scenario_is_recorded_and_the_viewer_moves_its_cubes() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let (_, [program, from, expect]) = import(&example("pivot180"), dir.path());
    let recording = dir.path().join("run.json");
    simulate(
        &program,
        &from,
        &expect,
        &["--seed", "1", "--record", arg(&recording)],
    );
    let poses = ok(&["view", arg(&recording), "--poses-at", "0,5000"], 0);
    let lines: Vec<&str> = poses.lines().collect();
    assert_eq!(lines.len(), 2, "{poses}");
    assert_ne!(
        lines[0].split("\"time_ms\"").next(),
        lines[1].split("\"time_ms\"").next(),
        "{poses}"
    );
    let page = dir.path().join("run.html");
    ok(&["view", arg(&recording), "-o", arg(&page)], 0);
    assert!(std::fs::metadata(&page).expect("written").len() > 10_000);
}

/// Fixed modules that no face joins stand on one ground (`--ground`): it holds the robot
/// together for the move rules and carries the fixed modules' packets, so the scenario
/// imports and simulates; without it the scenario is refused, its modules apart.
#[test]
fn a_ground_joins_fixed_modules_that_no_face_joins() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let plan = example("ground-monkey");
    let apart = dynarole(&["import", arg(&plan), "-o", arg(dir.path())]);
    assert_eq!(apart.status.code(), Some(1));
    assert!(
        text(&apart.stderr).contains("do not all touch"),
        "{}",
        text(&apart.stderr)
    );
    let printed = ok(
        &["import", arg(&plan), "-o", arg(dir.path()), "--ground", "1"],
        0,
    );
    assert!(printed.contains("1 monkey"), "{printed}");
    let [program, from, expect] =
        ["dr", "from.json", "expect.json"].map(|e| dir.path().join(format!("ground-monkey.{e}")));
    let start = std::fs::read_to_string(&from).expect("written");
    assert_eq!(start.matches("\"fixed\": true").count(), 2, "{start}");
    for seed in ["1", "2"] {
        let simulated = simulate(&program, &from, &expect, &["--loss", "0.3", "--seed", seed]);
        assert!(simulated.starts_with("SUCCESS"), "{simulated}");
    }
}

/// `verify` on a hand-written cube program (spin, installed by `scripts/ensure-spin` from the
/// test command): S1-S3 and L proved for the walk along the row.
#[test]
fn verify_proves_the_walk() {
    let examples = repo_root().join("robots/cubes/examples");
    let (program, from) = (examples.join("walk.dr"), examples.join("cubes-row4.json"));
    let args = [
        "verify",
        arg(&program),
        "--sequence",
        "walk",
        "--from",
        arg(&from),
    ];
    let printed = ok(&args, 0);
    assert!(printed.contains("result: verified"), "{printed}");
}
