//! `dynarole campaign`: a sweep of simulated runs described by a TOML file, run in parallel,
//! written to `DIR/runs.csv` (resumable), `DIR/summary.csv` and plots
//! (`crates/dynarole-campaign/README.md`); on a cluster, one shard per job, job files for the
//! schedulers, the merge and the status of the shards (`docs/cluster.md`).

use crate::load::Failure;
use crate::progress::{CampaignProgress, ProgressMode};
use dynarole_campaign::{Done, Error, Jobs, MergeOptions, Options, Progress, Scheduler};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// What `campaign` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct CampaignArgs {
    #[command(subcommand)]
    pub action: Option<Action>,
    /// The campaign file (TOML; see crates/dynarole-campaign/README.md).
    #[arg(required = true)]
    pub file: Option<std::path::PathBuf>,
    /// The output directory (default: out/NAME for NAME.toml).
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub out_dir: Option<std::path::PathBuf>,
    /// Do at most N of the runs not yet recorded, then stop (run again to go on).
    #[arg(long, value_name = "N", conflicts_with = "emit")]
    pub max_runs: Option<u64>,
    /// Worker threads (default: one per core; with --emit: per shard, default 1).
    #[arg(short = 'j', long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Write no plots.
    #[arg(long)]
    pub no_plots: bool,
    /// Run only shard K (from 0) of N into DIR/shard-K-of-N.csv (resumable); the split
    /// depends only on the campaign and N. Then `dynarole campaign merge DIR`.
    #[arg(long, value_name = "K/N", conflicts_with = "emit")]
    pub shard: Option<dynarole_campaign::Shard>,
    /// Write job files into DIR that run the campaign as --shards N shards on this
    /// scheduler, then merge them (docs/cluster.md).
    #[arg(long, value_enum, requires = "shards")]
    pub emit: Option<Emit>,
    /// With --emit: the number of shards.
    #[arg(long, value_name = "N", requires = "emit", value_parser = clap::value_parser!(u64).range(1..=dynarole_campaign::MAX_SHARDS))]
    pub shards: Option<u64>,
    /// With --emit: most shards running at once (default: all).
    #[arg(long, value_name = "T", requires = "emit", value_parser = clap::value_parser!(u64).range(1..))]
    pub throttle: Option<u64>,
}

/// The schedulers `--emit` writes job files for.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Emit {
    /// A Slurm array job (`sbatch`), then the merge as a dependent job.
    Slurm,
    /// An HTCondor cluster and the merge under a DAG (`condor_submit_dag`).
    Htcondor,
    /// A GNU parallel command list (inside an allocation or on one big machine).
    Parallel,
}

/// `--emit S --shards N --throttle T`.
pub struct EmitArgs {
    pub scheduler: Emit,
    pub shards: u64,
    pub throttle: u64,
}

/// The subcommands on a directory of shard results.
#[derive(clap::Subcommand)]
pub enum Action {
    /// Check that the shards in DIR hold every run exactly once (else name the missing shards
    /// and runs, exit 1), then write runs.csv, summary.csv, summary.md and the plots, byte for
    /// byte as a one-machine run does.
    Merge {
        /// The output directory of the shards (`--shard K/N -o DIR`).
        dir: PathBuf,
        /// Where to write the merged outputs (default: DIR).
        #[arg(short = 'o', long = "output", value_name = "OUT")]
        out_dir: Option<PathBuf>,
        /// Write no plots.
        #[arg(long)]
        no_plots: bool,
    },
    /// Count the runs the shards in DIR have recorded so far (reads only: jobs may be running).
    Status {
        /// The output directory of the shards.
        dir: PathBuf,
    },
}

pub fn run(args: &CampaignArgs) -> Result<ExitCode, Failure> {
    match (&args.action, &args.file) {
        (Some(action), _) => act(action),
        (None, Some(file)) => run_file(args, file),
        (None, None) => Err(Failure::Usage(
            "campaign: name a campaign file, or `merge DIR`, or `status DIR`".into(),
        )),
    }
}

/// `--emit S --shards N [--throttle T]`, when asked (clap makes --emit require --shards).
fn emit_args(args: &CampaignArgs) -> Option<EmitArgs> {
    args.emit
        .zip(args.shards)
        .map(|(scheduler, shards)| EmitArgs {
            scheduler,
            shards,
            throttle: args.throttle.unwrap_or(shards),
        })
}

fn run_file(args: &CampaignArgs, file: &Path) -> Result<ExitCode, Failure> {
    if let Some(emit) = &emit_args(args) {
        let out_dir = args
            .out_dir
            .clone()
            .unwrap_or_else(|| default_out_dir(file));
        return emit_jobs(args, file, emit, out_dir);
    }
    let mut progress = CampaignProgress::new(ProgressMode::for_stderr().map_err(Failure::Usage)?);
    let done = ran(args, file, &mut progress)?;
    print_done(&done);
    Ok(ExitCode::SUCCESS)
}

/// Runs the campaign `file` (or the shard `args` names), telling `progress`: what it did.
pub fn ran(args: &CampaignArgs, file: &Path, progress: &mut dyn Progress) -> Result<Done, Failure> {
    let options = Options {
        campaign: file.to_path_buf(),
        out_dir: args
            .out_dir
            .clone()
            .unwrap_or_else(|| default_out_dir(file)),
        max_runs: args.max_runs,
        jobs: args.jobs,
        plots: !args.no_plots,
        shard: args.shard,
    };
    dynarole_campaign::run(&options, crate::robots::robots(), progress).map_err(refused)
}

/// Prints what a merge did, or its error.
fn finish(result: Result<Done, Error>) -> Result<ExitCode, Failure> {
    let done = result.map_err(refused)?;
    print_done(&done);
    Ok(ExitCode::SUCCESS)
}

/// The failure of a campaign that cannot run: a sequence file's problems are
/// `Failure::Checked` (rendered, exit 1), as in every command.
fn refused(error: Error) -> Failure {
    match error {
        Error::Diagnostics {
            path,
            source,
            diagnostics,
        } => Failure::checked(&path.display().to_string(), &source, diagnostics),
        e => input_failure(e),
    }
}

/// `campaign merge DIR` and `campaign status DIR`.
fn act(action: &Action) -> Result<ExitCode, Failure> {
    match action {
        Action::Merge {
            dir,
            out_dir,
            no_plots,
        } => finish(dynarole_campaign::merge(&MergeOptions {
            dir: dir.clone(),
            out_dir: out_dir.clone().unwrap_or_else(|| dir.clone()),
            plots: !no_plots,
        })),
        Action::Status { dir } => {
            let status = dynarole_campaign::status(dir).map_err(input_failure)?;
            print_status(&status);
            Ok(ExitCode::SUCCESS)
        }
    }
}

fn input_failure(e: Error) -> Failure {
    match e {
        Error::Spec { path, text, error } => Failure::toml(&path, text, *error),
        other => Failure::Input(other.to_string()),
    }
}

/// `--emit`: the job files, and how to submit them.
fn emit_jobs(
    args: &CampaignArgs,
    file: &Path,
    emit: &EmitArgs,
    dir: PathBuf,
) -> Result<ExitCode, Failure> {
    if args.jobs == Some(0) {
        // The job files would ask the scheduler for no core at all.
        return Err(Failure::Usage(
            "campaign --emit: -j 0: each shard needs at least one worker thread; \
             -j N asks the scheduler for N cores per shard (default 1)"
                .into(),
        ));
    }
    let scheduler = match emit.scheduler {
        Emit::Slurm => Scheduler::Slurm,
        Emit::Htcondor => Scheduler::Htcondor,
        Emit::Parallel => Scheduler::Parallel,
    };
    let jobs = Jobs {
        campaign: file.to_path_buf(),
        dir,
        shards: emit.shards,
        throttle: emit.throttle,
        threads: args.jobs.unwrap_or(1),
    };
    // A campaign that cannot run is refused here, not in each of N jobs.
    let (runs, files) = match dynarole_campaign::emit(scheduler, &jobs, crate::robots::robots()) {
        Ok(done) => done,
        Err(e) => return Err(refused(e)),
    };
    for f in &files {
        println!("wrote {}", f.display());
    }
    // Printed for a user to paste into a shell: quoted as the job files quote.
    let first =
        |name: &str| dynarole_campaign::shell_word(&jobs.dir.join(name).display().to_string());
    let submit = match scheduler {
        Scheduler::Slurm => first("submit.sh"),
        Scheduler::Htcondor => format!("condor_submit_dag {}", first("campaign.dag")),
        Scheduler::Parallel => first("run.sh"),
    };
    println!(
        "{runs} runs in {} shards of {} or {} runs",
        emit.shards,
        runs / emit.shards,
        runs.div_ceil(emit.shards)
    );
    println!("submit from this directory: {submit}");
    println!(
        "progress: dynarole campaign status {}",
        dynarole_campaign::shell_word(&jobs.dir.display().to_string())
    );
    Ok(ExitCode::SUCCESS)
}

/// One line per shard, then the total.
fn print_status(status: &dynarole_campaign::Status) {
    for &(shard, done, size, finished) in &status.per_shard {
        let state = if finished {
            "finished"
        } else if done > 0 {
            "running or stopped"
        } else {
            "not started"
        };
        println!("shard {shard}: {done} of {size} runs, {state}");
    }
    let done = status.done();
    let percent = if status.total > 0 {
        100.0 * done as f64 / status.total as f64
    } else {
        100.0
    };
    let finished = status.per_shard.iter().filter(|s| s.3).count();
    let shards = match status.shards {
        Some(n) => format!("{finished} of {n} shards finished"),
        // Right after `--emit`: the split is known only once a shard has started.
        None => "no shard started yet".to_string(),
    };
    println!(
        "{done} of {} runs done ({percent:.1} %), {shards}",
        status.total
    );
}

/// `out/NAME` for `NAME.toml`: generated files stay under `out/`, which git ignores.
fn default_out_dir(file: &Path) -> PathBuf {
    let stem = file
        .file_stem()
        .map_or("campaign".into(), |s| s.to_string_lossy().into_owned());
    Path::new("out").join(stem)
}

fn print_done(done: &Done) {
    println!(
        "{} runs: {} recorded before, {} run now in {:.1} s, {} still to do",
        done.total,
        done.already,
        done.ran,
        done.wall_seconds,
        done.total - done.already - done.ran
    );
    if !done.summaries.is_empty() {
        print_table(&done.summaries);
    }
    for f in &done.files {
        println!("wrote {}", f.display());
    }
}

fn print_table(summaries: &[dynarole_campaign::PointSummary]) {
    println!(
        "{:<18} {:>8} {:<8} {:>5} {:>8} {:>15} {:>12} {:>9}",
        "axis", "value", "protocol", "runs", "success", "95 % interval", "median (s)", "packets"
    );
    for s in summaries {
        let median = s
            .median_completion_ms
            .map_or("-".into(), |t| format!("{:.3}", t / 1000.0));
        println!(
            "{:<18} {:>8} {:<8} {:>5} {:>7.1}% {:>15} {:>12} {:>9.0}",
            s.axis,
            s.value,
            s.protocol,
            s.runs,
            100.0 * s.success_rate,
            format!(
                "{:.1}-{:.1}%",
                100.0 * s.success_low,
                100.0 * s.success_high
            ),
            median,
            s.mean_packets_sent
        );
    }
}
