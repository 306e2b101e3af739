//! `dynarole verify`: the model checked (`model.rs` builds it), its report printed as it comes
//! (progress on stderr), its verdict turned into an exit code, and a counterexample recorded.

use crate::load::{self, Failure};
use crate::model::Asked;
use crate::model::{build, failed, with_request, Request, Scene};
use crate::progress::ProgressMode;
use dynarole_verify::{
    BuildOptions, Built, Entry, Header, Observer, Phase, Source, Verdict, VerifyOptions,
};
use indicatif::{ProgressBar, ProgressStyle};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// What `verify` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct VerifyArgs {
    /// The `.dr` file holding the sequences.
    pub file: std::path::PathBuf,
    /// Sequence to check; repeat to run several in turn (default: the first in the file).
    #[arg(long = "sequence", value_name = "NAME")]
    pub sequences: Vec<String>,
    /// The configuration to start from (JSON): modules, roles and who hears whom.
    #[arg(long, value_name = "CONFIG")]
    pub from: std::path::PathBuf,
    #[command(flatten)]
    pub options: crate::compile::ProtocolOptions,
    #[command(flatten)]
    pub model: crate::model::ModelArgs,
    /// Lattice protocol: how many times the whole sequence runs.
    #[arg(long, default_value_t = 1)]
    pub epochs: u16,
    /// Memory for each search (MB); beyond it the search falls back to bitstate hashing.
    #[arg(long, default_value_t = 4096, value_name = "MB")]
    pub memory: u64,
    /// Time for each search (seconds); beyond it the search falls back to bitstate hashing.
    #[arg(long, default_value_t = 600, value_name = "SECONDS")]
    pub time_limit: u64,
    /// Use bitstate hashing from the start (a partial search, never a proof).
    #[arg(long)]
    pub bitstate: bool,
    /// Check S1, S2 and S3 only (not L).
    #[arg(long)]
    pub safety_only: bool,
    /// Keep the model, spin's files and the trail in DIR.
    #[arg(long, value_name = "DIR")]
    pub keep: Option<std::path::PathBuf>,
    /// Check a deliberately broken lattice protocol (tests of the checker).
    #[arg(long, value_enum, hide = true)]
    pub fault: Option<crate::model::FaultArg>,
    #[command(flatten)]
    pub record: crate::view::RecordArgs,
    #[command(flatten)]
    pub plugins: crate::load::PluginArgs,
}

impl VerifyArgs {
    /// The model asked for, in the form `compile --target promela` gives it too.
    fn asked(&self) -> Asked<'_> {
        Asked {
            file: &self.file,
            plugins: &self.plugins,
            sequences: &self.sequences,
            from: &self.from,
            options: &self.options,
            model: &self.model,
            epochs: self.epochs,
        }
    }
}

pub fn run(args: &VerifyArgs) -> Result<ExitCode, Failure> {
    let verdict = verified(args, &mut Printer::default())?;
    print!("{verdict}");
    Ok(ExitCode::from(match verdict {
        Verdict::Verified => 0,
        Verdict::Violated => 1,
        Verdict::Inconclusive => 3,
    }))
}

/// The model of `args` built and checked, its report told to `observer` as it comes (a
/// counterexample recorded when asked); its verdict.
pub fn verified(args: &VerifyArgs, observer: &mut dyn Observer) -> Result<Verdict, Failure> {
    let asked = &args.asked();
    let protocol = asked
        .options
        .compile_options(asked.epochs, String::new())?
        .protocol;
    dynarole_verify::modelled(protocol).map_err(|e| Failure::Usage(e.to_string()))?;
    with_request(asked, |request| {
        let (built, options, scene) = build(request, args.fault)?;
        check(args, request, (&built, &options, &scene), observer)
    })
}

/// Checks the model in `--keep DIR` or a scratch directory (removed afterwards).
fn check(
    args: &VerifyArgs,
    request: &Request,
    (built, options, scene): (&Built, &BuildOptions, &Scene),
    observer: &mut dyn Observer,
) -> Result<Verdict, Failure> {
    let dir = match &args.keep {
        Some(d) => d.to_path_buf(),
        None => load::scratch_dir("verify"),
    };
    std::fs::create_dir_all(&dir)
        .map_err(|e| Failure::Internal(format!("cannot create {}: {e}", dir.display())))?;
    let header = dynarole_verify::header(built, options, &args.from.display().to_string());
    let verify = VerifyOptions {
        memory_mb: args.memory,
        time_s: args.time_limit,
        bitstate: args.bitstate,
        safety_only: args.safety_only,
    };
    let source = Source {
        path: request.display,
        text: request.source,
    };
    let report = dynarole_verify::verify(built, header, &verify, source, &dir, observer);
    if args.keep.is_none() {
        let _ = std::fs::remove_dir_all(&dir);
    }
    let report = report.map_err(|e| failed(e, request))?;
    if args.record.wanted() {
        record(&args.record, request, built, scene, &report)?;
    }
    Ok(report.verdict)
}

/// `--record`/`--html`: the counterexample's steps on the robot, the broken property marked
/// where it breaks; without a counterexample there is nothing to show (said on stderr).
fn record(
    args: &crate::view::RecordArgs,
    request: &Request,
    built: &Built,
    scene: &Scene,
    report: &dynarole_verify::Report,
) -> Result<(), Failure> {
    let Some(cx) = report.counterexample() else {
        eprintln!("note: no counterexample, so no recording was written");
        return Ok(());
    };
    let (steps, broken) = dynarole_verify::recorded::counterexample_steps(cx, &built.ir);
    let title = format!("counterexample of {} ({})", built.name, request.display);
    let mut notes = vec![format!("VIOLATED: {}", broken.join(", "))];
    notes.extend(cx.text.lines().map(str::to_string));
    let recording = dynarole_sim::ModelRecording {
        kind: "counterexample",
        title: &title,
        robot: &request.program.robot,
        steps: &steps,
        statements: &scene.statements,
        start: &scene.start,
        source: Some(dynarole_recording::Source {
            name: request.display,
            text: request.source,
        }),
    }
    .record(notes)
    .map_err(crate::view::model_failure)?;
    args.write(&recording)
}

/// Prints the report on stdout as it comes, and the progress of the tools on stderr.
#[derive(Default)]
struct Printer {
    /// The progress of the check whose tools run now.
    ticker: Option<Ticker>,
}

impl Observer for Printer {
    fn header(&mut self, header: &Header) {
        print!("{header}");
    }

    fn entry(&mut self, entry: &Entry) {
        print!("{entry}");
    }

    fn begin(&mut self, _label: &str) {
        self.ticker = Some(Ticker::new());
    }

    fn progress(&mut self, label: &str, phase: Phase, search: Option<(u64, u64)>) {
        if let Some(ticker) = &mut self.ticker {
            ticker.tick(label, phase, search);
        }
    }

    fn end(&mut self) {
        self.ticker = None;
    }
}

/// Progress of one check on stderr, shown as every long command shows it
/// (`crate::progress::ProgressMode`: a spinner on a terminal, otherwise a line every
/// `DYNAROLE_PROGRESS_SECONDS`, none when it is 0). Nothing goes to stdout, whose report stays
/// deterministic.
struct Ticker {
    started: Instant,
    last_line: Instant,
    /// Seconds between two lines; `None`: no lines (a spinner, or progress off).
    interval: Option<Duration>,
    spinner: Option<ProgressBar>,
}

impl Ticker {
    fn new() -> Ticker {
        // A bad interval does not stop a model-checking run: the default, with a warning.
        let mode = ProgressMode::for_stderr().unwrap_or_else(|e| {
            eprintln!("warning: {e}; progress every 10 s");
            ProgressMode::Lines {
                every: Duration::from_secs(10),
            }
        });
        let spinner = (mode == ProgressMode::Bar).then(|| {
            let bar = ProgressBar::new_spinner();
            if let Ok(style) = ProgressStyle::with_template("{spinner} {elapsed} {msg}") {
                bar.set_style(style);
            }
            bar.enable_steady_tick(Duration::from_millis(200));
            bar
        });
        let interval = match mode {
            ProgressMode::Lines { every } => Some(every),
            ProgressMode::Bar | ProgressMode::Off => None,
        };
        let now = Instant::now();
        Ticker {
            started: now,
            last_line: now,
            interval,
            spinner,
        }
    }

    fn tick(&mut self, label: &str, phase: Phase, search: Option<(u64, u64)>) {
        let figures = search.map_or(String::new(), |(states, depth)| {
            format!(", {states} states, depth {depth}")
        });
        let message = format!("{label}: {phase}{figures}");
        if let Some(bar) = &self.spinner {
            if bar.message() != message {
                bar.set_message(message);
            }
        } else if self
            .interval
            .is_some_and(|every| self.last_line.elapsed() >= every)
        {
            self.last_line = Instant::now();
            eprintln!(
                "progress: {message} ({} s)",
                self.started.elapsed().as_secs()
            );
        }
    }
}

impl Drop for Ticker {
    fn drop(&mut self) {
        if let Some(bar) = &self.spinner {
            bar.finish_and_clear();
        }
    }
}
