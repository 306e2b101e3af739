//! Shared by the CLI's integration tests: run the built `dynarole` binary from the repository
//! root and read its output as text.
#![allow(dead_code)]

pub mod tree;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn dynarole(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dynarole"))
        .args(args)
        .current_dir(repo_root())
        .output()
        .expect("the dynarole binary runs")
}

pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A path as a command-line argument.
pub fn arg(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// Runs `dynarole args`, asserting its exit code; its standard output.
pub fn ok(args: &[&str], code: i32) -> String {
    let out = dynarole(args);
    assert_eq!(
        out.status.code(),
        Some(code),
        "dynarole {}\n{}{}",
        args.join(" "),
        text(&out.stdout),
        text(&out.stderr)
    );
    text(&out.stdout)
}

/// `dynarole simulate PROGRAM --from FROM --expect EXPECT EXTRA...`, which must succeed; its
/// standard output.
pub fn simulate(program: &Path, from: &Path, expect: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "simulate",
        arg(program),
        "--from",
        arg(from),
        "--expect",
        arg(expect),
    ];
    args.extend_from_slice(extra);
    ok(&args, 0)
}

/// The directory of nescc 1.4.0, or None (with the reason printed) when this machine cannot
/// install it (`scripts/ensure-nesc` exits 77); a failed build is a failure, not a skip.
pub fn nescc_dir() -> Option<PathBuf> {
    let out = Command::new(repo_root().join("scripts/ensure-nesc"))
        .output()
        .expect("scripts/ensure-nesc runs");
    match out.status.code() {
        Some(0) => Some(PathBuf::from(text(&out.stdout).trim())),
        Some(77) => {
            eprintln!("skipped: {}", text(&out.stderr));
            None
        }
        _ => panic!("scripts/ensure-nesc failed: {}", text(&out.stderr)),
    }
}
