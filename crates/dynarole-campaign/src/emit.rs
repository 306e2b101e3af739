//! Job files that run a campaign's shards on a scheduler (a Slurm job array, an HTCondor
//! cluster under a DAG, a GNU parallel command list), then the merge. dynarole itself does no
//! scheduling: every job calls `dynarole campaign FILE --shard K/N -o DIR`.

use crate::Error;
use std::path::{Path, PathBuf};

/// The schedulers job files can be written for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheduler {
    Slurm,
    Htcondor,
    Parallel,
}

/// What the job files run.
#[derive(Clone, Debug)]
pub struct Jobs {
    /// The campaign file, as the user named it (relative to where jobs are submitted).
    pub campaign: PathBuf,
    /// The directory of the job files, the logs and the shards' results.
    pub dir: PathBuf,
    pub shards: u64,
    /// Most shards running at once.
    pub throttle: u64,
    /// Worker threads (cores) per shard.
    pub threads: usize,
}

/// One job file: its name in the directory, its text, whether it is a script to execute.
pub struct JobFile {
    pub name: &'static str,
    pub text: String,
    pub executable: bool,
}

/// The job files for `scheduler`.
pub fn job_files(scheduler: Scheduler, jobs: &Jobs) -> Vec<JobFile> {
    match scheduler {
        Scheduler::Slurm => slurm(jobs),
        Scheduler::Htcondor => htcondor(jobs),
        Scheduler::Parallel => parallel(jobs),
    }
}

/// Writes the job files into `jobs.dir` (and creates `logs/` there); returns their paths.
pub fn write(scheduler: Scheduler, jobs: &Jobs) -> Result<Vec<PathBuf>, Error> {
    let spaced = |p: &Path| p.to_string_lossy().contains(char::is_whitespace);
    if scheduler == Scheduler::Htcondor && (spaced(&jobs.dir) || spaced(&jobs.campaign)) {
        return Err(Error::Input(format!(
            "{}, {}: HTCondor's submit and DAG files cannot name paths with spaces; \
             choose others",
            jobs.campaign.display(),
            jobs.dir.display()
        )));
    }
    let logs = jobs.dir.join("logs");
    std::fs::create_dir_all(&logs).map_err(|e| Error::io(&logs, e))?;
    let mut written = Vec::new();
    for file in job_files(scheduler, jobs) {
        let path = jobs.dir.join(file.name);
        std::fs::write(&path, &file.text).map_err(|e| Error::io(&path, e))?;
        if file.executable {
            make_executable(&path)?;
        }
        written.push(path);
    }
    Ok(written)
}

#[cfg(unix)]
fn make_executable(path: &Path) -> Result<(), Error> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))
        .map_err(|e| Error::io(path, e))
}

#[cfg(not(unix))]
fn make_executable(_: &Path) -> Result<(), Error> {
    Ok(())
}

/// The shell's words for the paths and the shard command.
struct Words {
    campaign: String,
    dir: String,
    /// `DIR` unquoted, to join file names to.
    dir_raw: String,
    name: String,
}

impl Words {
    fn of(jobs: &Jobs) -> Words {
        let name = jobs
            .campaign
            .file_stem()
            .map_or("campaign".into(), |s| s.to_string_lossy().into_owned());
        Words {
            campaign: quote(&jobs.campaign.display().to_string()),
            dir: quote(&jobs.dir.display().to_string()),
            dir_raw: jobs.dir.display().to_string(),
            name: name
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '-' {
                        c
                    } else {
                        '_'
                    }
                })
                .collect(),
        }
    }

    /// In `DIR/`, for a file of the job files.
    fn at(&self, file: &str) -> String {
        quote(&format!("{}/{file}", self.dir_raw))
    }

    /// The command of shard `index` (a shell word or variable) of `jobs.shards`.
    fn shard(&self, jobs: &Jobs, index: &str, threads: &str) -> String {
        format!(
            "\"${{DYNAROLE:-dynarole}}\" campaign {} --shard \"{index}/{}\" -o {} -j {threads}",
            self.campaign, jobs.shards, self.dir
        )
    }

    fn merge(&self) -> String {
        format!("\"${{DYNAROLE:-dynarole}}\" campaign merge {}", self.dir)
    }

    /// Stops a job started from the wrong directory with a message saying which one.
    fn check_directory(&self) -> String {
        format!(
            "if [ ! -f {c} ]; then\n  echo \"{c} not found in $(pwd): submit from the directory \
             where the job files were written\" >&2\n  exit 2\nfi\n",
            c = self.campaign
        )
    }
}

/// `word` for a POSIX shell: as is when it has only safe characters, else single-quoted.
fn quote(word: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "_./-+=:,@%".contains(c);
    if !word.is_empty() && word.chars().all(safe) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

fn header(what: &str, jobs: &Jobs, words: &Words) -> String {
    format!(
        "# {what}: the campaign {} in {} shards.\n\
         # Written by `dynarole campaign --emit`; paths are relative to the directory it ran in:\n\
         # submit from there. DYNAROLE names the dynarole program if it is not on the PATH.\n",
        words.campaign, jobs.shards
    )
}

fn slurm(jobs: &Jobs) -> Vec<JobFile> {
    let w = Words::of(jobs);
    let shards = format!(
        "#!/bin/bash\n{}#SBATCH --job-name=dynarole-{}\n#SBATCH --array=0-{}%{}\n\
         #SBATCH --cpus-per-task={}\n#SBATCH --output={}\nset -euo pipefail\n{}exec {}\n",
        header("One Slurm array task per shard", jobs, &w),
        w.name,
        jobs.shards - 1,
        jobs.throttle,
        jobs.threads,
        w.at("logs/shard-%a.out"),
        w.check_directory(),
        w.shard(
            jobs,
            "${SLURM_ARRAY_TASK_ID}",
            "\"${SLURM_CPUS_PER_TASK:-1}\""
        ),
    );
    let merge = format!(
        "#!/bin/bash\n{}#SBATCH --job-name=dynarole-{}-merge\n#SBATCH --output={}\n\
         set -euo pipefail\nexec {}\n",
        header(
            "The merge of the shards, once all of them succeeded",
            jobs,
            &w
        ),
        w.name,
        w.at("logs/merge.out"),
        w.merge()
    );
    let submit = format!(
        "#!/bin/sh\n{}set -eu\nshards=$(sbatch --parsable {})\nshards=${{shards%%;*}}\n\
         merge=$(sbatch --parsable --dependency=afterok:\"$shards\" {})\nmerge=${{merge%%;*}}\n\
         echo \"shards: job $shards; merge: job $merge\"\n\
         echo \"progress: dynarole campaign status {}\"\n",
        header(
            "Submits the shards, then the merge once they all succeeded,",
            jobs,
            &w
        ),
        w.at("shards.sbatch"),
        w.at("merge.sbatch"),
        w.dir
    );
    vec![
        JobFile {
            name: "shards.sbatch",
            text: shards,
            executable: false,
        },
        JobFile {
            name: "merge.sbatch",
            text: merge,
            executable: false,
        },
        JobFile {
            name: "submit.sh",
            text: submit,
            executable: true,
        },
    ]
}

fn htcondor(jobs: &Jobs) -> Vec<JobFile> {
    let w = Words::of(jobs);
    let script = |what: &str, command: String| {
        format!(
            "#!/bin/sh\n{}set -eu\n{}exec {command}\n",
            header(what, jobs, &w),
            w.check_directory()
        )
    };
    // HTCondor's files take paths as they are (no shell quoting).
    let at = |file: &str| format!("{}/{file}", w.dir_raw);
    let submit = |what: &str, executable: &str, extra: &str, log: &str| {
        format!(
            "{}universe = vanilla\nexecutable = {}\n{extra}getenv = true\n\
             should_transfer_files = NO\noutput = {}\nerror = {}\nlog = {}\n",
            header(what, jobs, &w),
            at(executable),
            at(&format!("logs/{log}.out")),
            at(&format!("logs/{log}.err")),
            at("logs/condor.log"),
        )
    };
    let shards = submit(
        "One HTCondor job per shard",
        "shard.sh",
        &format!(
            "arguments = $(Process)\nrequest_cpus = {}\nmax_materialize = {}\n",
            jobs.threads, jobs.throttle
        ),
        "shard-$(Process)",
    ) + &format!("queue {}\n", jobs.shards);
    let merge = submit("The merge of the shards", "merge.sh", "", "merge") + "queue\n";
    let dag = format!(
        "{}JOB shards {}\nJOB merge {}\nPARENT shards CHILD merge\n",
        header(
            "For condor_submit_dag: the shards, then the merge",
            jobs,
            &w
        ),
        at("shards.sub"),
        at("merge.sub")
    );
    let threads = jobs.threads.to_string();
    vec![
        JobFile {
            name: "shard.sh",
            text: script("Runs shard $1", w.shard(jobs, "$1", &threads)),
            executable: true,
        },
        JobFile {
            name: "merge.sh",
            text: script("Merges the shards", w.merge()),
            executable: true,
        },
        JobFile {
            name: "shards.sub",
            text: shards,
            executable: false,
        },
        JobFile {
            name: "merge.sub",
            text: merge,
            executable: false,
        },
        JobFile {
            name: "campaign.dag",
            text: dag,
            executable: false,
        },
    ]
}

fn parallel(jobs: &Jobs) -> Vec<JobFile> {
    let w = Words::of(jobs);
    let threads = jobs.threads.to_string();
    let commands: String = (0..jobs.shards)
        .map(|k| w.shard(jobs, &k.to_string(), &threads) + "\n")
        .collect();
    let run = format!(
        "#!/bin/sh\n{}set -eu\n{}parallel --jobs {} --joblog {} --resume-failed < {}\nexec {}\n",
        header(
            "Runs the shards with GNU parallel (run again: only the failed ones), then merges",
            jobs,
            &w
        ),
        w.check_directory(),
        jobs.throttle,
        w.at("logs/parallel.log"),
        w.at("commands.txt"),
        w.merge()
    );
    vec![
        JobFile {
            name: "commands.txt",
            text: commands,
            executable: false,
        },
        JobFile {
            name: "run.sh",
            text: run,
            executable: true,
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_are_quoted_only_when_needed() {
        assert_eq!(quote("out/smoke"), "out/smoke");
        assert_eq!(quote("my runs/it's"), "'my runs/it'\\''s'");
        assert_eq!(quote(""), "''");
    }
}
