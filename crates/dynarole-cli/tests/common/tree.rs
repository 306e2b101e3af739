//! The repository's tree as the architecture tests read it: the workspace root, the files
//! under a folder (one walk, build outputs skipped) and `cargo metadata`.

use serde_json::Value;
use std::path::{Path, PathBuf};

/// The repository's root (`super::repo_root`, named as the architecture tests say it).
pub fn workspace() -> PathBuf {
    super::repo_root()
}

/// Every `.rs` file under `dir`, as (path relative to `dir` with `/`, text).
pub fn sources(dir: &Path) -> Vec<(String, String)> {
    files_under(dir, dir, &|name| name.ends_with(".rs"))
}

/// The workspace's packages and their dependencies (`cargo metadata`, no network).
pub fn metadata() -> Value {
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

/// Every file under `dir` whose name `wanted` accepts, as (path relative to the workspace with
/// `/`, text), skipping build outputs (`build/`, `target/`: copies and generated programs,
/// not sources), `node_modules/` and `.git/`.
pub fn tree_files(dir: &Path, wanted: &dyn Fn(&str) -> bool) -> Vec<(String, String)> {
    files_under(dir, &workspace(), wanted)
}

/// The one walk of the tree behind [`sources`] and [`tree_files`]: the files under `dir` whose
/// names `wanted` takes, as (path relative to `root` with `/`, text), build outputs skipped.
pub fn files_under(
    dir: &Path,
    root: &Path,
    wanted: &dyn Fn(&str) -> bool,
) -> Vec<(String, String)> {
    const SKIPPED: [&str; 4] = ["build", "target", "node_modules", ".git"];
    let mut out = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(d) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let name = entry.file_name().to_string_lossy().into_owned();
            if path.is_dir() {
                if !SKIPPED.contains(&name.as_str()) {
                    pending.push(path);
                }
            } else if wanted(&name) {
                let rel = path.strip_prefix(root).unwrap_or(&path);
                let rel = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy())
                    .collect::<Vec<_>>()
                    .join("/");
                let Ok(text) = std::fs::read_to_string(&path) else {
                    continue;
                };
                out.push((rel, text));
            }
        }
    }
    out.sort();
    out
}
