//! `dynarole verify` and `compile --target promela`: the arguments turned into
//! `dynarole_verify`'s options, its report printed as it comes (progress on stderr), its
//! errors turned into exit codes, and the model files written.

use crate::compile::ProtocolOptions;
use crate::load::{self, Failure, PluginArgs};
use crate::render;
use crate::world::{prepare, read_configuration};
use dynarole_campaign::ProgressMode;
use dynarole_codegen::Fault;
use dynarole_verify::{
    BuildOptions, Built, Entry, Event, Header, Inputs, Method, Models, Observer, Phase, Source,
    Verdict, VerifyError, VerifyOptions,
};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// The bounds of the environment, shared by `verify` and `compile --target promela`.
#[derive(Clone, Debug, clap::Args)]
pub struct ModelArgs {
    /// Module resets, at most, in a run (any module, at any moment, mid-operation included).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub resets: u8,
    /// Only this module may reset (its name in the configuration); may be repeated.
    #[arg(long = "reset-only", value_name = "MODULE")]
    pub reset_only: Vec<String>,
    /// Packets that can be in flight at once and be delivered late (again and again, so also
    /// duplicated and reordered). Losses are not bounded: any packet may be lost.
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub late: u8,
    /// How to model the robot: `full` (every module's logic and every link), `compositional`
    /// (lattice only: one model per module, every packet any state the robot has reached;
    /// scales to large robots), `auto` (compositional for the lattice protocol on more than
    /// three modules).
    #[arg(long, value_enum, default_value_t = MethodArg::Auto)]
    pub method: MethodArg,
}

/// How the robot is modelled (see docs/verification.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodArg {
    Auto,
    Full,
    Compositional,
}

/// A deliberately broken lattice protocol (for the tests of the checker itself).
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum FaultArg {
    /// The join drops the other copy's done bit of the lowest incomplete statement.
    JoinDropsDone,
    /// The join raises the low-water mark without re-basing the bits.
    JoinNoRebase,
}

/// What `verify` was asked to do.
pub struct VerifyArgs<'a> {
    pub file: &'a Path,
    pub sequences: &'a [String],
    pub from: &'a Path,
    pub options: &'a ProtocolOptions,
    pub model: &'a ModelArgs,
    pub epochs: u16,
    pub memory_mb: u64,
    pub time_s: u64,
    pub bitstate: bool,
    pub safety_only: bool,
    pub keep: Option<&'a Path>,
    pub fault: Option<FaultArg>,
    pub record: &'a crate::view::RecordArgs,
    pub plugins: &'a PluginArgs,
}

/// What a counterexample's recording is drawn on: the statements as lowered (the model's
/// statement numbers) and the start configuration.
struct Scene {
    statements: Vec<dynarole_core::check::ResolvedStatement>,
    start: dynarole_world::Configuration,
}

/// What a model is made from: a checked source, its sequences, a configuration, options.
pub struct Request<'a> {
    pub program: &'a dynarole_core::Program<'a>,
    pub source: &'a str,
    pub display: &'a str,
    pub sequences: &'a [String],
    pub from: &'a Path,
    pub options: &'a ProtocolOptions,
    pub model: &'a ModelArgs,
    pub epochs: u16,
}

/// The library's options for these arguments; the model is named after `names`.
fn build_options(
    req: &Request,
    names: &[String],
    fault: Option<FaultArg>,
) -> Result<BuildOptions, Failure> {
    Ok(BuildOptions {
        compile: req.options.compile_options(req.epochs, names.join(" + "))?,
        method: match req.model.method {
            MethodArg::Auto => Method::Auto,
            MethodArg::Full => Method::Full,
            MethodArg::Compositional => Method::Compositional,
        },
        resets: req.model.resets,
        reset_only: req.model.reset_only.clone(),
        late: req.model.late,
        fault: fault.map(|f| match f {
            FaultArg::JoinDropsDone => Fault::JoinDropsDone,
            FaultArg::JoinNoRebase => Fault::JoinNoRebase,
        }),
    })
}

/// The exit code or failure of a library error; the source's problems are rendered here.
fn failed(error: VerifyError, req: &Request) -> Result<ExitCode, Failure> {
    match error {
        VerifyError::Source(diagnostics) => {
            render::diagnostics(req.display, req.source, &diagnostics);
            Ok(ExitCode::from(1))
        }
        VerifyError::Input(m) => Err(Failure::Input(m)),
        VerifyError::Usage(m) => Err(Failure::Usage(m)),
        VerifyError::Internal(m) => Err(Failure::Internal(m)),
    }
}

/// Reads the configuration, expands the sequences and models them. `Err(code)` inside: the
/// problem was rendered as a diagnostic of the source.
fn build(
    req: &Request,
    fault: Option<FaultArg>,
) -> Result<Result<(Built, BuildOptions, Scene), ExitCode>, Failure> {
    let config = read_configuration(req.from)?;
    let prepared = match prepare(req.program, req.display, req.sequences, config)? {
        Ok(p) => p,
        Err(diagnostics) => {
            render::diagnostics(req.display, req.source, &diagnostics);
            return Ok(Err(ExitCode::from(1)));
        }
    };
    let options = build_options(req, &prepared.names, fault)?;
    let configuration = req.from.display().to_string();
    let inputs = Inputs {
        program: req.program,
        names: &prepared.names,
        plans: &prepared.plans,
        assignment: &prepared.assignment,
        world: &prepared.world,
        configuration: &configuration,
    };
    let scene = Scene {
        statements: prepared
            .plans
            .iter()
            .flat_map(|p| p.statements().into_iter().cloned())
            .collect(),
        start: prepared.start.clone(),
    };
    match dynarole_verify::build(&inputs, &options) {
        Ok(built) => Ok(Ok((built, options, scene))),
        Err(e) => failed(e, req).map(Err),
    }
}

pub fn run(args: &VerifyArgs) -> Result<ExitCode, Failure> {
    let protocol = args
        .options
        .compile_options(args.epochs, String::new())?
        .protocol;
    dynarole_verify::modelled(protocol).map_err(|e| Failure::Usage(e.to_string()))?;
    load::with_program(args.file, args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let request = Request {
            program,
            source,
            display: &display,
            sequences: args.sequences,
            from: args.from,
            options: args.options,
            model: args.model,
            epochs: args.epochs,
        };
        match build(&request, args.fault)? {
            Ok((built, options, scene)) => check(args, &request, &built, &options, &scene),
            Err(code) => Ok(code),
        }
    })
}

/// Checks the model in `--keep DIR` or a scratch directory (removed afterwards), printing
/// the report as it comes; the exit code of its verdict.
fn check(
    args: &VerifyArgs,
    request: &Request,
    built: &Built,
    options: &BuildOptions,
    scene: &Scene,
) -> Result<ExitCode, Failure> {
    let dir = match args.keep {
        Some(d) => d.to_path_buf(),
        None => scratch_dir(),
    };
    std::fs::create_dir_all(&dir)
        .map_err(|e| Failure::Internal(format!("cannot create {}: {e}", dir.display())))?;
    let header = dynarole_verify::header(built, options, &args.from.display().to_string());
    let verify = VerifyOptions {
        memory_mb: args.memory_mb,
        time_s: args.time_s,
        bitstate: args.bitstate,
        safety_only: args.safety_only,
    };
    let source = Source {
        path: request.display,
        text: request.source,
    };
    let report = dynarole_verify::verify(
        built,
        header,
        &verify,
        source,
        &dir,
        &mut Printer::default(),
    );
    if args.keep.is_none() {
        let _ = std::fs::remove_dir_all(&dir);
    }
    let report = match report {
        Ok(report) => report,
        Err(e) => return failed(e, request),
    };
    if args.record.wanted() {
        record(args.record, request, built, scene, &report)?;
    }
    let verdict = report.verdict;
    print!("{verdict}");
    Ok(ExitCode::from(match verdict {
        Verdict::Verified => 0,
        Verdict::Violated => 1,
        Verdict::Inconclusive => 3,
    }))
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
    use crate::view::Step;
    let Some(cx) = report.counterexample() else {
        eprintln!("note: no counterexample, so no recording was written");
        return Ok(());
    };
    let name = |m: &usize| cx.module_names.get(*m).cloned().unwrap_or_default();
    let mut broken = Vec::new();
    let steps: Vec<Step> = cx
        .events
        .iter()
        .enumerate()
        .filter_map(|(k, e)| match e {
            Event::Issue { m, s, .. } => Some(Step::Issue(*s, name(m))),
            Event::Done { m, s } => Some(Step::Done(*s, name(m))),
            Event::Reset { m } => Some(Step::Reset(name(m))),
            Event::Copy { m, .. } => Some(Step::Copy(name(m), cx.copies.get(&k)?.clone())),
            Event::Violation { property, m, s } => {
                broken.push(property.clone());
                let text = built
                    .ir
                    .statements
                    .get(*s)
                    .map_or("", |st| st.text.as_str());
                Some(Step::Violation(
                    name(m),
                    format!("#{s} {text}: {property} broken here"),
                ))
            }
            _ => None,
        })
        .collect();
    let title = format!("counterexample of {} ({})", built.name, request.display);
    let mut notes = vec![format!("VIOLATED: {}", broken.join(", "))];
    notes.extend(cx.text.lines().map(str::to_string));
    let recording = crate::view::ModelRun {
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
    .record(notes)?;
    args.write(&recording)
}

fn scratch_dir() -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    std::env::temp_dir().join(format!("dynarole-verify-{}-{nanos}", std::process::id()))
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
/// (`dynarole_campaign::ProgressMode`: a spinner on a terminal, otherwise a line every
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

/// `dynarole compile --target promela`: writes DIR/model.pml (the compositional method:
/// DIR/model-MODULE.pml for each module).
pub fn write_model(req: &Request, out_dir: &Path) -> Result<ExitCode, Failure> {
    let (built, _, _) = match build(req, None)? {
        Ok(b) => b,
        Err(code) => return Ok(code),
    };
    std::fs::create_dir_all(out_dir)
        .map_err(|e| Failure::Input(format!("cannot create {}: {e}", out_dir.display())))?;
    let mut written = Vec::new();
    for (name, model) in built.model_files() {
        let path = out_dir.join(name);
        std::fs::write(&path, &model.text)
            .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))?;
        written.push(path.display().to_string());
    }
    let what = match built.models {
        Models::Full(_) => "model",
        Models::Compositional { .. } => "compositional models",
    };
    println!(
        "{what} of {}: {} statements, {} modules, {} links -> {}",
        built.name,
        built.ir.statements.len(),
        built.topology.modules.len(),
        built.topology.links.len(),
        written.join(", ")
    );
    Ok(ExitCode::SUCCESS)
}
