//! `dynarole import` end to end on the RoFI example plans (`robots/rofi/examples/`): each
//! imports, replays to its last configuration given in RoFI's own format, reverses back to its
//! first, and simulates to its end at 30 % loss; a RofiWorld plan imports too, and
//! `parallelise` of a plan written one turn at a time finds its safe `&`.

mod common;

use common::{arg, dynarole, ok, repo_root, simulate, text};
use std::path::{Path, PathBuf};

/// The example plans, each with its sequence's name.
const PLANS: [(&str, &str); 3] = [
    ("gamma-swing", "gamma_swing"),
    ("snake-to-ring", "snake_to_ring"),
    ("fold-sync", "fold_sync"),
];

/// The last `C` block of a plan in RoFI's old text format: its last configuration, in RoFI's
/// own format.
fn last_configuration(plan: &str) -> String {
    let start = plan.rfind("\nC\n").map_or(0, |at| at + 1);
    plan[start..].to_string()
}

/// Imports `robots/rofi/examples/STEM.txt` into `dir`: the program and the two configurations.
fn import(stem: &str, dir: &Path) -> (String, [PathBuf; 3]) {
    let plan = repo_root().join(format!("robots/rofi/examples/{stem}.txt"));
    let printed = ok(&["import", arg(&plan), "-o", arg(dir)], 0);
    let files = ["dr", "from.json", "expect.json"].map(|ext| dir.join(format!("{stem}.{ext}")));
    (printed, files)
}

#[test]
fn every_example_plan_imports_replays_reverses_and_simulates_at_30_percent_loss() {
    for (stem, sequence) in PLANS {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let (printed, [program, from, expect]) = import(stem, dir.path());
        assert!(
            printed.contains(&format!("sequence `{sequence}`")),
            "{printed}"
        );
        assert!(
            printed.contains("replays to the plan's last configuration"),
            "{printed}"
        );
        assert!(printed.contains("critical path: "), "{printed}");
        let plan =
            std::fs::read_to_string(repo_root().join(format!("robots/rofi/examples/{stem}.txt")))
                .expect("the plan reads");
        let last = dir.path().join("last.txt");
        std::fs::write(&last, last_configuration(&plan)).expect("written");
        let ends = Ends {
            from: &from,
            expect: &expect,
            first: &from,
            last: &last,
        };
        replays_reverses_and_simulates(stem, sequence, &program, &ends, dir.path());
    }
}

/// An imported plan's files and its ends as the planner wrote them.
struct Ends<'a> {
    /// `STEM.from.json` and `STEM.expect.json`, as `import` wrote them.
    from: &'a Path,
    expect: &'a Path,
    /// The plan's first and last configurations, in the planner's own format.
    first: &'a Path,
    last: &'a Path,
}

/// The program replays from its first configuration to the plan's last, its derived reverse
/// goes back to the first, and it simulates to the last at 30 % loss.
fn replays_reverses_and_simulates(
    stem: &str,
    sequence: &str,
    program: &Path,
    ends: &Ends,
    dir: &Path,
) {
    let replay = |program: &Path, from: &Path, expect: &Path| {
        ok(
            &[
                "replay",
                arg(program),
                "--from",
                arg(from),
                "--expect",
                arg(expect),
            ],
            0,
        )
    };
    let replayed = replay(program, ends.from, ends.last);
    assert!(replayed.contains("0 rejected"), "{stem}: {replayed}");
    replay(program, ends.first, ends.last);
    let reverse = ok(&["reverse", arg(program), sequence], 0);
    let reversed = dir.join("reverse.dr");
    std::fs::write(&reversed, reverse).expect("written");
    replay(&reversed, ends.expect, ends.first);
    for seed in ["1", "2"] {
        let simulated = simulate(
            program,
            ends.first,
            ends.last,
            &["--loss", "0.3", "--seed", seed],
        );
        assert!(simulated.starts_with("SUCCESS"), "{stem}: {simulated}");
    }
}

#[test]
fn the_fold_is_a_synchronous_group_and_the_snake_fold_one_parallel_group() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let (_, [fold, ..]) = import("fold-sync", dir.path());
    let text = std::fs::read_to_string(fold).expect("written");
    assert_eq!(text.matches("    sync { ").count(), 1, "{text}");
    let (_, [snake, ..]) = import("snake-to-ring", dir.path());
    let text = std::fs::read_to_string(snake).expect("written");
    assert!(!text.contains("sync {"), "{text}");
    assert_eq!(
        text.matches(" & ").count(),
        3,
        "four turns in one group: {text}"
    );
}

/// Two modules end to end as a RofiWorld: module 2's gamma at `gamma`.
fn world(gamma: i64) -> String {
    format!(
        r#"{{"modules": [{{"id": 1, "type": "universal", "alpha": 0, "beta": 0, "gamma": 0}},
  {{"id": 2, "type": "universal", "alpha": 90, "beta": 0, "gamma": {gamma}}}],
 "moduleJoints": [{{"orientation": "North", "from": {{"id": 1, "connector": "B-Z"}}, "to": {{"id": 2, "connector": "A-Z"}}}}],
 "spaceJoints": [{{"point": [0, 0, 0], "to": {{"id": 1, "component": 6}}, "joint": {{"type": "rigid", "sourceToDestination": "identity"}}}}]}}"#
    )
}

#[test]
fn a_json_array_of_rofiworlds_imports_and_one_world_is_a_configuration() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let plan = dir.path().join("two-worlds.json");
    std::fs::write(&plan, format!("[\n{},\n{}\n]\n", world(0), world(90))).expect("written");
    let printed = ok(&["import", arg(&plan), "-o", arg(dir.path())], 0);
    assert!(printed.contains("RofiWorld JSON"), "{printed}");
    let last = dir.path().join("last.json");
    std::fs::write(&last, world(90)).expect("written");
    let program = dir.path().join("two-worlds.dr");
    let from = dir.path().join("two-worlds.from.json");
    ok(
        &[
            "replay",
            arg(&program),
            "--from",
            arg(&from),
            "--expect",
            arg(&last),
        ],
        0,
    );
    // The wrong end is told apart: the first world is not the last.
    let first = dir.path().join("first.json");
    std::fs::write(&first, world(0)).expect("written");
    ok(
        &[
            "replay",
            arg(&program),
            "--from",
            arg(&from),
            "--expect",
            arg(&first),
        ],
        1,
    );
}

#[test]
fn parallelise_of_a_plan_written_one_turn_at_a_time_joins_its_safe_turns() {
    // The snake's fold of snake-to-ring.txt, one turn per step.
    let config = |m2: (i64, i64), m3: (i64, i64)| {
        format!(
            "C\nM 1 0 0 0\nM 2 0 {} {}\nM 3 {} 0 {}\nM 4 0 0 0\nE 1 B -Z N -Z A 2\nE 2 B -Z N -Z A 3\nE 3 B -Z N -Z A 4\n\n",
            m2.0, m2.1, m3.0, m3.1
        )
    };
    let steps = [
        ((0, 0), (0, 0)),
        ((-90, 0), (0, 0)),
        ((-90, 90), (0, 0)),
        ((-90, 90), (90, 0)),
        ((-90, 90), (90, 90)),
    ];
    let plan_text: String = steps.iter().map(|(a, b)| config(*a, *b)).collect();
    let dir = tempfile::tempdir().expect("a temporary directory");
    let plan = dir.path().join("fold.txt");
    std::fs::write(&plan, plan_text).expect("written");
    ok(&["import", arg(&plan), "-o", arg(dir.path())], 0);
    let program = dir.path().join("fold.dr");
    let from = dir.path().join("fold.from.json");
    let out = dynarole(&[
        "parallelise",
        arg(&program),
        "--sequence",
        "fold",
        "--from",
        arg(&from),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let rewritten = text(&out.stdout);
    assert!(
        rewritten.contains(" &"),
        "the fold's turns are joined: {rewritten}"
    );
    let summary = text(&out.stderr);
    assert!(summary.contains("critical path"), "{summary}");
}

#[test]
fn a_simulated_import_is_recorded_and_the_viewer_moves_its_modules() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let (_, [program, from, expect]) = import("snake-to-ring", dir.path());
    let recording = dir.path().join("run.json");
    simulate(
        &program,
        &from,
        &expect,
        &["--loss", "0.3", "--seed", "1", "--record", arg(&recording)],
    );
    let poses = ok(&["view", arg(&recording), "--poses-at", "0,5000"], 0);
    let lines: Vec<&str> = poses.lines().collect();
    assert_eq!(lines.len(), 2, "{poses}");
    let modules = |line: &str| {
        line.split("\"time_ms\"")
            .next()
            .unwrap_or_default()
            .to_string()
    };
    assert_ne!(
        modules(lines[0]),
        modules(lines[1]),
        "the fold moves modules: {poses}"
    );
    let page = dir.path().join("run.html");
    ok(&["view", arg(&recording), "-o", arg(&page)], 0);
    assert!(std::fs::metadata(&page).expect("written").len() > 10_000);
}

/// Every fault kind (`examples/faults.toml`: loss, dead links, a reset, a power cycle, a
/// blocked connector, spontaneous resets, a second robot, varied durations) on the plans
/// without a synchronous group: the generated C still brings the robot to the plan's end. (A
/// synchronous group's start is agreed over the links: a member cut off by a dead link or a
/// power cycle can start alone, which the simulator reports as a clash; robots/rofi/README.md.)
#[test]
fn the_plans_without_a_synchronous_group_reach_their_end_under_every_fault_kind() {
    let scenario = repo_root().join("robots/rofi/examples/faults.toml");
    for stem in ["gamma-swing", "snake-to-ring"] {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let (_, [program, from, expect]) = import(stem, dir.path());
        for seed in ["1", "2", "3"] {
            let simulated = simulate(
                &program,
                &from,
                &expect,
                &["--scenario", arg(&scenario), "--seed", seed],
            );
            assert!(simulated.contains("resets "), "{simulated}");
        }
    }
}

/// The voxel plans of `robots/rofi/examples/` (rofi-voxel's output for starts written here),
/// each with its sequence's name.
const VOXEL_PLANS: [(&str, &str); 2] = [
    ("voxel-three", "voxel_three"),
    ("voxel-five-loop", "voxel_five_loop"),
];

/// World `k` of a voxel plan (`usize::MAX`: the last), alone in a file of `dir`.
fn voxel_world(plan: &Path, k: usize, dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(plan).expect("the plan reads");
    let worlds: Vec<serde_json::Value> = serde_json::from_str(&text).expect("a JSON array");
    let world = &worlds[k.min(worlds.len() - 1)];
    let path = dir.join(format!("world-{k}.json"));
    std::fs::write(&path, world.to_string()).expect("written");
    path
}

#[test]
fn voxel_plans_import_replay_to_their_last_world_reverse_and_simulate_at_30_percent_loss() {
    for (stem, sequence) in VOXEL_PLANS {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let plan = repo_root().join(format!("robots/rofi/examples/{stem}.json"));
        let printed = ok(&["import", arg(&plan), "-o", arg(dir.path())], 0);
        assert!(printed.contains("(RoFI's voxel JSON)"), "{printed}");
        assert!(
            printed.contains("replays to the plan's last configuration"),
            "{printed}"
        );
        let [program, from, expect] =
            ["dr", "from.json", "expect.json"].map(|ext| dir.path().join(format!("{stem}.{ext}")));
        // The worlds name no module: the last one is matched by its shape alone.
        let (first, last) = (
            voxel_world(&plan, 0, dir.path()),
            voxel_world(&plan, usize::MAX, dir.path()),
        );
        let wrong = ok(
            &[
                "replay",
                arg(&program),
                "--from",
                arg(&from),
                "--expect",
                arg(&first),
            ],
            1,
        );
        assert!(wrong.contains("compared by their shapes alone"), "{wrong}");
        let ends = Ends {
            from: &from,
            expect: &expect,
            first: &first,
            last: &last,
        };
        replays_reverses_and_simulates(stem, sequence, &program, &ends, dir.path());
    }
}

/// rofi-voxel's turns may cut a loop and close another: the cut is a disconnection before
/// the turn, the new contact a connection after it.
#[test]
fn a_voxel_turn_that_cuts_a_loop_disconnects_first_and_connects_what_it_brings_together() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let plan = repo_root().join("robots/rofi/examples/voxel-five-loop.json");
    let printed = ok(&["import", arg(&plan), "-o", arg(dir.path())], 0);
    assert!(printed.contains(", 1 connect(s), 0 turn(s)"), "{printed}");
    assert!(
        printed.contains("1 disconnect(s), 0 connect(s), 1 turn(s)"),
        "{printed}"
    );
    let program = std::fs::read_to_string(dir.path().join("voxel-five-loop.dr")).expect("written");
    assert!(
        program.contains("the connections the turn to configuration"),
        "{program}"
    );
}
