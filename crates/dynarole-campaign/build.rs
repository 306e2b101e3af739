//! The source a build of dynarole was made from, as one hash (`DYNAROLE_SOURCE`): every
//! crate's and robot folder's `src/`, manifest and build script (and a robot's plugin), the C
//! runtime and `Cargo.lock`, read in path
//! order (tests, examples and docs change no result and are left out). A campaign records it with the version (`inputs.rs`), so that rows computed by two
//! builds of one version from different code are never merged or resumed together. Debug and
//! release builds of one source, on any machine, give the same hash.

use std::path::{Path, PathBuf};

/// Folders that hold no source (the runtime's build outputs).
const SKIPPED: [&str; 2] = ["build", "target"];

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default());
    let root = manifest.join("../..");
    let mut files = Vec::new();
    let mut watched = vec![root.join("runtime"), root.join("Cargo.lock")];
    let crates = std::fs::read_dir(root.join("crates"))
        .into_iter()
        .flatten()
        .flatten();
    for krate in crates.map(|e| e.path()).filter(|p| p.is_dir()) {
        watched.extend(["src", "Cargo.toml", "build.rs"].map(|part| krate.join(part)));
    }
    // Each robot folder is a crate too, with its plugin (`NAME.robot.toml`) beside the manifest.
    let robots = std::fs::read_dir(root.join("robots"))
        .into_iter()
        .flatten()
        .flatten();
    for robot in robots.map(|e| e.path()).filter(|p| p.is_dir()) {
        watched.extend(["src", "Cargo.toml", "build.rs"].map(|part| robot.join(part)));
        let plugins = std::fs::read_dir(&robot).into_iter().flatten().flatten();
        watched.extend(
            (plugins.map(|e| e.path())).filter(|p| p.to_string_lossy().ends_with(".robot.toml")),
        );
    }
    for path in &watched {
        println!("cargo:rerun-if-changed={}", path.display());
        if path.is_dir() {
            collect(path, &mut files);
        } else if path.is_file() {
            files.push(path.clone());
        }
    }
    files.sort();
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut feed = |bytes: &[u8]| {
        for b in bytes {
            hash ^= u64::from(*b);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    };
    for path in &files {
        // Paths relative to the root, with `/`: the same hash on every machine.
        let relative = path.strip_prefix(&root).unwrap_or(path);
        let name: Vec<String> = (relative.components())
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        feed(name.join("/").as_bytes());
        feed(&[0]);
        feed(&std::fs::read(path).unwrap_or_default());
        feed(&[0]);
    }
    // No workspace around the crate (it was built alone): said as such, never a silent match.
    let source = if files.len() > 1 {
        format!("{hash:016x}")
    } else {
        "unknown-source".to_string()
    };
    println!("cargo:rustc-env=DYNAROLE_SOURCE={source}");
}

/// The source files under `dir`: Rust, C and headers, Promela, nesC, Make, TOML (plugins).
fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        if path.is_dir() {
            if !SKIPPED.contains(&name.as_str()) {
                collect(&path, out);
            }
        } else if is_source(&name) {
            out.push(path);
        }
    }
}

fn is_source(name: &str) -> bool {
    const ENDINGS: [&str; 7] = [".rs", ".toml", ".c", ".h", ".pml", ".nc", ".mk"];
    name == "Makefile" || ENDINGS.iter().any(|e| name.ends_with(e))
}
