//! Shards and merge on `examples/campaigns/smoke.toml`: merging 1, 7 or 64 shards gives the
//! bytes of a one-machine run; shards stopped midway (or cut) and run again give the same
//! merge; a missing or unfinished shard, or runs missing, are named.

use dynarole_campaign::{merge, run, status, Done, Error, MergeOptions, Options, Quiet};
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
        plots: true,
        shard: shard.map(|s| s.parse().expect("a shard")),
    }
}

fn shard(out: &Path, k: u64, n: u64, max_runs: Option<u64>) -> Done {
    match run(
        &options(out, Some(&format!("{k}/{n}")), max_runs),
        &dynarole_robots::robots(),
        &mut Quiet,
    ) {
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
    run(
        &options(&one, None, None),
        &dynarole_robots::robots(),
        &mut Quiet,
    )
    .expect("the one-machine run");
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
    // The record of the inputs, the header and two rows.
    let head = text.lines().take_while(|l| l.starts_with('#')).count();
    let kept: Vec<&str> = text.lines().take(head + 3).collect();
    std::fs::write(&file, kept.join("\n") + "\n").expect("rewrite");
    let err = merged(&dir, &dir).expect_err("runs missing").to_string();
    assert!(
        err.contains("16 of 36 runs are not recorded")
            && err.contains("runs missing: 5, 7, 9, 11, 13, 15, 17, 19, 21, 23 and 6 more"),
        "{err}"
    );
    let other = run(
        &options(&dir, Some("0/3"), None),
        &dynarole_robots::robots(),
        &mut Quiet,
    )
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

/// A copy of the smoke campaign and its files in `root`, laid out as in the repository
/// (`examples/campaigns/smoke.toml`, the robot's `robots/atron/examples/`), to edit; returns
/// the campaign file's path.
fn copy_of_smoke(root: &Path) -> PathBuf {
    let repository = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for file in [
        "examples/campaigns/smoke.toml",
        "robots/atron/examples/eight2car.dr",
        "robots/atron/examples/eight.json",
        "robots/atron/examples/car.json",
    ] {
        let to = root.join(file);
        std::fs::create_dir_all(to.parent().expect("a folder")).expect("a folder");
        std::fs::copy(repository.join(file), to).expect("a copy");
    }
    root.join("examples/campaigns/smoke.toml")
}

fn run_from(
    campaign: &Path,
    out: &Path,
    shard: Option<&str>,
    max_runs: Option<u64>,
) -> Result<Done, Error> {
    run(
        &Options {
            campaign: campaign.to_path_buf(),
            ..options(out, shard, max_runs)
        },
        &dynarole_robots::robots(),
        &mut Quiet,
    )
}

fn error_of(result: Result<Done, Error>) -> String {
    match result {
        Ok(_) => panic!("expected an error"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn shards_and_resumes_of_other_inputs_are_refused() {
    let root = tempfile::tempdir().expect("temp dir");
    let a = copy_of_smoke(&root.path().join("a"));
    let b = copy_of_smoke(&root.path().join("b"));
    // Copy b expects another configuration: the same campaign text, other results.
    std::fs::copy(
        root.path().join("b/robots/atron/examples/eight.json"),
        root.path().join("b/robots/atron/examples/car.json"),
    )
    .expect("another expect");
    let dir = root.path().join("shards");
    let elsewhere = root.path().join("elsewhere");
    for k in 0..2 {
        run_from(&a, &dir, Some(&format!("{k}/2")), None).expect("a shard");
    }
    run_from(&b, &elsewhere, Some("1/2"), None).expect("the shard run elsewhere");

    // Started in the split's directory, it is refused at once.
    let direct = error_of(run_from(&b, &dir, Some("1/2"), None));
    assert!(
        direct.contains(
            "were computed from other inputs than now: another expected configuration (expect): "
        ) && direct
            .contains("b/examples/campaigns/../../robots/atron/examples/car.json instead of "),
        "{direct}"
    );
    // Copied in, the merge names it.
    std::fs::copy(
        elsewhere.join("shard-1-of-2.csv"),
        dir.join("shard-1-of-2.csv"),
    )
    .expect("copy");
    let merge_err = error_of(merged(&dir, &root.path().join("merged")));
    assert!(
        merge_err.contains("cannot merge, the shards' runs were computed from different inputs")
            && merge_err
                .contains("shard 1/2 was run with another expected configuration (expect): ")
            && merge_err
                .contains("b/examples/campaigns/../../robots/atron/examples/car.json instead of ")
            && merge_err.contains("a/examples/campaigns/../../robots/atron/examples/car.json"),
        "{merge_err}"
    );

    // An edit of the program after some runs: a resumed one-machine campaign is refused.
    let one = root.path().join("one");
    run_from(&a, &one, None, Some(3)).expect("three runs");
    append(
        &root.path().join("a/robots/atron/examples/eight2car.dr"),
        "// edited\n",
    );
    let resumed = error_of(run_from(&a, &one, None, None));
    assert!(
        resumed.contains("the 3 runs of ")
            && resumed
                .contains("runs.csv were computed from other inputs than now: another program: ")
            && resumed
                .contains("a/examples/campaigns/../../robots/atron/examples/eight2car.dr changed"),
        "{resumed}"
    );
}

/// A shard file that is not a regular file, a dangling link, a name no shard has, or a file
/// larger than its runs can fill: named by `merge` and `status` at once.
#[cfg(unix)]
#[test]
fn unreadable_or_strange_shard_files_are_named() {
    let root = tempfile::tempdir().expect("temp dir");
    let dir = root.path().join("shards");
    for k in 0..2 {
        shard(&dir, k, 2, None);
    }
    let file = dir.join("shard-1-of-2.csv");
    let saved = std::fs::read(&file).expect("shard 1");
    let both = |expected: &str| {
        let merge_err = error_of(merged(&dir, &root.path().join("merged")));
        assert!(merge_err.contains(expected), "{merge_err}");
        let status_err = status(&dir).expect_err("status refuses too").to_string();
        assert!(status_err.contains(expected), "{status_err}");
    };
    std::fs::remove_file(&file).expect("remove");
    let fifo = std::process::Command::new("mkfifo")
        .arg(&file)
        .status()
        .expect("mkfifo");
    assert!(fifo.success());
    both("shard-1-of-2.csv: not a regular file (a FIFO)");
    // The shard run again names it too, and leaves it where it is.
    let again = error_of(run(
        &options(&dir, Some("1/2"), None),
        &dynarole_robots::robots(),
        &mut Quiet,
    ));
    assert!(again.contains("not a regular file (a FIFO)"), "{again}");
    assert!(!dir.join("shard-1-of-2.csv.partial").exists());
    std::fs::remove_file(&file).expect("remove");
    std::os::unix::fs::symlink("/dev/zero", &file).expect("a link");
    both("shard-1-of-2.csv: not a regular file (a device)");
    std::fs::remove_file(&file).expect("remove");
    std::os::unix::fs::symlink(root.path().join("gone.csv"), &file).expect("a link");
    both("shard-1-of-2.csv: a dangling link (to ");
    std::fs::remove_file(&file).expect("remove");
    let huge = std::fs::File::create(&file).expect("a file");
    huge.set_len(1 << 30).expect("a sparse gigabyte");
    both("shard-1-of-2.csv: larger than ");
    std::fs::write(&file, &saved).expect("restored");
    std::fs::write(dir.join("shard-9-of-2.csv"), "").expect("a strange name");
    both("a file is named like a shard's results but no shard's");
    std::fs::remove_file(dir.join("shard-9-of-2.csv")).expect("remove");
    merged(&dir, &root.path().join("merged")).expect("merges again");
}

/// Rewrites column `column` of the first row of `path` whose outcome is `success` to
/// `value`; returns that row's line number (from 1).
fn edit_success_row(path: &Path, column: usize, value: &str) -> usize {
    let text = std::fs::read_to_string(path).expect("a shard file");
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let at = lines
        .iter()
        .position(|l| l.split(',').nth(12) == Some("success"))
        .expect("a successful run");
    let mut fields: Vec<&str> = lines[at].split(',').collect();
    fields[column] = value;
    lines[at] = fields.join(",");
    std::fs::write(path, lines.join("\n") + "\n").expect("rewritten");
    at + 1
}

#[test]
fn rows_that_contradict_themselves_are_refused_with_file_line_and_field() {
    let root = tempfile::tempdir().expect("temp dir");
    let dir = root.path().join("shards");
    for k in 0..2 {
        shard(&dir, k, 2, None);
    }
    let file = dir.join("shard-1-of-2.csv");
    let saved = std::fs::read(&file).expect("shard 1");
    let out = root.path().join("merged");
    let line = edit_success_row(&file, 19, "7");
    let violations = error_of(merged(&dir, &out));
    let at = format!("{}:{line}: field s1: ", file.display());
    assert!(
        violations.contains(&at)
            && violations.contains("a run whose outcome is success has 7 S1 violations"),
        "{violations}"
    );
    std::fs::write(&file, &saved).expect("restored");
    let line = edit_success_row(&file, 13, "NaN");
    let nan = error_of(merged(&dir, &out));
    let at = format!(
        "{}:{line}: field completion_ms: NaN is not a time",
        file.display()
    );
    assert!(nan.contains(&at), "{nan}");
    std::fs::write(&file, &saved).expect("restored");
    let line = edit_success_row(&file, 16, "many");
    let garbled = error_of(merged(&dir, &out));
    let at = format!("{}:{line}: field packets_sent: ", file.display());
    assert!(garbled.contains(&at), "{garbled}");
    std::fs::write(&file, &saved).expect("restored");
    merged(&dir, &out).expect("merges again");
}
