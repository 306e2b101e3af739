//! Only the CLI draws on the terminal: the crates below it report progress to what they are
//! handed (`dynarole_campaign::Progress`, `dynarole_verify::Observer`), so none depends on
//! indicatif and none writes to stderr outside its tests (checked on `cargo metadata` and on
//! the sources).

mod common;

use common::tree::{metadata, tree_files, workspace};
use serde_json::Value;

/// The crate that owns the terminal.
const CLI: &str = "dynarole-cli";

/// What writes to stderr in Rust source.
const STDERR_WRITES: &[&str] = &["eprintln!", "eprint!", "io::stderr()"];

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

/// The lines below the CLI that write to stderr, as `crates/NAME/src/FILE:LINE`.
fn stderr_writers() -> Vec<String> {
    let mut found = Vec::new();
    for (path, text) in tree_files(&workspace().join("crates"), &|n| n.ends_with(".rs")) {
        let below_the_cli = !path.starts_with(&format!("crates/{CLI}/"));
        if below_the_cli && path.contains("/src/") {
            found.extend(stderr_writes(&text).iter().map(|k| format!("{path}:{k}")));
        }
    }
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
