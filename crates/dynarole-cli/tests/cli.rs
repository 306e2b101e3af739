//! The `dynarole` binary end to end: exit codes, output, and files it writes.

mod common;

use common::{dynarole, repo_root, text};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `dynarole replay FILE --sequence S... --from FROM --expect EXPECT`.
fn replay(file: &str, sequences: &[&str], from: &str, expect: &str) -> Output {
    let mut args = vec!["replay", file, "--from", from, "--expect", expect];
    for sequence in sequences {
        args.extend(["--sequence", sequence]);
    }
    dynarole(&args)
}

fn scratch(name: &str, contents: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-tests");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("scratch file");
    path
}

#[test]
fn a_mismatch_names_the_expected_and_the_reached_side() {
    // Once swapped: M0 is at [0, 0, 0] in eight.json, and was printed as "found" there.
    let out = replay(
        "robots/atron/examples/eight2car.dr",
        &["eight2car"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/eight.json",
    );
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains("module M0 misplaced: expected [0, 0, 0] NS_BROKEN, reached [2, 2, 0]"),
        "{stdout}"
    );
    assert!(
        stdout.contains("connection M0.C0-M6.C3 in the reached configuration only"),
        "{stdout}"
    );
}

#[test]
fn a_success_says_which_modules_never_declared_the_end_and_why() {
    // M2 lets go of M1 first: cut off, it cannot hear that M0's turn ends the sequence. The
    // run succeeds (every statement done), and once said nothing of M2.
    let program = scratch(
        "cut.dr",
        "robot atron;\nsequence cut {\n    M2.Connector[2].retract();\n    \
         M0.Joint.rotateFromToBy(0, 108, true, 150);\n}\n",
    );
    let scenario = scratch("cut.toml", "timeout_ms = 20000\n");
    let out = dynarole(&[
        "simulate",
        program.to_str().expect("path"),
        "--from",
        "robots/atron/examples/verify/line3.json",
        "--scenario",
        scenario.to_str().expect("path"),
    ]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.contains(
            "note: M2 never declared the end: no latched connection joins it to a module that did"
        ),
        "{stdout}"
    );
    assert!(!stdout.contains("note: M0"), "{stdout}");
}

#[test]
fn messages_quoting_huge_user_text_stay_small() {
    // A 100,000-character name, quoted by the message that lists the file's sequences, and a
    // 100,000-character module name in a scenario: once printed whole.
    let long = "s".repeat(100_000);
    let program = scratch(
        "long-name.dr",
        &format!("robot atron;\nsequence {long} {{\n    M0.Joint.rotateFromToBy(0, 108, true, 150);\n}}\n"),
    );
    let out = dynarole(&["reverse", program.to_str().expect("path"), "nosuch"]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.len() < 2_000, "{} bytes", stderr.len());
    assert!(stderr.contains("bytes not shown"), "{stderr}");
    let scenario = scratch(
        "long-module.toml",
        &format!("[[reset]]\nmodule = \"{long}\"\nat_ms = 10\n"),
    );
    let out = dynarole(&[
        "simulate",
        "robots/atron/examples/eight2car.dr",
        "--from",
        "robots/atron/examples/eight.json",
        "--scenario",
        scenario.to_str().expect("path"),
    ]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.len() < 2_000, "{} bytes", stderr.len());
    assert!(stderr.contains("is not shown"), "{stderr}");
}

#[test]
fn the_help_says_what_the_tool_is_and_every_command_shows_an_example() {
    let top = dynarole(&["--help"]);
    let help = text(&top.stdout);
    assert_eq!(top.status.code(), Some(0), "{help}");
    assert!(help.contains("A reconfiguration is written once"), "{help}");
    assert!(
        help.contains("Documentation:") && help.contains("Exit codes:"),
        "{help}"
    );
    for command in [
        "check",
        "compile",
        "verify",
        "show",
        "replay",
        "simulate",
        "view",
        "campaign",
        "fmt",
        "reverse",
        "parallelise",
    ] {
        let out = dynarole(&["help", command]);
        let help = text(&out.stdout);
        assert!(
            help.contains(&format!("Example:\n  dynarole {command} ")),
            "{command}: {help}"
        );
    }
}

#[test]
fn replay_reports_the_warnings_check_from_reports() {
    // eight2car's extend and retract joined by `&` split the robot if the retract ends first:
    // `check --from` warns, and `replay` once said "0 warnings" of the same sequence.
    let out = replay(
        "robots/atron/examples/eight2car.dr",
        &["eight2car"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/car.json",
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stdout));
    let stderr = text(&out.stderr);
    assert!(stderr.contains("warning[not-independent]"), "{stderr}");
    assert!(
        !text(&out.stdout).contains(" 0 warnings"),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn the_commands_emit_prints_are_quoted_for_a_shell() {
    // Pasting the printed `submit` line once ran what the output folder's name contained.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-emit-quoted");
    let _ = std::fs::remove_dir_all(&dir);
    let out_dir = dir.join("o$(touch PWNED)");
    let out = dynarole(&[
        "campaign",
        "examples/campaigns/smoke.toml",
        "--emit",
        "slurm",
        "--shards",
        "2",
        "-o",
        out_dir.to_str().expect("path"),
    ]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let quoted = format!("'{}/submit.sh'", out_dir.display());
    assert!(
        stdout.contains(&format!("submit from this directory: {quoted}")),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!("campaign status '{}'", out_dir.display())),
        "{stdout}"
    );
}

#[test]
fn check_accepts_the_examples() {
    let out = dynarole(&["check", "robots/atron/examples/eight2car.dr"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("ok: robots/atron/examples/eight2car.dr"));
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
        dynarole(&["check", "--protocol", "semaphore", "x.dr"])
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
    let out = dynarole(&["reverse", "robots/atron/examples/eight2car.dr", "eight2car"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let reversed = text(&out.stdout);
    assert!(reversed.starts_with(
        "robot atron;\n\nsequence car2eight {\n    M1.Joint.rotateFromToBy(216, 108, false, 150);"
    ));
    let path = scratch("car2eight.dr", &reversed);
    let path = path.to_str().expect("utf-8 path");
    assert_eq!(dynarole(&["check", path]).status.code(), Some(0));
    let back = dynarole(&["reverse", path, "car2eight", "--name", "eight2car"]);
    let original = dynarole(&["reverse", "robots/atron/examples/eight2car.dr", "car2eight"]);
    assert_eq!(text(&back.stdout), text(&original.stdout));
}

#[test]
fn reverse_of_an_unknown_sequence_is_bad_input() {
    let out = dynarole(&["reverse", "robots/atron/examples/eight2car.dr", "nope"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("no sequence `nope` in robots/atron/examples/eight2car.dr; sequences in robots/atron/examples/eight2car.dr: eight2car, car2eight"));
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
    let out = dynarole(&["fmt", "--check", "robots/atron/examples/eight2car.dr"]);
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
        stderr.contains("error: field `part[0].count`: expected 1 to 255, found 300"),
        "{stderr}"
    );
    // The file, line and column of the value, and a caret under it.
    assert!(stderr.contains("broken.robot.toml:4:9"), "{stderr}");
    assert!(stderr.contains("count = 300\n  │         ^^^"), "{stderr}");
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

#[test]
fn replay_of_fig5_gives_exactly_the_car_and_its_reverse_the_eight() {
    let forward = replay(
        "robots/atron/examples/eight2car.dr",
        &["eight2car"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/car.json",
    );
    assert_eq!(
        forward.status.code(),
        Some(0),
        "{}{}",
        text(&forward.stdout),
        text(&forward.stderr)
    );
    // One warning, as `check --from` gives: the extend and the retract joined by `&`.
    assert!(text(&forward.stdout).contains("25 statements, 0 rejected, 1 warning\n"));
    let back = replay(
        "robots/atron/examples/eight2car.dr",
        &["car2eight"],
        "robots/atron/examples/car.json",
        "robots/atron/examples/eight.json",
    );
    assert_eq!(back.status.code(), Some(0), "{}", text(&back.stdout));
    let both = replay(
        "robots/atron/examples/eight2car.dr",
        &["eight2car", "car2eight"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/eight.json",
    );
    assert_eq!(both.status.code(), Some(0), "{}", text(&both.stdout));
}

#[test]
fn replay_of_the_tour_and_the_snake() {
    let snake = replay(
        "robots/atron/examples/eight2car.dr",
        &["eight2snake"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/snake.json",
    );
    assert_eq!(snake.status.code(), Some(0), "{}", text(&snake.stdout));
    let tour = replay(
        "robots/atron/examples/eight2car.dr",
        &["tour"],
        "robots/atron/examples/car.json",
        "robots/atron/examples/car.json",
    );
    assert_eq!(tour.status.code(), Some(0), "{}", text(&tour.stdout));
    assert!(text(&tour.stdout).contains("62 statements, 0 rejected"));
}

#[test]
fn replay_of_the_mtran_experiment_and_its_derived_reverse() {
    let out = scratch("moved.json", "");
    let out = out.to_str().expect("utf-8 path");
    let forward = dynarole(&[
        "replay",
        "robots/mtran/examples/move_module.dr",
        "--sequence",
        "left2right",
        "--from",
        "robots/mtran/examples/mtran-snake4.json",
        "--expect",
        "robots/mtran/examples/mtran-snake4-moved.json",
        "--out",
        out,
    ]);
    assert_eq!(forward.status.code(), Some(0), "{}", text(&forward.stdout));
    // The final configuration as the robot summarises its modules (`module_lines`).
    let printed = "final configuration:\n  T10    -y-z+x       joints 0 / 0 deg\n  \
                   T11    -y-z+x       joints 0 / 0 deg\n  T12    -y-z+x       joints 0 / 0 deg\n  \
                   T13    -y-z+x       joints 0 / 0 deg\n  \
                   latches: T10.0-T13.3 T12.0-T11.3 T13.0-T12.3\n";
    assert!(
        text(&forward.stdout).contains(printed),
        "{}",
        text(&forward.stdout)
    );
    let back = dynarole(&[
        "replay",
        "robots/mtran/examples/move_module.dr",
        "--sequence",
        "right2left",
        "--from",
        out,
        "--expect",
        "robots/mtran/examples/mtran-snake4.json",
    ]);
    assert_eq!(back.status.code(), Some(0), "{}", text(&back.stdout));
}

#[test]
fn replay_reports_a_mismatch_with_the_difference_and_exit_1() {
    let out = replay(
        "robots/atron/examples/eight2car.dr",
        &["eight2car"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/eight.json",
    );
    assert_eq!(out.status.code(), Some(1));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("does NOT match robots/atron/examples/eight.json"),
        "{stdout}"
    );
    assert!(
        stdout.contains("misplaced") || stdout.contains("connection"),
        "{stdout}"
    );
}

#[test]
fn replay_rejects_a_configuration_of_another_robot_or_a_bad_field() {
    let other = dynarole(&[
        "replay",
        "robots/atron/examples/eight2car.dr",
        "--sequence",
        "eight2car",
        "--from",
        "robots/mtran/examples/mtran-snake4.json",
    ]);
    assert_eq!(other.status.code(), Some(1));
    assert!(
        text(&other.stderr).contains("robot `atron` but the configuration is an MTRAN robot"),
        "{}",
        text(&other.stderr)
    );
    let bad = scratch("bad.json", "{\"name\": \"x\", \"robot\": \"ATRON\", \"modules\": [{\"name\": \"M0\", \"id\": 0, \"position\": [0, 0, 0], \"orientation\": \"NX\", \"joint\": 0}], \"connections\": []}");
    let bad_out = dynarole(&[
        "replay",
        "robots/atron/examples/eight2car.dr",
        "--sequence",
        "eight2car",
        "--from",
        bad.to_str().expect("path"),
    ]);
    assert_eq!(bad_out.status.code(), Some(1));
    assert!(
        text(&bad_out.stderr).contains("modules[0].orientation"),
        "{}",
        text(&bad_out.stderr)
    );
}

#[test]
fn check_from_reports_the_order_dependent_group_of_fig5() {
    let out = dynarole(&[
        "check",
        "robots/atron/examples/fig5.dr",
        "--from",
        "robots/atron/examples/eight.json",
    ]);
    assert_eq!(out.status.code(), Some(0), "warnings do not fail a check");
    let stderr = text(&out.stderr);
    assert!(stderr.contains("warning[not-independent]"), "{stderr}");
    assert!(stderr.contains("fig5.dr:19:5"), "{stderr}");
}

/// The picture of a shipped configuration.
fn show_svg(file: &str) -> String {
    let text_json = std::fs::read_to_string(repo_root().join(file)).expect("configuration");
    let config = dynarole_robots::read_configuration(&text_json).expect("valid");
    dynarole_cli::show::render_svg(&config).expect("drawn")
}

/// Centre and radius of every module outline (the unfilled circles larger than a badge).
fn module_outlines(svg: &str) -> Vec<(f64, f64, f64)> {
    let attribute = |element: &str, name: &str| -> f64 {
        let start = element.find(&format!(" {name}=\"")).expect("attribute") + name.len() + 3;
        let rest = &element[start..];
        rest[..rest.find('"').expect("closing quote")]
            .parse()
            .expect("number")
    };
    svg.lines()
        .filter(|l| l.starts_with("<circle") && l.contains("fill=\"none\""))
        .map(|l| (attribute(l, "cx"), attribute(l, "cy"), attribute(l, "r")))
        .filter(|c| c.2 > 8.0)
        .collect()
}

#[test]
fn show_draws_every_module_and_latch_of_the_eight() {
    let svg = show_svg("robots/atron/examples/eight.json");
    assert_eq!(module_outlines(&svg).len(), 7, "one disc per module");
    assert_eq!(
        svg.matches("<polygon").count(),
        7,
        "one south half per module"
    );
    // Two numbered badges (a white disc and its outline) per latch.
    assert_eq!(svg.matches(r#" r="8" "#).count(), 8 * 2 * 2);
    for name in ["M0", "M1", "M2", "M3", "M4", "M5", "M6"] {
        assert!(
            svg.contains(&format!("\n{name}\n</text>")),
            "{name} is labelled"
        );
    }
    assert_eq!(
        svg,
        show_svg("robots/atron/examples/eight.json"),
        "deterministic"
    );
    insta::assert_snapshot!("eight_svg", svg);
}

#[test]
fn show_chooses_a_view_where_no_module_hides_another() {
    for file in [
        "robots/atron/examples/car.json",
        "robots/atron/examples/eight.json",
        "robots/atron/examples/snake.json",
    ] {
        let discs = module_outlines(&show_svg(file));
        assert_eq!(discs.len(), 7, "{file}");
        for (i, a) in discs.iter().enumerate() {
            for b in &discs[i + 1..] {
                let apart = (a.0 - b.0).hypot(a.1 - b.1);
                assert!(apart >= a.2 + b.2, "{file}: discs {a:?} and {b:?} overlap");
            }
        }
    }
}

#[test]
fn show_keeps_far_apart_modules_on_a_bounded_canvas() {
    let far = scratch(
        "far.json",
        r#"{"name": "far", "robot": "ATRON", "modules": [
            {"name": "A", "id": 0, "position": [0, 0, 0], "orientation": "NS", "joint": 0},
            {"name": "B", "id": 1, "position": [50000, 0, 50000], "orientation": "NS", "joint": 0}
        ], "connections": []}"#,
    );
    let png = scratch("far.png", "");
    let started = std::time::Instant::now();
    let out = dynarole(&[
        "show",
        far.to_str().expect("path"),
        "-o",
        png.to_str().expect("path"),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(started.elapsed().as_secs() < 60, "a small picture is quick");
    let bytes = std::fs::read(&png).expect("png written");
    let size =
        |at: usize| u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    assert!(
        size(16) <= 1400 && size(20) <= 1000,
        "{}x{}",
        size(16),
        size(20)
    );
}

#[test]
fn show_writes_png_and_svg_and_refuses_other_formats() {
    let png = scratch("car.png", "");
    let out = dynarole(&[
        "show",
        "robots/atron/examples/car.json",
        "-o",
        png.to_str().expect("path"),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let bytes = std::fs::read(&png).expect("png written");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let svg = scratch("snake.svg", "");
    let out = dynarole(&[
        "show",
        "robots/mtran/examples/mtran-snake4.json",
        "-o",
        svg.to_str().expect("path"),
    ]);
    assert_eq!(out.status.code(), Some(0));
    assert!(std::fs::read_to_string(&svg)
        .expect("svg")
        .contains("\nT12\n</text>"));
    assert_eq!(
        dynarole(&["show", "robots/atron/examples/car.json", "-o", "car.gif"])
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn show_makes_the_folder_it_writes_into() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-show-folder");
    let _ = std::fs::remove_dir_all(&dir);
    let svg = dir.join("pictures").join("car.svg");
    let out = dynarole(&[
        "show",
        "robots/atron/examples/car.json",
        "-o",
        svg.to_str().expect("path"),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(svg.is_file());
}

#[test]
fn compile_writes_a_self_contained_directory_for_each_protocol() {
    for protocol in ["lattice", "paper"] {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join("cli-compile")
            .join(protocol);
        let _ = std::fs::remove_dir_all(&dir);
        let out = dynarole(&[
            "compile",
            "robots/atron/examples/eight2car.dr",
            "--sequence",
            "eight2car",
            "--protocol",
            protocol,
            "-o",
            dir.to_str().expect("path"),
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let stdout = text(&out.stdout);
        assert!(
            stdout.contains("25 statements") && stdout.contains("packet"),
            "{stdout}"
        );
        for file in [
            "Makefile",
            "dr_program.c",
            "dr_program.h",
            "dr_program_conf.h",
            "dr_hal.h",
            "dr_packet.c",
        ] {
            assert!(dir.join(file).is_file(), "{protocol}: {file} missing");
        }
        let make = Command::new("make")
            .arg("-s")
            .current_dir(&dir)
            .output()
            .expect("make runs");
        assert!(make.status.success(), "{}", text(&make.stderr));
    }
}

#[test]
fn compile_token_needs_a_configuration_and_names_unroutable_statements() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-compile-token");
    let _ = std::fs::remove_dir_all(&dir);
    let dir_arg = dir.to_str().expect("path");
    let args = [
        "compile",
        "robots/atron/examples/eight2car.dr",
        "--protocol",
        "token",
        "-o",
        dir_arg,
    ];
    let without = dynarole(&args);
    assert_eq!(without.status.code(), Some(2));
    assert!(
        text(&without.stderr).contains("--from"),
        "{}",
        text(&without.stderr)
    );
    let with: Vec<&str> = args
        .iter()
        .copied()
        .chain([
            "--from",
            "robots/atron/examples/eight.json",
            "--token-retries",
            "plain",
        ])
        .collect();
    let out = dynarole(&with);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("token protocol"),
        "{}",
        text(&out.stdout)
    );
    let program = std::fs::read_to_string(dir.join("dr_program.c")).expect("dr_program.c");
    assert!(program.contains("0u, /* reliable: acknowledged hops (plain) */"));
    assert!(dir.join("dr_token.c").is_file());
    // Two modules with no latched chain between them: the hand-over is named at its line.
    let apart = scratch(
        "token_apart.dr",
        "robot atron;\nsequence s {\n    M0.Connector[0].retract();\n    M0.Connector[4].retract();\n    M6.Connector[2].retract();\n}\n",
    );
    let cut = dynarole(&[
        "compile",
        apart.to_str().expect("path"),
        "--protocol",
        "token",
        "--from",
        "robots/atron/examples/eight.json",
        "-o",
        dir_arg,
    ]);
    let stderr = text(&cut.stderr);
    assert_eq!(cut.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("token_apart.dr:5:5"), "{stderr}");
    assert!(
        stderr.contains("no chain of latched modules joins M0 to M6"),
        "{stderr}"
    );
    let bad = dynarole(&[
        "compile",
        "robots/atron/examples/eight2car.dr",
        "--protocol",
        "token",
        "--token-retries",
        "0",
        "-o",
        dir_arg,
    ]);
    assert_eq!(bad.status.code(), Some(2));
}

#[test]
fn compile_refuses_what_the_paper_protocol_cannot_run() {
    let path = scratch("nested_compile.dr", "robot atron;\nsequence s {\n    { M0.Connector[0].retract(); M0.Connector[0].extend(); } & M3.Connector[4].retract();\n}\n");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-compile-refused");
    let _ = std::fs::remove_dir_all(&dir);
    let out = dynarole(&[
        "compile",
        path.to_str().expect("path"),
        "--protocol",
        "paper",
        "-o",
        dir.to_str().expect("path"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("not supported by the paper protocol"));
    assert!(!dir.exists(), "nothing is written");
    let lattice = dynarole(&[
        "compile",
        path.to_str().expect("path"),
        "-o",
        dir.to_str().expect("path"),
    ]);
    assert_eq!(lattice.status.code(), Some(0), "{}", text(&lattice.stderr));
}

/// The paper's experiments as ready scenarios (examples/scenarios/README.md): file, sequences,
/// start, expected end, scenario.
const SCENARIOS: [(&str, &[&str], &str, &str, &str); 6] = [
    (
        "robots/atron/examples/eight2car.dr",
        &["eight2car", "car2eight", "eight2car", "car2eight"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/eight.json",
        "long-running",
    ),
    (
        "robots/atron/examples/eight2car.dr",
        &["eight2car"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/car.json",
        "fig7-power-off",
    ),
    (
        "robots/atron/examples/eight2car.dr",
        &["eight2car"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/car.json",
        "fig8-reset-connecting",
    ),
    (
        "robots/atron/examples/eight2car.dr",
        &["eight2car"],
        "robots/atron/examples/eight.json",
        "robots/atron/examples/car.json",
        "fig8-blocked-paths",
    ),
    (
        "robots/atron/examples/eight2car.dr",
        &["tour"],
        "robots/atron/examples/car.json",
        "robots/atron/examples/car.json",
        "lossy",
    ),
    (
        "robots/mtran/examples/move_module.dr",
        &["left2right", "right2left"],
        "robots/mtran/examples/mtran-snake4.json",
        "robots/mtran/examples/mtran-snake4.json",
        "lossy",
    ),
];

fn simulate(scenario: &(&str, &[&str], &str, &str, &str), extra: &[&str]) -> Output {
    let (file, sequences, from, expect, name) = scenario;
    let path = format!("examples/scenarios/{name}.toml");
    let mut args = vec![
        "simulate",
        file,
        "--from",
        from,
        "--expect",
        expect,
        "--scenario",
        &path,
        "--seed",
        "1",
    ];
    for s in sequences.iter() {
        args.push("--sequence");
        args.push(s);
    }
    args.extend_from_slice(extra);
    dynarole(&args)
}

#[test]
fn every_scenario_ends_in_the_expected_configuration_with_the_lattice_protocol() {
    for scenario in &SCENARIOS {
        let out = simulate(scenario, &[]);
        let stdout = text(&out.stdout);
        assert_eq!(out.status.code(), Some(0), "{}: {stdout}", scenario.4);
        assert!(
            stdout.starts_with("SUCCESS: lattice protocol"),
            "{}: {stdout}",
            scenario.4
        );
        assert!(
            stdout.contains("violations: S1 0, S2 0, S3 0"),
            "{}: {stdout}",
            scenario.4
        );
    }
}

#[test]
fn the_paper_protocol_as_it_is() {
    // It cannot reset a module during a parallel operation without the restart the paper
    // proposed (Sec. III-C): M4 is reset while its parallel extend runs and the run stalls.
    let reset = &SCENARIOS[2];
    let stalled = simulate(reset, &["--protocol", "paper"]);
    assert_eq!(stalled.status.code(), Some(3), "{}", text(&stalled.stdout));
    assert!(
        text(&stalled.stderr).contains("replay with: dynarole simulate"),
        "a failed run says how to replay it"
    );
    let restarted = simulate(reset, &["--protocol", "paper", "--restart-pending"]);
    assert_eq!(
        restarted.status.code(),
        Some(0),
        "{}",
        text(&restarted.stdout)
    );
    // The other experiments succeed with it too (single runs of each), the four-sequence
    // long-running one included (examples/scenarios/README.md once said it could not run).
    for scenario in [&SCENARIOS[0], &SCENARIOS[1], &SCENARIOS[3], &SCENARIOS[4]] {
        let out = simulate(scenario, &["--protocol", "paper"]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}: {}",
            scenario.4,
            text(&out.stdout)
        );
    }
}

#[test]
fn the_printed_replay_command_gives_the_same_run_for_a_keyed_robot() {
    // The printed command once dropped --key and --robot-id: the keyed run it printed then
    // replayed as another program, and a success.
    let reset = &SCENARIOS[2];
    let keyed = [
        "--protocol",
        "paper",
        "--robot-id",
        "5",
        "--key",
        "00112233445566778899aabbccddeeff",
    ];
    let failed = simulate(reset, &keyed);
    assert_eq!(failed.status.code(), Some(3), "{}", text(&failed.stdout));
    let stderr = text(&failed.stderr);
    let line = stderr
        .lines()
        .find_map(|l| l.strip_prefix("replay with: dynarole simulate "))
        .unwrap_or_else(|| panic!("no replay command in: {stderr}"));
    assert!(line.contains("--robot-id 5"), "{line}");
    assert!(
        line.contains("--key 00112233445566778899aabbccddeeff"),
        "{line}"
    );
    // The repository's paths need no quoting, so the words are the arguments.
    let words: Vec<&str> = line.split(' ').collect();
    let again = dynarole(&std::iter::once("simulate").chain(words).collect::<Vec<_>>());
    assert_eq!(again.status.code(), Some(3), "{}", text(&again.stdout));
    // The same run: every line but the wall time.
    let run = |out: &std::process::Output| {
        text(&out.stdout)
            .lines()
            .filter(|l| !l.contains("of wall time"))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    assert_eq!(run(&again), run(&failed), "the same run");
}

#[test]
fn campaign_writes_runs_summary_and_plots_and_resumes() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-campaign");
    let _ = std::fs::remove_dir_all(&dir);
    let dir_arg = dir.to_str().expect("path");
    let first = dynarole(&[
        "campaign",
        "examples/campaigns/smoke.toml",
        "-o",
        dir_arg,
        "--max-runs",
        "2",
    ]);
    assert_eq!(first.status.code(), Some(0), "{}", text(&first.stderr));
    let partial = std::fs::read_to_string(dir.join("runs.csv")).expect("runs.csv");
    assert_eq!(
        partial.lines().count(),
        3,
        "a header and two runs:\n{partial}"
    );
    let rest = dynarole(&["campaign", "examples/campaigns/smoke.toml", "-o", dir_arg]);
    assert_eq!(rest.status.code(), Some(0), "{}", text(&rest.stderr));
    let runs = std::fs::read_to_string(dir.join("runs.csv")).expect("runs.csv");
    assert!(
        runs.starts_with(&partial),
        "resuming keeps what was recorded"
    );
    assert!(runs.lines().count() > 3);
    assert!(dir.join("summary.csv").is_file());
    assert!(dir.join("success-loss.svg").is_file() && dir.join("success-loss.png").is_file());
}

#[test]
fn simulate_defaults_to_the_first_sequence_like_the_other_commands() {
    let run = |extra: &[&str]| {
        let mut args = vec![
            "simulate",
            "robots/atron/examples/verify/ab_c.dr",
            "--from",
            "robots/atron/examples/verify/line3.json",
        ];
        args.extend(extra);
        let out = dynarole(&args);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        // Everything but the wall-time line, which varies from run to run.
        text(&out.stdout)
            .lines()
            .filter(|l| !l.contains("wall time"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let default = run(&[]);
    assert!(default.starts_with("SUCCESS"), "{default}");
    assert_eq!(default, run(&["--sequence", "ab_c"]));
}

#[test]
fn campaign_prints_progress_lines_when_stderr_is_not_a_terminal() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-campaign-progress");
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_dynarole"))
        .args(["campaign", "examples/campaigns/smoke.toml", "--no-plots"])
        .args(["--max-runs", "6", "-j", "1", "-o"])
        .arg(&dir)
        .env("DYNAROLE_PROGRESS_SECONDS", "0.001")
        .current_dir(repo_root())
        .output()
        .expect("dynarole runs");
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stderr = text(&out.stderr);
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("campaign: ") && l.contains(" of 6 runs ("))
        .collect();
    // Six runs take a few milliseconds even in a release build: lines while they run, and one
    // at the end.
    assert!(lines.len() >= 2, "{stderr}");
    assert!(lines.iter().all(|l| l.contains("runs/s")), "{stderr}");
    assert!(
        lines
            .last()
            .is_some_and(|l| l.contains("6 of 6 runs (100.0 %)") && l.contains("all done")),
        "{stderr}"
    );
    assert!(
        !text(&out.stdout).contains("runs/s"),
        "progress stays off stdout"
    );
}

#[test]
fn a_bad_progress_interval_is_a_usage_error_naming_the_variable() {
    let out = Command::new(env!("CARGO_BIN_EXE_dynarole"))
        .args(["campaign", "examples/campaigns/smoke.toml", "-o"])
        .arg(Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-campaign-bad-interval"))
        .env("DYNAROLE_PROGRESS_SECONDS", "often")
        .current_dir(repo_root())
        .output()
        .expect("dynarole runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("DYNAROLE_PROGRESS_SECONDS=often"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn simulate_explains_the_checks_once_and_heads_the_trace_with_its_columns() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-simulate-trace");
    std::fs::create_dir_all(&dir).expect("dir");
    let trace = dir.join("run.trace");
    let trace_arg = trace.to_str().expect("path");
    let out = dynarole(&[
        "simulate",
        "robots/atron/examples/eight2car.dr",
        "--sequence",
        "eight2car",
        "--from",
        "robots/atron/examples/eight.json",
        "--expect",
        "robots/atron/examples/car.json",
        "--seed",
        "1",
        "--repeat",
        "2",
        "--trace",
        trace_arg,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    for check in ["S1", "S2", "S3"] {
        assert_eq!(
            stdout.matches(&format!("    {check}: no ")).count(),
            1,
            "{stdout}"
        );
    }
    let first = std::fs::read_to_string(dir.join("run.trace.0")).expect("trace");
    let header = first.lines().next().unwrap_or_default();
    assert!(header.starts_with('#'), "{header}");
    // The titles stand where the columns of the lines start.
    let line = first
        .lines()
        .find(|l| l.contains(" start "))
        .expect("a start event");
    for (title, value) in [("module", "M"), ("event", "start"), ("state", "e0")] {
        let column = header.find(title).expect("title");
        assert!(
            line[column..].starts_with(value),
            "{title}:\n{header}\n{line}"
        );
    }
}

/// A statement every ATRON file can use, on module `m`.
fn retract(m: u32) -> String {
    format!("M{m}.Connector[$CONNECTOR_0].retract();")
}

#[test]
fn reverse_names_are_names() {
    let bad = dynarole(&[
        "reverse",
        "robots/atron/examples/eight2car.dr",
        "eight2car",
        "--name",
        "a b",
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        text(&bad.stderr).contains("--name `a b`: expected a name"),
        "{}",
        text(&bad.stderr)
    );
    let injected = dynarole(&[
        "reverse",
        "robots/atron/examples/eight2car.dr",
        "eight2car",
        "--name",
        "x { M0.Connector[$CONNECTOR_0].extend(); } sequence y",
    ]);
    assert_eq!(injected.status.code(), Some(2));
    let grid = scratch(
        "grid.dr",
        &format!("robot atron;\nsequence grid20p {{ {} }}\n", retract(0)),
    );
    let out = dynarole(&["reverse", grid.to_str().expect("path"), "grid20p"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("sequence grid20p_reversed {"),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn a_program_at_the_statement_limit_checks() {
    // On one module each statement waits for one: 60,000 entries in the dependency table.
    let one_module: Vec<String> = (0..60_000).map(|_| retract(0)).collect();
    let source = format!(
        "robot atron;\nsequence s {{\n{}\n}}\n",
        one_module.join("\n")
    );
    let out = dynarole(&["check", scratch("long.dr", &source).to_str().expect("path")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    // Groups of two on 200 modules, each statement waiting for the two of the group before:
    // past the 16-bit table.
    let many: Vec<String> = (0..30_000)
        .map(|i| {
            let first = retract(2 * i % 200);
            format!(
                "{} & {}",
                first.trim_end_matches(';'),
                retract((2 * i + 1) % 200)
            )
        })
        .collect();
    let source = format!("robot atron;\nsequence s {{\n{}\n}}\n", many.join("\n"));
    let out = dynarole(&[
        "check",
        scratch("long-200.dr", &source).to_str().expect("path"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = text(&out.stderr);
    assert!(stderr.contains("more than 65535 entries"), "{stderr}");
}

#[test]
fn hostile_inputs_end_in_one_short_error() {
    // Doubling compositions: refused where the count passes the limit, before expanding.
    let mut doubling = format!("robot atron;\nsequence s0 {{ {} }}\n", retract(0));
    for i in 1..40 {
        doubling.push_str(&format!("sequence s{i} {{ s{}; s{}; }}\n", i - 1, i - 1));
    }
    // A line of 10,000 bad characters: one error, the line not printed.
    let bad_line = format!(
        "robot atron;\nsequence s {{ {} }}\n{}\n",
        retract(0),
        "@".repeat(10_000)
    );
    // A chain of 10,000 sequences, each using the one before.
    let mut chain = format!("robot atron;\nsequence c0 {{ {} }}\n", retract(0));
    for i in 1..10_000 {
        chain.push_str(&format!("sequence c{i} {{ c{}; }}\n", i - 1));
    }
    let role = format!(
        "robot atron;\nrole R requires id == 4294967296;\nsequence s {{ {} }}\n",
        "R.Connector[$CONNECTOR_0].retract();"
    );
    // Many roles and many unknown labels: suggestions are searched for the first few only.
    let mut unknown = String::from("robot atron;\n");
    for i in 0..2_000 {
        unknown.push_str(&format!("role R{i} requires id == {i};\n"));
    }
    unknown.push_str("sequence s {\n");
    for i in 0..2_000 {
        unknown.push_str(&format!("X{i}.Connector[$CONNECTOR_0].retract();\n"));
    }
    unknown.push_str("}\n");
    for (name, source, expected) in [
        ("unknown.dr", unknown, "1950 more diagnostics not shown"),
        (
            "doubling.dr",
            doubling,
            "sequence `s16` would have 65536 statements",
        ),
        ("bad-line.dr", bad_line, "10000 unexpected characters"),
        (
            "chain.dr",
            chain,
            "sequence `c64` uses sequences more than 64 levels deep",
        ),
        ("role-id.dr", role, "4294967296 is out of range here"),
    ] {
        let path = scratch(name, &source);
        let out = dynarole(&["check", path.to_str().expect("path")]);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
        assert!(stderr.contains(expected), "{name}: {stderr}");
        assert!(
            stderr.len() < 40_000,
            "{name}: {} bytes of errors",
            stderr.len()
        );
    }
}

#[test]
fn endless_or_huge_inputs_are_refused_with_the_limit() {
    for args in [
        vec!["check", "/dev/zero"],
        vec![
            "check",
            "robots/atron/examples/eight2car.dr",
            "--from",
            "/dev/zero",
        ],
    ] {
        let out = dynarole(&args);
        assert_eq!(out.status.code(), Some(1));
        let stderr = text(&out.stderr);
        assert!(
            stderr.contains("cannot read /dev/zero") || stderr.contains("/dev/zero:"),
            "{stderr}"
        );
        // A device is refused before it is read (once: after 8 MiB of it).
        assert!(stderr.contains("not a regular file"), "{stderr}");
    }
}

#[test]
fn a_huge_plugin_count_names_the_field() {
    let plugin = scratch(
        "huge.robot.toml",
        "name = \"huge\"\n[[part]]\nname = \"P\"\ncount = 1000000000\nconstant_prefix = \"P_\"\n",
    );
    let source = scratch("huge.dr", "robot huge;\nsequence s { M0.P[0].x(); }\n");
    let out = dynarole(&[
        "check",
        source.to_str().expect("path"),
        "--plugin",
        plugin.to_str().expect("path"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("field `part[0].count`: expected 1 to 255"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn simulate_gives_the_same_trace_with_fixed_and_tickless_stepping() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-simulate-stepping");
    std::fs::create_dir_all(&dir).expect("dir");
    let mut traces = Vec::new();
    for stepping in ["fixed", "tickless"] {
        let trace = dir.join(format!("{stepping}.trace"));
        let trace_arg = trace.to_str().expect("path");
        let out = simulate(
            &SCENARIOS[0],
            &["--stepping", stepping, "--trace", trace_arg],
        );
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        traces.push(std::fs::read_to_string(&trace).expect("trace"));
    }
    assert!(traces[0].lines().count() > 100, "{}", traces[0]);
    assert_eq!(traces[0], traces[1]);
    let out = simulate(&SCENARIOS[0], &["--stepping", "sometimes"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("--stepping"),
        "{}",
        text(&out.stderr)
    );
}

/// `--dissemination`: `fixed` and `adaptive` compile the lattice protocol with that mode in its
/// configuration; another name, or the flag with the paper or token protocol (which have their
/// own fixed period), is a usage error naming what is wrong.
#[test]
fn dissemination_selects_the_lattice_mode_and_is_refused_elsewhere() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-dissemination");
    for (mode, macro_name) in [
        ("fixed", "DR_DISSEMINATION_FIXED"),
        ("adaptive", "DR_DISSEMINATION_ADAPTIVE"),
    ] {
        let out_dir = dir.join(mode);
        let out_text = out_dir.display().to_string();
        let out = dynarole(&[
            "compile",
            "robots/atron/examples/eight2car.dr",
            "--dissemination",
            mode,
            "-o",
            &out_text,
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let conf = std::fs::read_to_string(out_dir.join("dr_program_conf.h")).expect("conf");
        assert!(
            conf.contains(&format!(
                "#define DR_CONF_LATTICE_DISSEMINATION {macro_name}"
            )),
            "{conf}"
        );
    }
    let out = dynarole(&[
        "compile",
        "robots/atron/examples/eight2car.dr",
        "--dissemination",
        "trickle",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("[possible values: adaptive, fixed]"));
    let out = dynarole(&[
        "simulate",
        "robots/atron/examples/eight2car.dr",
        "--from",
        "robots/atron/examples/eight.json",
        "--protocol",
        "paper",
        "--dissemination",
        "fixed",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("--dissemination fixed applies to the lattice protocol only"),
        "{}",
        text(&out.stderr)
    );
}

/// Every protocol option given to a protocol that does not take it is a usage error naming
/// the protocols it applies to (the protocol table's settings), never silently ignored.
#[test]
fn an_option_of_another_protocol_is_refused() {
    let cases: [(&[&str], &str); 5] = [
        (
            &["--protocol", "paper", "--no-nv"],
            "--no-nv applies to the lattice protocol only",
        ),
        (
            &["--protocol", "lattice", "--merge", "java"],
            "--merge java applies to the paper protocol only",
        ),
        (
            &["--protocol", "token", "--restart-pending"],
            "--restart-pending applies to the paper protocol only",
        ),
        (
            &["--protocol", "paper", "--token-retries", "plain"],
            "--token-retries plain applies to the token protocol only",
        ),
        (
            &["--protocol", "paper", "--epochs", "3"],
            "--epochs 3 applies to the lattice protocol only",
        ),
    ];
    let never_written = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-refused-option");
    for (flags, expected) in cases {
        let mut args = vec![
            "compile",
            "robots/atron/examples/eight2car.dr",
            "--from",
            "robots/atron/examples/eight.json",
            "-o",
            never_written.to_str().expect("path"),
        ];
        args.extend_from_slice(flags);
        let out = dynarole(&args);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{flags:?}: {}",
            text(&out.stderr)
        );
        assert!(
            text(&out.stderr).contains(expected),
            "{flags:?}: {}",
            text(&out.stderr)
        );
    }
}
