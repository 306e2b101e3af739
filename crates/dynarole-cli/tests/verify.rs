//! `dynarole verify` and `compile --target promela` end to end (spin must be installed:
//! `scripts/test` installs it), and the translation of a counterexample back to the source.

use dynarole_verify::{explain, parse_events, Context};
mod common;

use common::{dynarole, repo_root, text};
use std::path::Path;

const LINE: &str = "robots/atron/examples/verify/line3.json";

fn verify(file: &str, extra: &[&str]) -> (Option<i32>, String) {
    let mut args = vec!["verify", file, "--from", LINE];
    args.extend(extra);
    let out = dynarole(&args);
    let all = format!("{}{}", text(&out.stdout), text(&out.stderr));
    (out.status.code(), all)
}

#[test]
fn the_lattice_protocol_is_proved_on_a_line_with_a_reset_and_a_late_packet() {
    let (code, out) = verify(
        "robots/atron/examples/verify/ab_c.dr",
        &["--resets", "1", "--late", "1"],
    );
    assert_eq!(code, Some(0), "{out}");
    assert!(
        out.contains("S1, S2, S3 (safety): verified — exhaustive"),
        "{out}"
    );
    assert!(
        out.contains("L (finishes, weak fairness): verified — exhaustive"),
        "{out}"
    );
    assert!(out.contains("at most 1 reset(s)"), "{out}");
}

/// Two statements of one module in one group, which the lattice runtime starts as one batch
/// and completes together: proved with a reset (and a late packet), without NV, and module by
/// module.
#[test]
fn a_batch_of_one_modules_statements_is_proved() {
    let runs: [&[&str]; 3] = [
        &["--resets", "1", "--late", "1"],
        &["--resets", "1", "--no-nv"],
        &["--method", "compositional", "--resets", "1"],
    ];
    for extra in runs {
        let (code, out) = verify("robots/atron/examples/verify/ab_same_c.dr", extra);
        assert_eq!(code, Some(0), "{extra:?}: {out}");
        assert!(
            out.contains("L (finishes, weak fairness): verified"),
            "{out}"
        );
        assert!(out.contains("result: verified"), "{extra:?}: {out}");
    }
}

#[test]
fn every_paper_merge_variant_starts_a_statement_too_early_without_any_loss() {
    for merge in ["printed", "java", "c-port"] {
        let (code, out) = verify(
            "robots/atron/examples/verify/ab_c.dr",
            &["--protocol", "paper", "--merge", merge, "--late", "0"],
        );
        assert_eq!(code, Some(1), "{merge}: {out}");
        assert!(out.contains("S1 violated: M2 started #2"), "{merge}: {out}");
        // The counterexample is the note's: a neighbour's packet at the same state erases the
        // pending state between S and S+1, and nothing is lost or late.
        assert!(!out.contains("earlier packet"), "{merge}: {out}");
        assert!(
            out.contains("robots/atron/examples/verify/ab_c.dr:8:5"),
            "{merge}: {out}"
        );
    }
}

/// The paper's own robot (eight.json, seven modules): the Java merge's race found by the
/// bounded search on the first two groups of eight2car (the whole sequence: the same race,
/// docs/verification.md), and progress reported on stderr while spin works, not on stdout.
#[test]
fn the_paper_protocols_race_is_found_on_the_papers_own_robot() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dynarole"))
        .args([
            "verify",
            "robots/atron/examples/verify/eight2car_start.dr",
            "--from",
            "robots/atron/examples/eight.json",
            "--protocol",
            "paper",
            "--merge",
            "java",
        ])
        .env("DYNAROLE_PROGRESS_SECONDS", "1")
        .current_dir(repo_root())
        .output()
        .expect("the dynarole binary runs");
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stdout.contains("bounded search, runs of at most 50 steps: a violation"),
        "{stdout}"
    );
    assert!(
        stdout.contains("S1 violated: M3 started #2 `M3.Joint.rotateFromToBy(0, 324, false, 150)` (robots/atron/examples/verify/eight2car_start.dr:9:5) before #0 was done"),
        "{stdout}"
    );
    // The race: M0 starts #0 (pending {1}), and a neighbour's copy at state 0 erases it.
    assert!(
        stdout.contains("M0 starts #0 `M0.Connector[0].retract()`"),
        "{stdout}"
    );
    assert!(stdout.contains("pending {1}"), "{stdout}");
    assert!(
        stderr.contains("progress: S1, S2, S3 (safety): compiling the verifier ("),
        "{stderr}"
    );
    assert!(!stdout.contains("progress:"), "{stdout}");
}

/// Without spin, `verify` cannot give a verdict: an error of its own (exit 4), never 1
/// (violated) or 3 (inconclusive).
#[test]
fn a_missing_spin_is_an_internal_failure_not_a_verdict() {
    let empty = std::env::temp_dir().join(format!("dynarole-no-tools-{}", std::process::id()));
    std::fs::create_dir_all(&empty).expect("a scratch directory");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dynarole"))
        .args([
            "verify",
            "robots/atron/examples/verify/ab_c.dr",
            "--from",
            LINE,
        ])
        .env("PATH", &empty)
        .current_dir(repo_root())
        .output()
        .expect("the dynarole binary runs");
    let _ = std::fs::remove_dir_all(&empty);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(4), "{stderr}");
    assert!(stderr.contains("error: spin is not installed"), "{stderr}");
    assert!(!text(&out.stdout).contains("result:"));
}

#[test]
fn the_single_step_handover_repairs_the_c_port_but_not_the_java_merge() {
    let args = [
        "--protocol",
        "paper",
        "--single-step-handover",
        "--late",
        "0",
    ];
    let (code, out) = verify(
        "robots/atron/examples/verify/abc_d_first.dr",
        &[&args[..], &["--merge", "c-port"]].concat(),
    );
    assert_eq!(code, Some(0), "{out}");
    let (code, out) = verify(
        "robots/atron/examples/verify/abc_d_first.dr",
        &[&args[..], &["--merge", "java", "--safety-only"]].concat(),
    );
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("S1 violated"), "{out}");
}

#[test]
fn a_broken_lattice_join_is_caught() {
    let (code, out) = verify(
        "robots/atron/examples/verify/ab_c.dr",
        &["--fault", "join-no-rebase", "--late", "0", "--safety-only"],
    );
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("deliberately broken"), "{out}");
    assert!(out.contains("violated: M1 declared the end"), "{out}");
}

#[test]
fn resetting_the_paper_protocols_first_module_re_issues_its_first_operation() {
    let (code, out) = verify(
        "robots/atron/examples/verify/abc_d_first.dr",
        &[
            "--protocol",
            "paper",
            "--single-step-handover",
            "--resets",
            "1",
            "--late",
            "0",
            "--safety-only",
        ],
    );
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("S2 violated: M0 issued #0"), "{out}");
    assert!(out.contains("M0 resets"), "{out}");
}

#[test]
fn compile_to_promela_writes_the_model_and_needs_a_configuration() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("promela-model");
    let dir_text = dir.to_str().expect("utf-8 path");
    let out = dynarole(&[
        "compile",
        "robots/atron/examples/verify/a_bc_d.dr",
        "--target",
        "promela",
        "--from",
        LINE,
        "--protocol",
        "paper",
        "-o",
        dir_text,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let model = std::fs::read_to_string(dir.join("model.pml")).expect("model.pml");
    for needle in [
        "proctype module_0()",
        "proctype link_0_1()",
        "inline merge(m)",
        "ltl finishes",
        "#define MERGE 2",
    ] {
        assert!(model.contains(needle), "{needle}");
    }
    let out = dynarole(&[
        "compile",
        "robots/atron/examples/verify/a_bc_d.dr",
        "--target",
        "promela",
        "-o",
        dir_text,
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
}

/// What `spin -T -t` printed for the paper protocol's `A & B; C;` (Java merge): the replay of
/// a trail, as `dynarole verify` reads it. Kept here so that the translation is tested without
/// depending on the exact trail a given version of spin finds.
const TRAIL: &str = "\
ltl finishes: <> ([] ((((g_state[0]==254)) && ((g_state[1]==254))) && ((g_state[2]==254))))
@issue 0 0 0
@copy 0 1 0 1 0 0 0 0
@deliver 1 0 0 0 0 0 0 0 0
@copy 0 0 0 0 0 0 0 0
@copy 0 4 1 0 0 0 0 0
@capture 0 0 1
@deliver 0 1 4 1 0 0 0 0 0
@copy 1 4 1 0 0 0 0 0
@issue 1 1 0
@copy 1 4 1 0 0 0 0 0
@done 1 1
@copy 1 6 2 0 0 0 0 0
@late 0 0 1
@deliver 0 1 4 1 0 0 0 0 0
@copy 1 6 2 0 0 0 0 0
@deliver 1 2 6 2 0 0 0 0 0
@copy 2 6 2 0 0 0 0 0
@issue 2 2 0
@violation S1 2 2
spin: trail ends after 12 steps
";

/// `ab_c.dr`'s source and IR.
fn ab_c() -> (String, dynarole_core::lower::Ir) {
    let source = std::fs::read_to_string(repo_root().join(AB_C)).expect("source");
    let parsed = dynarole_core::parse(&source);
    let registry = dynarole_robots::plugins();
    let (program, diagnostics) = dynarole_core::driver::analyze_all(&parsed, &registry);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let program = program.expect("checked");
    let plan = program.expand("ab_c").expect("sequence");
    let ir = dynarole_core::driver::lower(&program, &[plan], dynarole_core::driver::Shape::Nested)
        .expect("lowered");
    (source, ir)
}

const AB_C: &str = "robots/atron/examples/verify/ab_c.dr";

#[test]
fn a_counterexample_is_told_in_the_sources_terms() {
    let path = AB_C;
    let (source, ir) = ab_c();
    let units = ir.paper_layout().expect("layout");
    let paper_states: Vec<(u8, Vec<usize>)> = units
        .iter()
        .map(|u| (u.first_state, u.statements.clone()))
        .collect();
    let names: Vec<String> = ["M0", "M1", "M2"].map(String::from).to_vec();
    let events = parse_events(TRAIL);
    let told = explain(
        &events,
        &Context {
            ir: &ir,
            module_names: &names,
            paper_states: &paper_states,
            path,
            source: &source,
        },
    );
    insta::assert_snapshot!(told);
}

/// A compositional model's trail (M1 checked, the join without re-basing): the other modules
/// only start and record, and M1 hears packets from nobody in particular.
const COMPOSITIONAL_TRAIL: &str = "\
ltl finishes: <> ([] ((epoch[1]>=1)))
@issue 0 0 0
@done 0 0
@record 0 0
@issue 1 1 0
@copy 1 0 0 0
@done 1 1
@complete 1 1
@record 1 1
@copy 1 0 0 2
@hear 1 0 1 0
@copy 1 0 1 2
@violation G3 1 1
spin: trail ends after 9 steps
";

#[test]
fn a_compositional_counterexample_is_told_in_the_sources_terms() {
    let (source, ir) = ab_c();
    let names: Vec<String> = ["M0", "M1", "M2"].map(String::from).to_vec();
    let told = explain(
        &parse_events(COMPOSITIONAL_TRAIL),
        &Context {
            ir: &ir,
            module_names: &names,
            paper_states: &[],
            path: AB_C,
            source: &source,
        },
    );
    assert!(told.contains("G3 violated"), "{told}");
    insta::assert_snapshot!(told);
}

#[test]
fn the_compositional_model_proves_the_lattice_protocol_module_by_module() {
    let (code, out) = verify(AB_C, &["--method", "compositional", "--resets", "1"]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("method: compositional"), "{out}");
    assert!(
        out.contains("any number of packets delivered late"),
        "{out}"
    );
    for module in ["M0", "M1", "M2"] {
        assert!(
            out.contains(&format!(
                "{module}: S1, S2, S3, G1-G4 (safety): verified — exhaustive"
            )),
            "{out}"
        );
        assert!(
            out.contains(&format!(
                "{module}: L (finishes, weak fairness): verified — exhaustive"
            )),
            "{out}"
        );
    }
}

#[test]
fn the_compositional_model_catches_a_broken_join() {
    let (code, out) = verify(
        AB_C,
        &[
            "--method",
            "compositional",
            "--fault",
            "join-no-rebase",
            "--safety-only",
        ],
    );
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("M1: S1, S2, S3, G1-G4 (safety): VIOLATED"),
        "{out}"
    );
    assert!(out.contains("may be spurious"), "{out}");
    // It stops at the first module with a violation.
    assert!(!out.contains("M2: S1"), "{out}");
}

#[test]
fn eight2car_is_proved_safe_with_a_reset_module_by_module() {
    let out = dynarole(&[
        "verify",
        "robots/atron/examples/eight2car.dr",
        "--sequence",
        "eight2car",
        "--from",
        "robots/atron/examples/eight.json",
        "--resets",
        "1",
        "--safety-only",
    ]);
    let all = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{all}{}", text(&out.stderr));
    // Seven modules: `auto` chooses the compositional method.
    assert!(all.contains("method: compositional"), "{all}");
    assert_eq!(
        all.matches("(safety): verified — exhaustive").count(),
        7,
        "{all}"
    );
}

/// `compile --target promela --method compositional` of `ab_c` into a fresh test directory.
fn compositional_models(name: &str) -> std::path::PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let out = dynarole(&[
        "compile",
        AB_C,
        "--target",
        "promela",
        "--from",
        LINE,
        "--method",
        "compositional",
        "-o",
        dir.to_str().expect("utf-8 path"),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    dir
}

#[test]
fn compile_to_promela_writes_one_compositional_model_per_module() {
    let dir = compositional_models("promela-compositional");
    for module in ["M0", "M1", "M2"] {
        let model = std::fs::read_to_string(dir.join(format!("model-{module}.pml")))
            .expect("one model per module");
        assert!(model.contains("inline guarantee(m)"), "{module}");
    }
}

#[test]
fn the_liveness_check_fails_when_the_end_is_never_surely_carried() {
    // M0's model without the fair delivery of the end: only the unfair `news` can tell M0,
    // so a run in which it never does is fair, and L must fail.
    let dir = compositional_models("compositional-no-end");
    let model = std::fs::read_to_string(dir.join("model-M0.pml")).expect("model");
    let fair_end = "    :: d_step { t_end && epoch[0] < N_EPOCHS -> hear(1, 0, 0) } /* the end */";
    assert!(model.contains(fair_end), "{model}");
    let check = dir.join("no-end");
    std::fs::create_dir_all(&check).expect("dir");
    std::fs::write(
        check.join("model.pml"),
        model.replace(fair_end, "    :: false -> skip"),
    )
    .expect("write");
    let limits = dynarole_verify::spin::Limits {
        memory_mb: 1024,
        time_s: 300,
        bitstate: false,
        shortest: false,
        depth: None,
    };
    let result = dynarole_verify::spin::run_check(
        &check,
        dynarole_verify::spin::Check::Liveness,
        limits,
        "L",
    )
    .expect("pan runs");
    assert!(result.errors > 0, "{result:?}");
    // The unchanged model proves L.
    std::fs::write(check.join("model.pml"), &model).expect("write");
    let result = dynarole_verify::spin::run_check(
        &check,
        dynarole_verify::spin::Check::Liveness,
        limits,
        "L",
    )
    .expect("pan runs");
    assert!(result.errors == 0 && result.complete(), "{result:?}");
}

#[test]
fn the_compositional_method_refuses_what_it_does_not_model() {
    for extra in [
        &["--protocol", "paper"][..],
        &["--no-nv"][..],
        &["--epochs", "2"][..],
    ] {
        let (code, out) = verify(AB_C, &[&["--method", "compositional"][..], extra].concat());
        assert_eq!(code, Some(2), "{extra:?}: {out}");
        assert!(out.contains("use --method full"), "{extra:?}: {out}");
    }
}
