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
/// Paths that a job file could not carry safely are refused first (see [`check`]).
pub fn write(scheduler: Scheduler, jobs: &Jobs) -> Result<Vec<PathBuf>, Error> {
    check(scheduler, jobs)?;
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

/// Refuses what the job files could not carry as written. Every path is written as a quoted
/// shell word in the scripts, but it also appears in comments and in `commands.txt`, which
/// end at a line break, so no control character may appear in it; Slurm reads a backslash
/// in `--output` as "no `%a`" (every shard would write one log); HTCondor's submit and DAG
/// files cannot quote at all, so its directory keeps to the characters that need no quoting.
pub fn check(scheduler: Scheduler, jobs: &Jobs) -> Result<(), Error> {
    if jobs.threads == 0 {
        return Err(Error::Input(
            "-j 0: each shard needs at least one worker thread (the job files ask the \
             scheduler for -j cores per shard)"
                .into(),
        ));
    }
    let campaign = utf8("the campaign file", &jobs.campaign)?;
    let dir = utf8("the output directory (-o DIR)", &jobs.dir)?;
    refuse_char(
        "the campaign file",
        campaign,
        char::is_control,
        "no job file",
    )?;
    refuse_char(
        "the output directory (-o DIR)",
        dir,
        char::is_control,
        "no job file",
    )?;
    match scheduler {
        Scheduler::Slurm => refuse_char(
            "the output directory (-o DIR)",
            dir,
            |c| c == '\\',
            "Slurm's --output (a backslash turns off its %a)",
        ),
        Scheduler::Htcondor => refuse_char(
            "the output directory (-o DIR)",
            dir,
            |c| !is_plain(c),
            "HTCondor's submit and DAG files (they cannot quote)",
        ),
        Scheduler::Parallel => Ok(()),
    }
}

/// The path as text: a job file holds text, and a lossy copy would name another path.
fn utf8<'a>(field: &str, path: &'a Path) -> Result<&'a str, Error> {
    path.to_str().ok_or_else(|| {
        Error::Input(format!(
            "{field} {}: the path is not UTF-8 text, which job files cannot name; choose another",
            path.display()
        ))
    })
}

/// An error naming `field` and the first character of `text` that `bad` refuses.
fn refuse_char(
    field: &str,
    text: &str,
    bad: impl Fn(char) -> bool,
    what: &str,
) -> Result<(), Error> {
    match text.chars().find(|&c| bad(c)) {
        None => Ok(()),
        Some(c) => Err(Error::Input(format!(
            "{field} \"{}\" holds {}, which {what} can carry; choose another path",
            text.escape_debug(),
            describe(c)
        ))),
    }
}

/// `a newline (U+000A)`, `the character '$' (U+0024)`.
fn describe(c: char) -> String {
    let name = match c {
        '\n' => "a newline".to_string(),
        '\r' => "a carriage return".to_string(),
        '\t' => "a tab".to_string(),
        c if c.is_control() => "a control character".to_string(),
        ' ' => "a space".to_string(),
        c => format!("the character '{c}'"),
    };
    format!("{name} (U+{:04X})", u32::from(c))
}

/// Characters that need no quoting in a shell word or any scheduler's file.
fn is_plain(c: char) -> bool {
    c.is_ascii_alphanumeric() || "_./-+=:,@%".contains(c)
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
    /// `DIR` unquoted (as a path: see [`as_argument`]), to join file names to.
    dir_raw: String,
    name: String,
}

impl Words {
    fn of(jobs: &Jobs) -> Words {
        let name = jobs
            .campaign
            .file_stem()
            .map_or("campaign".into(), |s| s.to_string_lossy().into_owned());
        let dir_raw = as_argument(&jobs.dir);
        Words {
            campaign: quote(&as_argument(&jobs.campaign)),
            dir: quote(&dir_raw),
            dir_raw,
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

    /// Slurm's `--output` for a log in `DIR/logs/` (`%` is Slurm's own pattern character,
    /// `%%` a percent sign of the path), as a shell word.
    fn slurm_log(&self, file: &str) -> String {
        quote(&format!(
            "--output={}/logs/{file}",
            self.dir_raw.replace('%', "%%")
        ))
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

    /// Stops a job started from the wrong directory with a message saying which one. The
    /// paths are `printf`'s arguments, never part of its format or of a double-quoted text,
    /// so that nothing in them is expanded.
    fn check_directory(&self) -> String {
        format!(
            "if [ ! -f {c} ]; then\n  printf '%s not found in %s: submit from the directory \
             where the job files were written\\n' {c} \"$(pwd)\" >&2\n  exit 2\nfi\n",
            c = self.campaign
        )
    }
}

/// A path as a command's argument: a relative one starting with `-` or `+` gets `./` (it
/// would read as an option, or as GNU parallel's "append to the joblog").
fn as_argument(path: &Path) -> String {
    let text = path.display().to_string();
    if text.starts_with(['-', '+']) {
        format!("./{text}")
    } else {
        text
    }
}

/// `word` for a POSIX shell: as is when it has only safe characters, else single-quoted
/// (inside single quotes only `'` itself is special). The one quoting of the tool: the job
/// files, and the commands it prints for a user to run (`replay with:`, `submit ...`).
pub fn quote(word: &str) -> String {
    if !word.is_empty() && word.chars().all(is_plain) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

/// `text` in a `#` comment line: control characters (refused in paths by [`check`]) could
/// end the comment, so none is written as is.
fn comment(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}

fn header(what: &str, jobs: &Jobs, words: &Words) -> String {
    format!(
        "# {}: the campaign {} in {} shards.\n\
         # Written by `dynarole campaign --emit`; paths are relative to the directory it ran in:\n\
         # submit from there. DYNAROLE names the dynarole program if it is not on the PATH.\n",
        comment(what),
        comment(&words.campaign),
        jobs.shards
    )
}

fn slurm(jobs: &Jobs) -> Vec<JobFile> {
    let w = Words::of(jobs);
    // No path on an `#SBATCH` line: sbatch splits those lines by its own rules, not the
    // shell's. The logs are named on sbatch's command line in `submit.sh` instead.
    let shards = format!(
        "#!/bin/bash\n{}#SBATCH --job-name=dynarole-{}\n#SBATCH --array=0-{}%{}\n\
         #SBATCH --cpus-per-task={}\nset -euo pipefail\n{}exec {}\n",
        header("One Slurm array task per shard", jobs, &w),
        w.name,
        jobs.shards - 1,
        jobs.throttle,
        jobs.threads,
        w.check_directory(),
        w.shard(
            jobs,
            "${SLURM_ARRAY_TASK_ID}",
            "\"${SLURM_CPUS_PER_TASK:-1}\""
        ),
    );
    let merge = format!(
        "#!/bin/bash\n{}#SBATCH --job-name=dynarole-{}-merge\nset -euo pipefail\nexec {}\n",
        header(
            "The merge of the shards, once all of them succeeded",
            jobs,
            &w
        ),
        w.name,
        w.merge()
    );
    let submit = format!(
        "#!/bin/sh\n{}set -eu\nshards=$(sbatch --parsable {} {})\nshards=${{shards%%;*}}\n\
         merge=$(sbatch --parsable --dependency=afterok:\"$shards\" {} {})\n\
         merge=${{merge%%;*}}\necho \"shards: job $shards; merge: job $merge\"\n\
         printf 'progress: dynarole campaign status %s\\n' {}\n",
        header(
            "Submits the shards, then the merge once they all succeeded",
            jobs,
            &w
        ),
        w.slurm_log("shard-%a.out"),
        w.at("shards.sbatch"),
        w.slurm_log("merge.out"),
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
