//! Shared by the CLI's integration tests: run the built `dynarole` binary from the repository
//! root and read its output as text.
#![allow(dead_code)]

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
