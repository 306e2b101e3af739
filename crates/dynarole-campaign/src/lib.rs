//! dynarole-campaign: a sweep of simulated runs described as data (a TOML campaign file: the
//! program, the configurations, the protocols, a base scenario and the fault axes), run in
//! parallel, streamed to `runs.csv` (resumable), summarised in `summary.csv` and plotted.
//! See `README.md` for the file format and the outputs.

mod emit;
mod exec;
mod files;
mod inputs;
mod limits;
mod load;
mod plan;
mod plot;
mod progress;
mod results;
mod shard;
mod spec;
mod stats;
mod tables;

pub use dynarole_input::{read_limited, MAX_INPUT_BYTES};
pub use emit::{
    check as check_jobs, job_files, quote as shell_word, write as write_job_files, JobFile, Jobs,
    Scheduler,
};
pub use inputs::INPUTS_FILE;
pub use plan::{plan, Axis, Faults, Plan, PlannedRun, MAX_RUNS};
pub use plot::{bounds, rasterise_svg};
pub use progress::{Progress, Quiet};
pub use results::{Outcome, Row, COLUMNS};
pub use shard::{status, Shard, Status, CAMPAIGN_COPY, MAX_SHARDS};
pub use spec::{CampaignFile, ProtocolOptions, Range, SpecError, Sweep};
pub use stats::{median, summarise, wilson, PointSummary};

use dynarole_core::Diagnostic;
use dynarole_world::Robots;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Why a campaign could not run (runs that fail their goal are results, not errors).
#[derive(Debug)]
pub enum Error {
    /// A TOML file (the campaign file, or a robot plugin it loads) is wrong: the error names
    /// the field and its span in `text`.
    Spec {
        path: PathBuf,
        text: String,
        error: Box<SpecError>,
    },
    /// The `.dr` file has errors, or a sequence cannot be compiled for a protocol.
    Diagnostics {
        path: PathBuf,
        source: String,
        diagnostics: Vec<Diagnostic>,
    },
    /// A file that could not be read or written.
    Io(String),
    /// A configuration, plugin or sequence that does not fit.
    Input(String),
    /// The simulator could not build or run.
    Sim(String),
    /// `runs.csv` is unreadable or was written by another campaign.
    Results(String),
    Plot(String),
    /// The caller asked the runs to stop (`Progress::stop_requested`).
    Interrupted,
}

impl Error {
    fn io(path: &Path, e: std::io::Error) -> Error {
        Error::Io(format!("{}: {e}", path.display()))
    }
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Error::Spec { path, error, .. } => write!(f, "{}: {error}", path.display()),
            Error::Diagnostics { path, .. } => {
                write!(f, "{}: the program has errors", path.display())
            }
            Error::Io(m) | Error::Input(m) | Error::Sim(m) | Error::Results(m) => f.write_str(m),
            Error::Plot(m) => write!(f, "cannot draw {m}"),
            Error::Interrupted => f.write_str(
                "interrupted: the runs recorded so far are kept; run the campaign again to resume",
            ),
        }
    }
}

impl std::error::Error for Error {}

/// What `run` was asked to do.
#[derive(Clone, Debug)]
pub struct Options {
    pub campaign: PathBuf,
    pub out_dir: PathBuf,
    /// Do at most this many of the runs not yet recorded (then stop, resumable).
    pub max_runs: Option<u64>,
    /// Worker threads (default: one per core).
    pub jobs: Option<usize>,
    /// Draw the plots (SVG and PNG).
    pub plots: bool,
    /// Run only this shard (into `shard-K-of-N.csv`; no summary or plots).
    pub shard: Option<Shard>,
}

/// What a campaign did.
#[derive(Clone, Debug)]
pub struct Done {
    /// Runs in the campaign (or in the shard).
    pub total: u64,
    /// Runs found in `runs.csv` (or the shard's file) at the start.
    pub already: u64,
    /// Runs done now.
    pub ran: u64,
    /// Every recorded row, by run index.
    pub rows: Vec<Row>,
    /// None for a shard (summaries come from the merge).
    pub summaries: Vec<PointSummary>,
    /// `runs.csv`, `summary.csv` and the plots (for a shard: its results file).
    pub files: Vec<PathBuf>,
    pub wall_seconds: f64,
}

/// Runs (or resumes) the campaign described by `options.campaign`, writing into
/// `options.out_dir`: all of it, or only `options.shard`, its configurations of one of
/// `robots`; `progress` is told how the runs advance.
pub fn run(options: &Options, robots: &Robots, progress: &mut dyn Progress) -> Result<Done, Error> {
    let started = Instant::now();
    let sources = load::sources(&options.campaign, robots)?;
    let inputs = load::inputs(&sources)?;
    let planned = plan_of(&sources, inputs.campaign)?;
    std::fs::create_dir_all(&options.out_dir).map_err(|e| Error::io(&options.out_dir, e))?;
    let mut done = match options.shard {
        None => {
            let csv_path = options.out_dir.join("runs.csv");
            let campaign = (inputs.campaign, Some(inputs.preset.name));
            let before = recorded(&csv_path, &planned, campaign, None)?.rows;
            let what = format!("the {} runs of {}", before.len(), csv_path.display());
            let has_results = !before.is_empty();
            shard::keep_inputs(&options.out_dir, &inputs.fingerprint, has_results, &what)?;
            let run = (csv_path.as_path(), None, before, "");
            let (rows, already, ran) = execute(&inputs, &planned, run, options, progress)?;
            let (summaries, files) = write_outputs(&rows, &options.out_dir, options.plots)?;
            Done {
                total: planned.len(),
                already,
                ran,
                rows,
                summaries,
                files,
                wall_seconds: 0.0,
            }
        }
        Some(shard) => run_shard(&inputs, &planned, &sources.text, shard, options, progress)?,
    };
    done.wall_seconds = started.elapsed().as_secs_f64();
    Ok(done)
}

/// The number of runs of the campaign in `path`, after checking it as `run` would (the file,
/// the program, the configurations, the plan), without running anything.
pub fn count_runs(path: &Path, robots: &Robots) -> Result<u64, Error> {
    let sources = load::sources(path, robots)?;
    let inputs = load::inputs(&sources)?;
    Ok(plan_of(&sources, inputs.campaign)?.len())
}

/// `--emit`: checks the campaign as `run` would (so that a campaign that cannot run is refused
/// here, not in each of N jobs), keeps its copy and the record of its inputs in `jobs.dir` as
/// the first shard would (so that `status` works before any shard ran), and writes the job
/// files. Returns the number of runs and the files written.
pub fn emit(
    scheduler: Scheduler,
    jobs: &Jobs,
    robots: &Robots,
) -> Result<(u64, Vec<PathBuf>), Error> {
    emit::check(scheduler, jobs)?;
    let sources = load::sources(&jobs.campaign, robots)?;
    let inputs = load::inputs(&sources)?;
    let runs = plan_of(&sources, inputs.campaign)?.len();
    let dir = &jobs.dir;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    keep_split(dir, jobs.shards, &sources.text, &inputs.fingerprint)?;
    Ok((runs, emit::write(scheduler, jobs)?))
}

/// Checks that `dir` holds no shards of a split other than into `count`, and keeps the copy
/// of the campaign file (`text`) and the record of its inputs there, or checks them against
/// those of the shards already there.
fn keep_split(
    dir: &Path,
    count: u64,
    text: &str,
    fingerprint: &inputs::Fingerprint,
) -> Result<(), Error> {
    let found = shard::find(dir)?;
    if let Some(n) = found.count.filter(|&n| n != count) {
        return Err(Error::Results(format!(
            "{}: holds shards of a split into {n}, not {count}; write to another directory (-o)",
            dir.display()
        )));
    }
    let has_results = !found.files.is_empty();
    shard::keep_campaign(dir, text, has_results)?;
    let what = format!("the shards in {}", dir.display());
    shard::keep_inputs(dir, fingerprint, has_results, &what)
}

/// The plan of a loaded campaign; an error points into the campaign file.
fn plan_of(sources: &load::Sources, campaign: &CampaignFile) -> Result<Plan, Error> {
    plan::plan(campaign).map_err(|error| Error::Spec {
        path: sources.path.clone(),
        error: Box::new(error.locate(&sources.text)),
        text: sources.text.clone(),
    })
}

/// Runs what is left of `shard` (resuming its partial file), and once all of its runs are
/// recorded, writes them in run order to its finished file.
fn run_shard(
    inputs: &load::Inputs,
    planned: &Plan,
    text: &str,
    shard: Shard,
    options: &Options,
    progress: &mut dyn Progress,
) -> Result<Done, Error> {
    let dir = &options.out_dir;
    keep_split(dir, shard.count, text, &inputs.fingerprint)?;
    let finished = dir.join(shard.file_name());
    let partial = dir.join(shard.partial_name());
    if files::regular(&finished)? {
        // Checked and completed like a partial file (it may have been cut or edited).
        std::fs::rename(&finished, &partial).map_err(|e| Error::io(&partial, e))?;
    }
    let before = resumable(&partial, planned, inputs, shard)?;
    let preamble = inputs.fingerprint.to_text();
    let run = (partial.as_path(), Some(shard), before, preamble.as_str());
    let (rows, already, ran) = execute(inputs, planned, run, options, progress)?;
    let total = shard.size(planned.len());
    let mut files = vec![partial.clone()];
    if rows.len() as u64 == total {
        results::write_atomically(&finished, &rows, &preamble)?;
        std::fs::remove_file(&partial).map_err(|e| Error::io(&partial, e))?;
        files = vec![finished];
    }
    Ok(Done {
        total,
        already,
        ran,
        rows,
        summaries: Vec::new(),
        files,
        wall_seconds: 0.0,
    })
}

/// The rows of a shard's partial file that a resumed shard keeps: all of them when the file
/// records the inputs of this run, none when it holds no row (the file is started again, with
/// the record); an error naming what changed otherwise.
fn resumable(
    partial: &Path,
    planned: &Plan,
    inputs: &load::Inputs,
    shard: Shard,
) -> Result<Vec<Row>, Error> {
    let campaign = (inputs.campaign, Some(inputs.preset.name));
    let before = recorded(partial, planned, campaign, Some(shard))?;
    if before.rows.is_empty() {
        match std::fs::remove_file(partial) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(Error::io(partial, e))
            }
            _ => return Ok(Vec::new()),
        }
    }
    let changes = match &before.inputs {
        Some(recorded) => recorded.changes(&inputs.fingerprint),
        None => vec!["inputs it holds no record of (written by an older dynarole?)".into()],
    };
    if changes.is_empty() {
        return Ok(before.rows);
    }
    Err(Error::Results(format!(
        "{}: its {} runs were computed from {}; remove it to run shard {shard} again, or \
         write to another directory (-o)",
        partial.display(),
        before.rows.len(),
        changes.join("; ")
    )))
}

/// Where `execute` records: the results file, the shard (all runs when `None`), the rows
/// already checked in it, and what heads a new file (the record of the inputs, for a shard).
type Target<'a> = (&'a Path, Option<Shard>, Vec<Row>, &'a str);

/// Runs the runs of the target's shard not yet recorded in its file, at most
/// `options.max_runs` of them, appending each to it; returns every recorded row in run order,
/// how many were there before and how many ran now.
fn execute(
    inputs: &load::Inputs,
    planned: &Plan,
    (csv_path, shard, mut rows, preamble): Target<'_>,
    options: &Options,
    progress: &mut dyn Progress,
) -> Result<(Vec<Row>, u64, u64), Error> {
    let already = rows.len() as u64;
    let done: std::collections::BTreeSet<u64> = rows.iter().map(|r| r.run).collect();
    let pending: Vec<PlannedRun> = planned
        .iter()
        .filter(|r| shard.is_none_or(|s| s.holds(r.index)) && !done.contains(&r.index))
        .take(options.max_runs.map_or(usize::MAX, |n| n as usize))
        .collect();
    if !pending.is_empty() {
        exec::prepare(inputs)?;
    }
    let label = shard.map_or("campaign".to_string(), |s| format!("shard {s}"));
    let sink = results::Sink::open(csv_path, preamble)?;
    let total = shard.map_or(planned.len(), |s| s.size(planned.len()));
    // Counted against the runs this command may do (`--max-runs` stops before the end).
    let target = total.min(already + pending.len() as u64);
    let count = (label.as_str(), already, target);
    let new = exec::run_all(inputs, &pending, sink, options.jobs, progress, count)?;
    let ran = new.len() as u64;
    rows.extend(new);
    rows.sort_by_key(|r| r.run);
    Ok((rows, already, ran))
}

/// What `merge` was asked to do.
#[derive(Clone, Debug)]
pub struct MergeOptions {
    /// The directory of the shards' results.
    pub dir: PathBuf,
    /// Where to write the merged outputs.
    pub out_dir: PathBuf,
    pub plots: bool,
}

/// Checks that the shards in `options.dir` hold every run of their campaign exactly once,
/// then writes the same outputs as a one-machine run of it.
pub fn merge(options: &MergeOptions) -> Result<Done, Error> {
    let started = Instant::now();
    let (rows, inputs) = shard::merged_rows(&options.dir)?;
    std::fs::create_dir_all(&options.out_dir).map_err(|e| Error::io(&options.out_dir, e))?;
    // The merged runs.csv is bound to its inputs as a one-machine run's is.
    let record = options.out_dir.join(INPUTS_FILE);
    files::write_atomically(&record, &inputs.to_text())?;
    let (summaries, files) = write_outputs(&rows, &options.out_dir, options.plots)?;
    Ok(Done {
        total: rows.len() as u64,
        already: rows.len() as u64,
        ran: 0,
        rows,
        summaries,
        files,
        wall_seconds: started.elapsed().as_secs_f64(),
    })
}

/// The outputs of a campaign from its rows (in run order): `runs.csv`, `summary.csv`,
/// `summary.md` and the plots. A one-machine run and a merge of shards both write through
/// here, so that the same rows give the same bytes.
fn write_outputs(
    rows: &[Row],
    dir: &Path,
    plots: bool,
) -> Result<(Vec<PointSummary>, Vec<PathBuf>), Error> {
    let csv_path = dir.join("runs.csv");
    results::write_atomically(&csv_path, rows, "")?;
    let summaries = summarise(rows);
    let tables = dir.join("summary.md");
    std::fs::write(&tables, tables::markdown(&summaries)).map_err(|e| Error::io(&tables, e))?;
    let mut files = vec![csv_path, write_summary(&summaries, dir)?, tables];
    if plots {
        files.extend(plot::write_all(&summaries, dir)?);
    }
    Ok((summaries, files))
}

/// The rows already in `path`, each checked against the planned run of its index (and, for a
/// shard's file, against the shard), run under the network preset `preset` (`None` where the
/// robot is not loaded, as in a merge: the campaign's own, else the first row's for all).
fn recorded(
    path: &Path,
    planned: &plan::Plan,
    (campaign, preset): (&CampaignFile, Option<&str>),
    shard: Option<Shard>,
) -> Result<results::Recorded, Error> {
    let runs = shard.map_or(planned.len(), |s| s.size(planned.len()));
    let read = results::read_existing(path, files::results_bound(runs))?;
    let rows = &read.rows;
    let named = campaign.scenario.network.preset.0.as_deref();
    let first = rows.first().map(|r| r.preset.as_str());
    let preset = preset.or(named).or(first).unwrap_or_default();
    let timeout = campaign.scenario.timeout_ms;
    let mut seen = std::collections::BTreeSet::new();
    for row in rows {
        if let Some(s) = shard.filter(|s| !s.holds(row.run)) {
            return Err(Error::Results(format!(
                "{}: run {} does not belong to shard {s}",
                path.display(),
                row.run
            )));
        }
        let matches = planned
            .get(row.run)
            .is_some_and(|run| row.is_result_of(&run, preset, timeout));
        if !matches {
            return Err(Error::Results(format!(
                "{}: run {} was recorded with other parameters than this campaign's; \
                 write to another directory (-o) or remove the file",
                path.display(),
                row.run
            )));
        }
        if !seen.insert(row.run) {
            return Err(Error::Results(format!(
                "{}: run {} is recorded twice",
                path.display(),
                row.run
            )));
        }
    }
    Ok(read)
}

fn write_summary(summaries: &[PointSummary], dir: &Path) -> Result<PathBuf, Error> {
    let path = dir.join("summary.csv");
    let mut writer = csv::Writer::from_path(&path)
        .map_err(|e| Error::Results(format!("{}: {e}", path.display())))?;
    for s in summaries {
        writer
            .serialize(s)
            .map_err(|e| Error::Results(format!("{}: {e}", path.display())))?;
    }
    writer.flush().map_err(|e| Error::io(&path, e))?;
    Ok(path)
}
