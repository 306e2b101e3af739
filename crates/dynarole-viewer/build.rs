//! Bundles the front end (`web/`) at build time: `npm ci` of the pinned lockfile into
//! OUT_DIR (once per lockfile), then esbuild into `OUT_DIR/viewer.js`, which `lib.rs` embeds.
//! Needs node and npm; nothing is fetched at run time.

use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    if let Err(message) = bundle() {
        eprintln!("error: building the viewer's front end: {message}");
        std::process::exit(1);
    }
}

fn bundle() -> Result<(), String> {
    let web = PathBuf::from(env("CARGO_MANIFEST_DIR")?).join("web");
    let out = PathBuf::from(env("OUT_DIR")?);
    for watched in ["src", "package.json", "package-lock.json"] {
        println!("cargo:rerun-if-changed={}", web.join(watched).display());
    }
    let npm_dir = out.join("npm");
    install(&web, &npm_dir)?;
    let esbuild = npm_dir.join("node_modules/esbuild/bin/esbuild");
    let status = Command::new("node")
        .arg(&esbuild)
        .arg(web.join("src/main.js"))
        .args([
            "--bundle",
            "--minify",
            "--format=iife",
            "--target=es2020",
            "--log-level=warning",
        ])
        .arg(format!("--outfile={}", out.join("viewer.js").display()))
        .env("NODE_PATH", npm_dir.join("node_modules"))
        .status()
        .map_err(|e| format!("cannot run node ({e}): install Node.js 18 or later and npm"))?;
    if !status.success() {
        return Err(format!("esbuild failed ({status})"));
    }
    Ok(())
}

/// `npm ci` of the lockfile into `dir`, skipped when that lockfile is installed already.
fn install(web: &Path, dir: &Path) -> Result<(), String> {
    let lock = read(&web.join("package-lock.json"))?;
    let stamp = dir.join("installed-lock.json");
    if std::fs::read_to_string(&stamp).ok().as_deref() == Some(lock.as_str()) {
        return Ok(());
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for file in ["package.json", "package-lock.json"] {
        std::fs::copy(web.join(file), dir.join(file)).map_err(|e| format!("{file}: {e}"))?;
    }
    let status = Command::new("npm")
        .args([
            "ci",
            "--ignore-scripts",
            "--no-audit",
            "--no-fund",
            "--loglevel=error",
        ])
        .current_dir(dir)
        .status()
        .map_err(|e| format!("cannot run npm ({e}): install Node.js 18 or later and npm"))?;
    if !status.success() {
        return Err(format!(
            "`npm ci` failed ({status}); it needs the npm registry once"
        ));
    }
    std::fs::write(&stamp, lock).map_err(|e| format!("{}: {e}", stamp.display()))
}

fn read(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
}

fn env(name: &str) -> Result<String, String> {
    std::env::var(name).map_err(|_| format!("{name} is not set (not run by cargo?)"))
}
