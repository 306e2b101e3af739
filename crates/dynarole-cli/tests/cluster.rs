//! `dynarole campaign` on a cluster, end to end through the binary: shard processes started
//! at once on an empty cache of compiled C, `campaign status` while shards are missing, the
//! merge, and `--emit` (the real Slurm test is `scripts/test-slurm`).

mod common;

use common::{repo_root, text};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn dynarole_with_cache(args: &[&str], cache: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dynarole"))
        .args(args)
        .current_dir(repo_root())
        .env("DYNAROLE_SIM_CACHE", cache)
        .env("DYNAROLE_PROGRESS_SECONDS", "0")
        .output()
        .expect("the dynarole binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

fn utf8(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

#[test]
fn shards_started_at_once_share_an_empty_cache_then_merge() {
    let root = scratch("cli-cluster");
    let cache = root.join("cache");
    let out = root.join("shards");
    let shard = |k: u32| {
        Command::new(env!("CARGO_BIN_EXE_dynarole"))
            .args(["campaign", "examples/campaigns/smoke.toml", "-j", "1"])
            .args(["--shard", &format!("{k}/6"), "-o", utf8(&out)])
            .current_dir(repo_root())
            .env("DYNAROLE_SIM_CACHE", &cache)
            .env("DYNAROLE_PROGRESS_SECONDS", "0")
            .stdout(std::process::Stdio::null())
            .spawn()
            .expect("a shard process")
    };
    // Shards 0 to 3 together: each builds the three protocols' C into the same empty cache.
    let children: Vec<_> = (0..4).map(shard).collect();
    for mut child in children {
        assert!(child.wait().expect("a shard ends").success());
    }
    let entries = dynarole_sim::cache_entries(&cache).expect("the cache");
    assert_eq!(entries.len(), 3, "one build per protocol: {entries:?}");
    assert!(
        entries.iter().all(|e| !e.starts_with("tmp-")),
        "{entries:?}"
    );

    let status = dynarole_with_cache(&["campaign", "status", utf8(&out)], &cache);
    assert_eq!(status.status.code(), Some(0), "{}", text(&status.stderr));
    let lines = text(&status.stdout);
    assert!(
        lines.contains("shard 0/6: 6 of 6 runs, finished\n"),
        "{lines}"
    );
    assert!(
        lines.contains("shard 5/6: 0 of 6 runs, not started\n"),
        "{lines}"
    );
    assert!(
        lines.ends_with("24 of 36 runs done (66.7 %), 4 of 6 shards finished\n"),
        "{lines}"
    );

    let early = dynarole_with_cache(&["campaign", "merge", utf8(&out), "--no-plots"], &cache);
    assert_eq!(early.status.code(), Some(1));
    let err = text(&early.stderr);
    assert!(
        err.contains("shard 4/6 is missing") && err.contains("shard 5/6 is missing"),
        "{err}"
    );

    for k in 4..6 {
        assert!(shard(k).wait().expect("a shard ends").success());
    }
    let merged = dynarole_with_cache(&["campaign", "merge", utf8(&out), "--no-plots"], &cache);
    assert_eq!(merged.status.code(), Some(0), "{}", text(&merged.stderr));
    let printed = text(&merged.stdout);
    assert!(
        printed.starts_with("36 runs: 36 recorded before"),
        "{printed}"
    );
    assert!(printed.contains("runs.csv"), "{printed}");
}

#[test]
fn emit_writes_the_job_files_and_says_how_to_submit() {
    let root = scratch("cli-cluster-emit");
    let jobs = root.join("jobs");
    let out = dynarole_with_cache(
        &[
            "campaign",
            "examples/campaigns/smoke.toml",
            "--emit",
            "parallel",
            "--shards",
            "3",
            "-o",
            utf8(&jobs),
        ],
        &root.join("cache"),
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let printed = text(&out.stdout);
    assert!(
        printed.contains("commands.txt") && printed.contains("run.sh"),
        "{printed}"
    );
    assert!(printed.contains("submit from this directory:"), "{printed}");
    assert!(
        printed.contains("36 runs in 3 shards of 12 or 12 runs"),
        "{printed}"
    );
    let commands = std::fs::read_to_string(jobs.join("commands.txt")).expect("commands");
    assert_eq!(commands.lines().count(), 3);
    assert!(commands.contains("--shard \"2/3\""), "{commands}");

    let missing = dynarole_with_cache(
        &[
            "campaign",
            "no/such.toml",
            "--emit",
            "slurm",
            "--shards",
            "2",
        ],
        &root.join("cache"),
    );
    assert_eq!(missing.status.code(), Some(1));
    let err = text(&missing.stderr);
    assert!(err.contains("no/such.toml: No such file"), "{err}");
}
