//! Shards and merge on `examples/campaigns/smoke.toml`: merging 1, 7 or 64 shards gives the
//! bytes of a one-machine run; shards stopped midway (or cut) and run again give the same
//! merge; a missing or unfinished shard, or runs missing, are named.

use dynarole_campaign::{merge, run, status, Done, Error, MergeOptions, Options, ProgressMode};
use std::path::{Path, PathBuf};

fn smoke() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/campaigns/smoke.toml")
}

fn options(out: &Path, shard: Option<&str>, max_runs: Option<u64>) -> Options {
    Options {
        campaign: smoke(),
        out_dir: out.to_path_buf(),
        max_runs,
        jobs: Some(1),
        progress: ProgressMode::Off,
        plots: true,
        shard: shard.map(|s| s.parse().expect("a shard")),
    }
}

fn shard(out: &Path, k: u64, n: u64, max_runs: Option<u64>) -> Done {
    match run(&options(out, Some(&format!("{k}/{n}")), max_runs)) {
        Ok(done) => done,
        Err(e) => panic!("shard {k}/{n} failed: {e}"),
    }
}

fn merged(dir: &Path, out: &Path) -> Result<Done, Error> {
    merge(&MergeOptions {
        dir: dir.to_path_buf(),
        out_dir: out.to_path_buf(),
        plots: true,
    })
}

/// Every file a campaign writes (runs.csv, summaries, plots), by name, with its bytes.
fn outputs(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .expect("the output directory")
        .map(|e| e.expect("an entry").path())
        .filter(|p| {
            !p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("shard-"))
        })
        .filter(|p| p.file_name().is_some_and(|n| n != "campaign.toml"))
        .map(|p| {
            let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
            (name.unwrap_or_default(), std::fs::read(&p).expect("a file"))
        })
        .collect();
    files.sort();
    files
}

#[test]
fn merging_any_number_of_shards_gives_the_one_machine_bytes() {
    let root = tempfile::tempdir().expect("temp dir");
    let one = root.path().join("one");
    run(&options(&one, None, None)).expect("the one-machine run");
    let expected = outputs(&one);
    let names: Vec<&str> = expected.iter().map(|(n, _)| n.as_str()).collect();
    for name in ["runs.csv", "summary.csv", "summary.md", "success-loss.svg"] {
        assert!(names.contains(&name), "{name} missing from {names:?}");
    }
    for n in [1, 7, 64] {
        let dir = root.path().join(format!("shards-{n}"));
        let mut total = 0;
        for k in 0..n {
            total += shard(&dir, k, n, None).total;
        }
        assert_eq!(total, 36);
        let out = root.path().join(format!("merged-{n}"));
        merged(&dir, &out).expect("a complete split merges");
        assert!(outputs(&out) == expected, "merging {n} shards differs");
    }
}

#[test]
fn shards_stopped_or_cut_and_run_again_give_the_same_merge() {
    let root = tempfile::tempdir().expect("temp dir");
    let whole = root.path().join("whole");
    let broken = root.path().join("broken");
    for k in 0..4 {
        shard(&whole, k, 4, None);
    }
    // Shard 1 stopped after 3 runs, its last row half written; shard 2 finished but its file
    // cut in the middle of a row; shard 3 never started.
    let stopped = shard(&broken, 1, 4, Some(3));
    assert_eq!((stopped.ran, stopped.total), (3, 9));
    let partial = broken.join("shard-1-of-4.csv.partial");
    let cut_row = "30,loss,0.4,paper,atron,2,0.4";
    append(&partial, cut_row);
    shard(&broken, 0, 4, None);
    shard(&broken, 2, 4, None);
    let finished = broken.join("shard-2-of-4.csv");
    let text = std::fs::read_to_string(&finished).expect("shard 2");
    std::fs::write(&finished, &text[..text.len() - 20]).expect("cut");
    let err = merged(&broken, &root.path().join("early"))
        .expect_err("an incomplete split does not merge")
        .to_string();
    assert!(
        err.contains("shard 1/4 is unfinished (3 of 9 runs"),
        "{err}"
    );
    assert!(err.contains("shard 3/4 is missing"), "{err}");
    let now = status(&broken).expect("status");
    assert_eq!(
        (now.total, now.done(), now.shards),
        (36, 3 + 9 + 8, Some(4))
    );

    for k in 1..4 {
        shard(&broken, k, 4, None);
    }
    let a = root.path().join("merged-whole");
    let b = root.path().join("merged-broken");
    merged(&whole, &a).expect("merge");
    merged(&broken, &b).expect("merge after the reruns");
    assert!(outputs(&a) == outputs(&b));
    assert!(!partial.exists());
}

fn append(path: &Path, text: &str) {
    use std::io::Write;
    let mut file = std::fs::OpenOptions::new()
        .append(true)
        .open(path)
        .expect("open");
    file.write_all(text.as_bytes()).expect("append");
}

#[test]
fn missing_runs_and_mixed_splits_are_named() {
    let root = tempfile::tempdir().expect("temp dir");
    let dir = root.path().join("shards");
    shard(&dir, 0, 2, None);
    shard(&dir, 1, 2, None);
    // A finished file that lost rows (edited by hand, say) names the runs.
    let file = dir.join("shard-1-of-2.csv");
    let text = std::fs::read_to_string(&file).expect("shard 1");
    let kept: Vec<&str> = text.lines().take(3).collect();
    std::fs::write(&file, kept.join("\n") + "\n").expect("rewrite");
    let err = merged(&dir, &dir).expect_err("runs missing").to_string();
    assert!(
        err.contains("16 of 36 runs are not recorded")
            && err.contains("runs missing: 5, 7, 9, 11, 13, 15, 17, 19, 21, 23 and 6 more"),
        "{err}"
    );
    let other = run(&options(&dir, Some("0/3"), None))
        .expect_err("another split in the same directory")
        .to_string();
    assert!(
        other.contains("holds shards of a split into 2, not 3"),
        "{other}"
    );
    let none = merged(root.path(), root.path())
        .expect_err("not a shard directory")
        .to_string();
    assert!(none.contains("campaign.toml"), "{none}");
}
