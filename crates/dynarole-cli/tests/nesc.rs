//! `compile --target nesc` compiled for real: nesC 1.4.0 (built by `scripts/ensure-nesc`)
//! against the stand-ins of `runtime/nesc/`, for the host and for the ATmega128, and the host
//! build run in the C harness next to the C build, which must do the same things in the same
//! order.
mod common;

use common::{dynarole, nescc_dir, repo_root, text};
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("nesc")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// `dynarole compile FILE --sequence SEQ --target nesc EXTRA -o DIR`.
fn compile_nesc(file: &str, sequence: &str, extra: &[&str], dir: &Path) {
    let dir_arg = dir.to_string_lossy().into_owned();
    let mut args = vec!["compile", file, "--sequence", sequence, "--target", "nesc"];
    args.extend(extra);
    args.extend(["-o", dir_arg.as_str()]);
    let out = dynarole(&args);
    assert!(out.status.success(), "{}", text(&out.stderr));
}

/// `make -C runtime/nesc OUT=DIR GOALS...` with nescc on the PATH.
fn nesc_make(nescc: &Path, dir: &Path, goals: &[&str], ids: &str) -> Output {
    nesc_make_with(nescc, dir, goals, &[&format!("IDS={ids}")])
}

/// The same with the make variables `vars` (`NAME=VALUE`).
fn nesc_make_with(nescc: &Path, dir: &Path, goals: &[&str], vars: &[&str]) -> Output {
    let path = std::env::var_os("PATH").unwrap_or_default();
    let path = std::env::join_paths(
        std::iter::once(nescc.to_path_buf()).chain(std::env::split_paths(&path)),
    )
    .expect("PATH");
    let mut out_arg = OsString::from("OUT=");
    out_arg.push(dir);
    let out = Command::new("make")
        .arg("-s")
        .arg("-C")
        .arg(repo_root().join("runtime/nesc"))
        .arg(out_arg)
        .args(vars)
        .args(goals)
        .env("PATH", path)
        .output()
        .expect("make runs");
    assert!(
        out.status.success(),
        "make {goals:?} for {}:\n{}{}",
        dir.display(),
        text(&out.stdout),
        text(&out.stderr)
    );
    out
}

/// The C build of the same directory in the same harness (as the codegen tests build it).
fn c_harness(dir: &Path, ids: &str) -> String {
    let mut sources: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "c"))
        .collect();
    sources.sort();
    let binary = dir.join("c-harness");
    let status = Command::new("cc")
        // The runtime's strict flags (runtime/dr_warn.mk), as the codegen tests build it.
        .args(dynarole_codegen::warning_flags())
        .arg("-I")
        .arg(dir)
        .args(&sources)
        .arg(repo_root().join("runtime/harness/harness.c"))
        .arg("-o")
        .arg(&binary)
        .status()
        .expect("cc runs");
    assert!(status.success(), "the C harness does not build");
    let out = Command::new(&binary)
        .args(ids.split(' '))
        .output()
        .expect("runs");
    assert!(out.status.success(), "C build: {}", text(&out.stdout));
    text(&out.stdout)
}

/// The harness's events without their times: which statement started or finished, in order.
fn events(trace: &str) -> Vec<&str> {
    trace
        .lines()
        .filter_map(|l| l.split_once(" ms  ").map(|(_, event)| event))
        .collect()
}

/// Each table is in the AVR build's program memory (`.progmem*`), not copied to RAM.
fn tables_in_flash(dir: &Path, name: &str, tables: &[&str]) {
    let out = Command::new("avr-objdump")
        .arg("-t")
        .arg(dir.join("build/nesc-atmega128/dr_program.o"))
        .output()
        .expect("avr-objdump runs");
    let symbols = text(&out.stdout);
    for table in tables {
        let line = symbols
            .lines()
            .find(|l| l.ends_with(&format!(" {table}")))
            .unwrap_or_else(|| panic!("{name}: no {table} in\n{symbols}"));
        assert!(line.contains(" .progmem"), "{name}: {line}");
    }
}

struct Case {
    name: &'static str,
    file: &'static str,
    sequence: &'static str,
    extra: &'static [&'static str],
    /// Module IDs for the harness; None: the protocol needs connectors (token), compile only.
    ids: Option<&'static str>,
    /// Constant tables of the program that must stay in the ATmega128's flash.
    tables: &'static [&'static str],
}

const LATTICE_TABLES: &[&str] = &["dr_program_statements", "dr_program_deps"];

const CASES: [Case; 5] = [
    Case {
        name: "eight2car-lattice",
        file: "robots/atron/examples/eight2car.dr",
        sequence: "eight2car",
        extra: &[],
        ids: Some("0 1 2 3 4 5 6"),
        tables: LATTICE_TABLES,
    },
    Case {
        name: "eight2car-lattice-no-nv",
        file: "robots/atron/examples/eight2car.dr",
        sequence: "eight2car",
        extra: &["--no-nv"],
        ids: Some("0 1 2 3 4 5 6"),
        tables: LATTICE_TABLES,
    },
    Case {
        name: "eight2car-paper",
        file: "robots/atron/examples/eight2car.dr",
        sequence: "eight2car",
        extra: &["--protocol", "paper"],
        ids: Some("0 1 2 3 4 5 6"),
        tables: &["dr_args_0", "dr_args_24"],
    },
    Case {
        name: "eight2car-token",
        file: "robots/atron/examples/eight2car.dr",
        sequence: "eight2car",
        extra: &[
            "--protocol",
            "token",
            "--from",
            "robots/atron/examples/eight.json",
        ],
        ids: None,
        tables: &["dr_program_statements", "dr_program_hops"],
    },
    Case {
        name: "mtran-left2right-lattice",
        file: "robots/mtran/examples/move_module.dr",
        sequence: "left2right",
        extra: &[],
        ids: Some("10 11 12 13"),
        tables: LATTICE_TABLES,
    },
];

#[test]
fn the_nesc_component_compiles_for_host_and_atmega128_and_runs_like_the_c_build() {
    let Some(nescc) = nescc_dir() else { return };
    for case in &CASES {
        let dir = out_dir(case.name);
        compile_nesc(case.file, case.sequence, case.extra, &dir);
        let avr = nesc_make(&nescc, &dir, &["host", "avr"], "0");
        assert!(
            text(&avr.stdout).contains("build/nesc-atmega128/app.o"),
            "{}: {}",
            case.name,
            text(&avr.stdout)
        );
        tables_in_flash(&dir, case.name, case.tables);
        let Some(ids) = case.ids else { continue };
        let nesc = text(&nesc_make(&nescc, &dir, &["harness"], ids).stdout);
        let c = c_harness(&dir, ids);
        let summary = nesc.lines().last().unwrap_or_default();
        assert!(summary.starts_with("finished"), "{}: {summary}", case.name);
        assert!(
            summary.contains(", 0 violations, 0 re-issued"),
            "{}: {summary}",
            case.name
        );
        assert!(!events(&nesc).is_empty(), "{}: no events", case.name);
        assert_eq!(
            events(&nesc),
            events(&c),
            "{}: the nesC build must start and finish the statements as the C build does",
            case.name
        );
    }
}

#[test]
fn the_nesc_makefile_names_a_missing_output_directory() {
    let Some(nescc) = nescc_dir() else { return };
    let dir = out_dir("not-compiled");
    std::fs::create_dir_all(&dir).expect("dir");
    let mut out_arg = OsString::from("OUT=");
    out_arg.push(&dir);
    let out = Command::new("make")
        .arg("-s")
        .arg("-C")
        .arg(repo_root().join("runtime/nesc"))
        .arg(out_arg)
        .arg("host")
        .env("NESCC", nescc.join("nescc"))
        .output()
        .expect("make runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("compiled with --target nesc"),
        "{}",
        text(&out.stderr)
    );
}

/// The nesC component passes the harness's failed operations to the runtime: statement 3 of
/// eight2car (M4's first turn) fails twice, the default policy retries it and the sequence
/// ends with every statement done once.
#[test]
fn the_nesc_component_retries_a_failed_operation_like_the_c_build() {
    let Some(nescc) = nescc_dir() else { return };
    let dir = out_dir("eight2car-lattice-failing");
    compile_nesc("robots/atron/examples/eight2car.dr", "eight2car", &[], &dir);
    let vars = ["IDS=0 1 2 3 4 5 6", "FAULTS=-f 3:2"];
    let nesc = text(&nesc_make_with(&nescc, &dir, &["harness"], &vars).stdout);
    let summary = nesc.lines().last().unwrap_or_default();
    assert!(summary.starts_with("finished"), "{summary}");
    assert!(
        summary.contains("25 of 25 statements done, 0 violations"),
        "{summary}"
    );
    assert!(summary.ends_with("2 attempts failed"), "{summary}");
    assert_eq!(nesc.matches(" failed ").count(), 2, "{nesc}");
}
