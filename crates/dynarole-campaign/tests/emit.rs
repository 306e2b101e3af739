//! Golden job files: what `--emit slurm|htcondor|parallel` writes for a campaign split into 8
//! shards, 2 at a time (one snapshot per scheduler, every file in turn).

use dynarole_campaign::{job_files, Jobs, Scheduler};
use std::path::PathBuf;

/// Job files in `out/smoke shards` (a space, to show the quoting), or `out/smoke` for
/// HTCondor, whose files cannot quote.
fn jobs(dir: &str) -> Jobs {
    Jobs {
        campaign: PathBuf::from("examples/campaigns/smoke.toml"),
        dir: PathBuf::from(dir),
        shards: 8,
        throttle: 2,
        threads: 1,
    }
}

/// Each file under a `=== NAME (executable) ===` line.
fn all(scheduler: Scheduler) -> String {
    let dir = match scheduler {
        Scheduler::Htcondor => "out/smoke",
        _ => "out/smoke shards",
    };
    job_files(scheduler, &jobs(dir))
        .iter()
        .map(|f| {
            let mode = if f.executable { " (executable)" } else { "" };
            format!("=== {}{mode} ===\n{}", f.name, f.text)
        })
        .collect()
}

#[test]
fn slurm_array_then_merge() {
    insta::assert_snapshot!(all(Scheduler::Slurm));
}

#[test]
fn htcondor_dag_of_shards_then_merge() {
    insta::assert_snapshot!(all(Scheduler::Htcondor));
}

#[test]
fn gnu_parallel_command_list() {
    insta::assert_snapshot!(all(Scheduler::Parallel));
}

#[test]
fn written_scripts_are_executable() {
    let dir = tempfile::tempdir().expect("temp dir");
    let jobs = jobs(&dir.path().join("jobs").display().to_string());
    let files = dynarole_campaign::write_job_files(Scheduler::Slurm, &jobs).expect("written");
    assert_eq!(files.len(), 3);
    assert!(jobs.dir.join("logs").is_dir());
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = |name: &str| {
            std::fs::metadata(jobs.dir.join(name))
                .expect("a job file")
                .permissions()
                .mode()
        };
        assert_eq!(mode("submit.sh") & 0o111, 0o111);
        assert_eq!(mode("shards.sbatch") & 0o111, 0);
    }
    let spaced = jobs_in(dir.path().join("my jobs"));
    let err = dynarole_campaign::write_job_files(Scheduler::Htcondor, &spaced)
        .expect_err("HTCondor cannot take spaces")
        .to_string();
    assert!(
        err.contains("the output directory (-o DIR)") && err.contains("a space (U+0020)"),
        "{err}"
    );
}

fn jobs_in(dir: PathBuf) -> Jobs {
    Jobs { dir, ..jobs("") }
}

/// Every character a shell treats specially (a space too), in a campaign path and a directory
/// name, with commands that leave a marker file if anything runs them.
const METACHARACTERS: &str = " ;&|<>()$`'\"\\*?[]{}~!#%^=,@+:";

/// A campaign name and a directory name holding every metacharacter and two injections.
/// Slurm's directory keeps no backslash (refused: it turns off `%a`).
fn hostile(scheduler: Scheduler) -> (String, String) {
    let campaign = format!("c{METACHARACTERS}$(touch PWNED)`touch PWNED2`.toml");
    let dir = match scheduler {
        Scheduler::Slurm => format!("-o{}$(touch PWNED3)", METACHARACTERS.replace('\\', "")),
        Scheduler::Htcondor => "+out/jobs-1".to_string(),
        Scheduler::Parallel => format!("+o{METACHARACTERS}$(touch PWNED3)`touch PWNED4`"),
    };
    (campaign, dir)
}

/// Stand-ins for the schedulers and dynarole: each records its arguments (one a line) in
/// `$RECORD` and runs the job scripts as the real one would, from the submitting directory.
const FAKES: [(&str, &str); 4] = [
    (
        "dynarole",
        "printf '%s\\n' \"$@\" >> \"$RECORD/dynarole\"\necho --- >> \"$RECORD/dynarole\"\n",
    ),
    (
        "sbatch",
        "printf '%s\\n' \"$@\" >> \"$RECORD/sbatch\"\nfor a in \"$@\"; do script=$a; done\n\
         SLURM_ARRAY_TASK_ID=0 SLURM_CPUS_PER_TASK=1 bash \"$script\" >&2\necho 42\n",
    ),
    (
        "parallel",
        "printf '%s\\n' \"$@\" >> \"$RECORD/parallel\"\n\
         while IFS= read -r line; do sh -c \"$line\" || exit 1; done\n",
    ),
    (
        "condor_submit_dag",
        "printf '%s\\n' \"$@\" >> \"$RECORD/condor\"\n\
         grep '^JOB ' \"$1\" | while read -r _ name sub; do\n\
         exe=$(sed -n 's/^executable = //p' \"$sub\")\n\
         args=$(sed -n 's/^arguments = //p' \"$sub\" | sed 's/[$](Process)/0/')\n\
         \"$exe\" $args || exit 1\ndone\n",
    ),
];

/// A scratch folder with `bin/` (the stand-ins), `record/` and `work/` (where `--emit` runs,
/// with the hostile campaign file in it).
struct Bench {
    root: tempfile::TempDir,
}

impl Bench {
    fn new(campaign: &str) -> Bench {
        use std::os::unix::fs::PermissionsExt;
        let root = tempfile::tempdir().expect("temp dir");
        for sub in ["bin", "record", "work", "elsewhere"] {
            std::fs::create_dir(root.path().join(sub)).expect("a folder");
        }
        for (name, body) in FAKES {
            let path = root.path().join("bin").join(name);
            std::fs::write(&path, format!("#!/bin/sh\n{body}")).expect("a stand-in");
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755))
                .expect("executable");
        }
        std::fs::write(root.path().join("work").join(campaign), "").expect("the campaign");
        Bench { root }
    }

    fn path(&self, sub: &str) -> PathBuf {
        self.root.path().join(sub)
    }

    /// Runs `program args` in `cwd` with the stand-ins first on the PATH.
    fn run(&self, cwd: &str, program: &str, args: &[&std::ffi::OsStr]) -> std::process::Output {
        let path = format!(
            "{}:{}",
            self.path("bin").display(),
            std::env::var("PATH").unwrap_or_default()
        );
        std::process::Command::new(program)
            .args(args)
            .current_dir(self.path(cwd))
            .env("PATH", path)
            .env("DYNAROLE", self.path("bin").join("dynarole"))
            .env("RECORD", self.path("record"))
            .output()
            .expect("the script runs")
    }

    fn recorded(&self, name: &str) -> String {
        std::fs::read_to_string(self.path("record").join(name)).unwrap_or_default()
    }

    /// Every marker file an injected command would have made, anywhere in the scratch folder.
    fn markers(&self) -> Vec<PathBuf> {
        let mut found = Vec::new();
        let mut stack = vec![self.root.path().to_path_buf()];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).expect("a folder") {
                let path = entry.expect("an entry").path();
                if path.is_dir() {
                    stack.push(path);
                } else if path
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("PWNED"))
                {
                    found.push(path);
                }
            }
        }
        found
    }
}

/// Emits job files for the hostile names in `work/` (written here, as `write_job_files`
/// would from there: the job files name the paths as given, relative to `work/`); returns
/// the bench and the names.
fn emit_hostile(scheduler: Scheduler) -> (Bench, String, String) {
    use std::os::unix::fs::PermissionsExt;
    let (campaign, dir) = hostile(scheduler);
    let bench = Bench::new(&campaign);
    let jobs = Jobs {
        campaign: PathBuf::from(&campaign),
        dir: PathBuf::from(&dir),
        shards: 1,
        throttle: 1,
        threads: 1,
    };
    dynarole_campaign::check_jobs(scheduler, &jobs).expect("the paths can be carried");
    let at = bench.path("work").join(&dir);
    std::fs::create_dir_all(at.join("logs")).expect("the job directory");
    for file in job_files(scheduler, &jobs) {
        let path = at.join(file.name);
        std::fs::write(&path, &file.text).expect("a job file");
        let mode = if file.executable { 0o755 } else { 0o644 };
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(mode)).expect("mode");
    }
    (bench, campaign, dir)
}

/// The argument lists the stand-in dynarole got for one shard and the merge, exactly: the
/// paths arrive as the words they are, whatever characters they hold.
fn expected_calls(campaign: &str, dir: &str) -> String {
    let arg = |p: &str| {
        if p.starts_with(['-', '+']) {
            format!("./{p}")
        } else {
            p.to_string()
        }
    };
    let (c, d) = (arg(campaign), arg(dir));
    format!("campaign\n{c}\n--shard\n0/1\n-o\n{d}\n-j\n1\n---\ncampaign\nmerge\n{d}\n---\n")
}

/// The script `name` run from a directory without the campaign file: it says so, exit 2.
fn from_elsewhere(bench: &Bench, dir: &str, shell: &str, name: &str, campaign: &str) {
    let script = bench.path("work").join(dir).join(name);
    let out = bench.run("elsewhere", shell, &[script.as_os_str(), "0".as_ref()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains(&format!("{campaign} not found in ")), "{err}");
    assert!(bench.recorded("dynarole").is_empty());
}

#[cfg(unix)]
#[test]
fn slurm_job_files_carry_every_metacharacter_as_text() {
    let (bench, campaign, dir) = emit_hostile(Scheduler::Slurm);
    from_elsewhere(&bench, &dir, "bash", "shards.sbatch", &campaign);
    let submit = bench.path("work").join(&dir).join("submit.sh");
    let out = bench.run("work", "sh", &[submit.as_os_str()]);
    let printed = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        printed.starts_with("shards: job 42; merge: job 42\n"),
        "{printed}"
    );
    assert!(
        printed.ends_with(&format!("campaign status ./{dir}\n")),
        "{printed}"
    );
    assert_eq!(bench.recorded("dynarole"), expected_calls(&campaign, &dir));
    let log = format!("--output=./{}/logs/shard-%a.out", dir.replace('%', "%%"));
    assert!(
        bench.recorded("sbatch").lines().any(|l| l == log),
        "{}",
        bench.recorded("sbatch")
    );
    assert_eq!(bench.markers(), Vec::<PathBuf>::new());
}

#[cfg(unix)]
#[test]
fn parallel_job_files_carry_every_metacharacter_as_text() {
    let (bench, campaign, dir) = emit_hostile(Scheduler::Parallel);
    from_elsewhere(&bench, &dir, "sh", "run.sh", &campaign);
    let run = bench.path("work").join(&dir).join("run.sh");
    let out = bench.run("work", "sh", &[run.as_os_str()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(bench.recorded("dynarole"), expected_calls(&campaign, &dir));
    let joblog = format!("./{dir}/logs/parallel.log");
    assert!(bench.recorded("parallel").lines().any(|l| l == joblog));
    assert_eq!(bench.markers(), Vec::<PathBuf>::new());
}

#[cfg(unix)]
#[test]
fn htcondor_job_files_carry_a_hostile_campaign_path_as_text() {
    let (bench, campaign, dir) = emit_hostile(Scheduler::Htcondor);
    from_elsewhere(&bench, &dir, "sh", "shard.sh", &campaign);
    let dag = format!("{dir}/campaign.dag");
    let out = bench.run("work", "condor_submit_dag", &[dag.as_ref()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(bench.recorded("dynarole"), expected_calls(&campaign, &dir));
    assert_eq!(bench.markers(), Vec::<PathBuf>::new());
}

/// What no job file can carry is refused before anything is written, naming the field and
/// the character.
#[test]
fn paths_the_job_files_cannot_carry_are_refused() {
    let root = tempfile::tempdir().expect("temp dir");
    let refused = |scheduler, campaign: &str, dir: &str, threads| {
        let jobs = Jobs {
            campaign: PathBuf::from(campaign),
            dir: root.path().join(dir),
            shards: 2,
            threads,
            throttle: 1,
        };
        let err = dynarole_campaign::write_job_files(scheduler, &jobs)
            .expect_err("refused")
            .to_string();
        assert!(!jobs.dir.exists(), "nothing written for {err}");
        err
    };
    let newline = refused(Scheduler::Slurm, "a\ntouch PWNED\n.toml", "out", 1);
    assert!(
        newline.contains("the campaign file \"a\\ntouch PWNED\\n.toml\" holds a newline (U+000A)"),
        "{newline}"
    );
    let dollar = refused(Scheduler::Htcondor, "c.toml", "o$(x)", 1);
    assert!(
        dollar.contains("the output directory (-o DIR)")
            && dollar.contains("the character '$' (U+0024)")
            && dollar.contains("HTCondor"),
        "{dollar}"
    );
    let backslash = refused(Scheduler::Slurm, "c.toml", "o\\x", 1);
    assert!(backslash.contains("'\\' (U+005C)"), "{backslash}");
    let tab = refused(Scheduler::Parallel, "c.toml", "o\tx", 1);
    assert!(tab.contains("a tab (U+0009)"), "{tab}");
    let zero = refused(Scheduler::Slurm, "c.toml", "out", 0);
    assert!(zero.starts_with("-j 0: "), "{zero}");
}

/// `campaign status DIR` works right after `--emit`: 0 of the campaign's runs, no shard yet;
/// the first shard then finds the copy and the record `--emit` kept, and counts.
#[test]
fn status_right_after_emit_counts_no_run_done() {
    let root = tempfile::tempdir().expect("temp dir");
    let campaign =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/campaigns/smoke.toml");
    let jobs = Jobs {
        campaign: campaign.clone(),
        dir: root.path().join("jobs"),
        shards: 3,
        throttle: 3,
        threads: 1,
    };
    let (runs, files) =
        dynarole_campaign::emit(Scheduler::Parallel, &jobs, &dynarole_robots::robots())
            .expect("emitted");
    assert_eq!((runs, files.len()), (36, 2));
    let now = dynarole_campaign::status(&jobs.dir).expect("a status");
    assert_eq!((now.total, now.done(), now.shards), (36, 0, None));
    let options = dynarole_campaign::Options {
        campaign,
        out_dir: jobs.dir.clone(),
        max_runs: Some(2),
        jobs: Some(1),
        plots: false,
        shard: Some("0/3".parse().expect("a shard")),
    };
    dynarole_campaign::run(
        &options,
        &dynarole_robots::robots(),
        &mut dynarole_campaign::Quiet,
    )
    .expect("the first shard starts");
    let now = dynarole_campaign::status(&jobs.dir).expect("a status");
    assert_eq!((now.total, now.done(), now.shards), (36, 2, Some(3)));
    let other = Jobs { shards: 4, ..jobs };
    let err = dynarole_campaign::emit(Scheduler::Parallel, &other, &dynarole_robots::robots())
        .expect_err("another split")
        .to_string();
    assert!(
        err.contains("holds shards of a split into 3, not 4"),
        "{err}"
    );
}
