//! Only the CLI draws on the terminal: the crates below it report progress to what they are
//! handed (`dynarole_campaign::Progress`, `dynarole_verify::Observer`), so none depends on
//! indicatif and none writes to stderr outside its tests (checked on `cargo metadata` and on
//! the sources).

use serde_json::Value;
use std::path::{Path, PathBuf};

/// The crate that owns the terminal.
const CLI: &str = "dynarole-cli";

/// What writes to stderr in Rust source.
const STDERR_WRITES: &[&str] = &["eprintln!", "eprint!", "io::stderr()"];

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn metadata() -> Value {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = std::process::Command::new(cargo)
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(workspace())
        .output()
        .expect("cargo metadata runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).expect("cargo metadata's JSON")
}

/// The workspace crates other than the CLI that depend on indicatif (dev-dependencies aside).
fn indicatif_users(metadata: &Value) -> Vec<String> {
    let packages = metadata["packages"].as_array().expect("packages");
    packages
        .iter()
        .filter(|p| p["name"].as_str() != Some(CLI))
        .filter(|p| {
            p["dependencies"].as_array().is_some_and(|deps| {
                deps.iter().any(|d| {
                    d["name"].as_str() == Some("indicatif") && d["kind"].as_str() != Some("dev")
                })
            })
        })
        .filter_map(|p| {
            p["name"]
                .as_str()
                .map(|n| format!("{n} depends on indicatif"))
        })
        .collect()
}

/// The lines of `text` that write to stderr, comments and the `#[cfg(test)]` module (last in
/// a file, after its helpers) left out.
fn stderr_writes(text: &str) -> Vec<usize> {
    text.lines()
        .take_while(|line| line.trim() != "#[cfg(test)]")
        .enumerate()
        .filter(|(_, line)| !line.trim_start().starts_with("//"))
        .filter(|(_, line)| STDERR_WRITES.iter().any(|w| line.contains(w)))
        .map(|(k, _)| k + 1)
        .collect()
}

/// Every `.rs` file under `dir`, as its path and text.
fn rust_files(dir: &Path) -> Vec<(PathBuf, String)> {
    let mut out = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(d) = pending.pop() {
        for entry in std::fs::read_dir(&d).expect("a source folder").flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).expect("a source file");
                out.push((path, text));
            }
        }
    }
    out
}

/// The lines below the CLI that write to stderr, as `crate/src/FILE:LINE`.
fn stderr_writers() -> Vec<String> {
    let crates = workspace().join("crates");
    let mut found = Vec::new();
    for entry in std::fs::read_dir(&crates).expect("crates/").flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name == CLI {
            continue;
        }
        for (path, text) in rust_files(&entry.path().join("src")) {
            let shown = path
                .strip_prefix(&crates)
                .unwrap_or(&path)
                .display()
                .to_string();
            found.extend(stderr_writes(&text).iter().map(|k| format!("{shown}:{k}")));
        }
    }
    found.sort();
    found
}

#[test]
fn no_crate_below_the_cli_draws_on_the_terminal() {
    let mut problems = indicatif_users(&metadata());
    problems.extend(
        stderr_writers()
            .into_iter()
            .map(|at| format!("{at} writes to stderr")),
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn a_write_to_stderr_is_found_outside_comments_and_tests() {
    let text = "fn f() {\n    eprintln!(\"x\");\n    // eprint!(\"y\")\n    let _ = std::io::stderr();\n}\n#[cfg(test)]\nmod tests {\n    fn g() { eprint!(\"z\"); }\n}\n";
    assert_eq!(stderr_writes(text), vec![2, 4]);
}
