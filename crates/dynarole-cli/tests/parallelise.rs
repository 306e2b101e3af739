//! `dynarole parallelise` end to end: the paper's eight2car written in order comes back
//! parallel (the hand-parallel file's own groups do not verify), its output checks clean
//! forwards and in reverse, the paper protocol gets flat groups, and bad inputs get the usual exit codes.

mod common;

use common::{dynarole, text};
use std::path::{Path, PathBuf};

fn scratch(name: &str, contents: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("parallelise-tests");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let path = dir.join(name);
    // Tests run in parallel and several write the same file: each writes its own copy and
    // renames it into place (atomic), so that no test reads a file another is truncating.
    let thread = format!("{:?}", std::thread::current().id());
    let own: String = thread.chars().filter(char::is_ascii_alphanumeric).collect();
    let partial = dir.join(format!("{name}.{own}.partial"));
    std::fs::write(&partial, contents).expect("scratch file");
    std::fs::rename(&partial, &path).expect("scratch file in place");
    path
}

/// eight2car.dr with every `&` made `;`.
fn sequential_eight2car() -> PathBuf {
    let shipped =
        std::fs::read_to_string(common::repo_root().join("robots/atron/examples/eight2car.dr"))
            .expect("example");
    let sequential = shipped.replace(" &\n", ";\n");
    assert!(!sequential.contains(" &"));
    scratch("eight2car_in_order.dr", &sequential)
}

/// The two critical paths (ms) of the summary line on stderr.
fn critical_paths(stderr: &str) -> (u64, u64) {
    let line = stderr
        .lines()
        .find(|l| l.contains("critical path"))
        .unwrap_or_else(|| panic!("no summary in {stderr}"));
    let figures: Vec<u64> = line
        .split_whitespace()
        .filter_map(|w| w.parse::<f64>().ok())
        .map(|s| (s * 1000.0).round() as u64)
        .collect();
    match figures.as_slice() {
        [.., before, after] => (*before, *after),
        _ => panic!("no figures in {line}"),
    }
}

fn parallelise(file: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "parallelise",
        file,
        "--sequence",
        "eight2car",
        "--from",
        "robots/atron/examples/eight.json",
    ];
    args.extend(extra);
    dynarole(&args)
}

#[test]
fn eight2car_in_order_comes_back_parallel_and_the_hand_parallel_groups_do_not_verify() {
    // The shipped file joins `M4.Connector[0].extend()` and the retract of M6's connector 2
    // it makes safe: if the retract ended first the robot would be in two parts, so its own
    // groups are not a candidate. The output, every `&` of it safe, is still faster.
    let input = sequential_eight2car();
    let out = parallelise(&input.display().to_string(), &[]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let (before, after) = critical_paths(&text(&out.stderr));
    assert!(after < before, "{after} ms, in order {before} ms");
    let shipped = parallelise("robots/atron/examples/eight2car.dr", &[]);
    assert_eq!(shipped.status.code(), Some(0), "{}", text(&shipped.stderr));
    let (hand, _) = critical_paths(&text(&shipped.stderr));
    assert!(after <= hand, "{after} ms, the shipped file {hand} ms");
    let notes = text(&shipped.stdout);
    assert!(
        notes.contains(
            "the input's own groups do not verify (forwards, `M4.Connector[0].extend()` and \
             `M6.Connector[2].retract()` are not independent: if `M6.Connector[2].retract()` \
             ends first: the robot is now in two parts"
        ),
        "{notes}"
    );
    insta::assert_snapshot!("eight2car_parallel", text(&out.stdout));
}

/// `dynarole ARGS` (a `check`) accepts the file with no warning.
fn assert_checks_clean(args: &[&str]) {
    let check = dynarole(args);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stderr));
    assert!(
        !text(&check.stderr).contains("warning"),
        "{}",
        text(&check.stderr)
    );
}

#[test]
fn the_output_checks_clean_forwards_and_its_reverse_from_the_end() {
    let input = sequential_eight2car();
    let output = scratch("eight2car_parallel.dr", "");
    let out = parallelise(
        &input.display().to_string(),
        &["--name", "fast", "-o", &output.display().to_string()],
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let output_path = output.display().to_string();
    assert_checks_clean(&[
        "check",
        &output_path,
        "--from",
        "robots/atron/examples/eight.json",
    ]);
    let replay = dynarole(&[
        "replay",
        &output_path,
        "--sequence",
        "fast",
        "--from",
        "robots/atron/examples/eight.json",
        "--expect",
        "robots/atron/examples/car.json",
    ]);
    assert_eq!(replay.status.code(), Some(0), "{}", text(&replay.stdout));
    let reversed = dynarole(&["reverse", &output_path, "fast", "--name", "back"]);
    assert_eq!(
        reversed.status.code(),
        Some(0),
        "{}",
        text(&reversed.stderr)
    );
    let back = scratch("eight2car_parallel_back.dr", &text(&reversed.stdout));
    assert_checks_clean(&[
        "check",
        &back.display().to_string(),
        "--from",
        "robots/atron/examples/car.json",
    ]);
}

#[test]
fn the_paper_protocol_gets_flat_groups_and_fig5_keeps_its_turns_in_order() {
    let output = scratch("fig5_paper.dr", "");
    let out = parallelise(
        "robots/atron/examples/fig5.dr",
        &["--protocol", "paper", "-o", &output.display().to_string()],
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let written = std::fs::read_to_string(&output).expect("output");
    let code: String = written.lines().filter(|l| !l.starts_with("//")).collect();
    assert_eq!(code.matches('{').count(), 1, "no blocks: {written}");
    // M0's turn (which sweeps M6 near M5 if M1 turns first) ends its group.
    let turn = written
        .lines()
        .find(|l| !l.starts_with("//") && l.contains("M0.Joint.rotateFromToBy(0, 324"))
        .expect("M0's turn");
    assert!(turn.trim_end().ends_with(';'), "{written}");
    let output_path = output.display().to_string();
    assert_checks_clean(&[
        "check",
        "--protocol",
        "paper",
        &output_path,
        "--from",
        "robots/atron/examples/eight.json",
    ]);
}

#[test]
fn bad_inputs_get_a_clear_error_and_the_usual_exit_codes() {
    // Usage: a missing option, an option value that is not a name.
    let out = dynarole(&[
        "parallelise",
        "robots/atron/examples/eight2car.dr",
        "--sequence",
        "x",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let out = parallelise("robots/atron/examples/eight2car.dr", &["--name", "2fast"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("`2fast`"),
        "{}",
        text(&out.stderr)
    );
    // Bad input: no such sequence, a missing file.
    let out = dynarole(&[
        "parallelise",
        "robots/atron/examples/eight2car.dr",
        "--sequence",
        "nope",
        "--from",
        "robots/atron/examples/eight.json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("no sequence `nope` in robots/atron/examples/eight2car.dr"));
    let out = parallelise("robots/atron/examples/missing.dr", &[]);
    assert_eq!(out.status.code(), Some(1));
    // Nothing to do, a configuration of another robot.
    let empty = scratch("empty.dr", "robot atron;\nsequence e {\n}\n");
    let empty = empty.display().to_string();
    let out = dynarole(&[
        "parallelise",
        &empty,
        "--sequence",
        "e",
        "--from",
        "robots/atron/examples/eight.json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("nothing to parallelise"));
    let out = dynarole(&[
        "parallelise",
        &empty,
        "--sequence",
        "e",
        "--from",
        "robots/mtran/examples/mtran-snake4.json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("MTRAN"), "{}", text(&out.stderr));
    // A sequence that does not replay from the configuration: its refused step, located.
    let out = dynarole(&[
        "parallelise",
        "robots/atron/examples/eight2car.dr",
        "--sequence",
        "eight2car",
        "--from",
        "robots/atron/examples/car.json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = text(&out.stderr);
    assert!(stderr.contains("eight2car.dr:"), "{stderr}");
    assert!(stderr.contains("does not replay"), "{stderr}");
}

#[test]
fn a_window_checks_fewer_pairs_and_keeps_the_rest_in_order() {
    let input = sequential_eight2car();
    let input = input.display().to_string();
    let full = parallelise(&input, &[]);
    let windowed = parallelise(&input, &["--window", "2"]);
    assert_eq!(
        windowed.status.code(),
        Some(0),
        "{}",
        text(&windowed.stderr)
    );
    let (_, exact) = critical_paths(&text(&full.stderr));
    let (before, narrow) = critical_paths(&text(&windowed.stderr));
    // Narrower is not always longer: the verification's repairs (`docs/parallelise.md`)
    // start from a different graph.
    assert!(
        exact < before && narrow < before,
        "{exact} {narrow} {before}"
    );
    assert!(text(&windowed.stdout).contains("at most 2 apart"));
    let out = parallelise(&input, &["--window", "-1"]);
    assert_eq!(out.status.code(), Some(2));
}

/// The simulated time (ms) at which `sequence` of `file` declares its end on `chain`.
fn completion_ms(file: &str, sequence: &str, chain: &str, seed: &str) -> f64 {
    let out = dynarole(&[
        "simulate",
        file,
        "--sequence",
        sequence,
        "--from",
        chain,
        "--seed",
        seed,
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).expect("a JSON summary");
    summary["completion_ms"]
        .as_f64()
        .expect("a completion time")
}

#[test]
fn the_rotation_experiments_in_order_come_back_as_the_hand_parallel_groups() {
    // Every joint of the chain turned at once: the group check proves it safe for every
    // relative timing, so `parallelise` writes the hand-parallel groups from the `;` form, and
    // its output ends no later in simulation.
    let (file, chain) = (
        "robots/atron/examples/parallel-rotate-10.dr",
        "robots/atron/examples/rotation-chain-10.json",
    );
    for n in [5, 10, 15, 20] {
        let file = format!("robots/atron/examples/parallel-rotate-{n}.dr");
        let chain = format!("robots/atron/examples/rotation-chain-{n}.json");
        assert_checks_clean(&["check", &file, "--from", &chain]);
    }
    let output = scratch("parallel_rotate_10.dr", "");
    let out = dynarole(&[
        "parallelise",
        file,
        "--sequence",
        "rotate_in_order",
        "--from",
        chain,
        "--name",
        "parallel_rotate",
        "-o",
        &output.display().to_string(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let body = |text: &str| -> String {
        let start = text
            .find("sequence parallel_rotate {")
            .expect("the sequence");
        let end = text[start..].find("\n}").expect("its end") + start;
        text[start..end].to_string()
    };
    let written = std::fs::read_to_string(&output).expect("the output");
    let shipped = std::fs::read_to_string(common::repo_root().join(file)).expect("the example");
    assert_eq!(body(&written), body(&shipped));
    let output = output.display().to_string();
    for seed in ["1", "2", "3"] {
        let parallelised = completion_ms(&output, "parallel_rotate", chain, seed);
        let hand = completion_ms(file, "parallel_rotate", chain, seed);
        let in_order = completion_ms(file, "rotate_in_order", chain, seed);
        assert!(
            parallelised <= hand,
            "seed {seed}: {parallelised} ms, by hand {hand} ms"
        );
        assert!(
            parallelised < in_order,
            "seed {seed}: {parallelised} ms, in order {in_order} ms"
        );
    }
}
