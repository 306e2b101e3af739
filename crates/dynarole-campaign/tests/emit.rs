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
    assert!(err.contains("cannot name paths with spaces"), "{err}");
}

fn jobs_in(dir: PathBuf) -> Jobs {
    Jobs { dir, ..jobs("") }
}
