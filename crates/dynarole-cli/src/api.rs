//! The commands as functions that return values, for programs that embed dynarole (the Python
//! package in `python/`): the code the command line runs, its options parsed by the same
//! definitions, so that defaults and checks are decided in one place. Values are JSON, with
//! the fields the command line's `--json` (or its printed lines) show.

use crate::campaign::CampaignArgs;
use crate::check::{check_one, CheckArgs};
use crate::parallelise::ParalleliseArgs;
use crate::replay::ReplayArgs;
use crate::simulate::{simulate_into, RunSink, SimulateArgs};
use crate::verify::VerifyArgs;
use clap::{Args, FromArgMatches};
use codespan_reporting::files::{Files, SimpleFile};
use dynarole_core::diagnostic::{has_errors, Severity};
use dynarole_core::Diagnostic;
use serde_json::{json, Value};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

pub use dynarole_campaign::Progress;

pub use crate::failure::Failure;
pub use crate::simulate::report_json;

/// One diagnostic of a `.dr` file, located by line and column (1-based, columns in
/// characters) as the command line shows it.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Located {
    pub file: String,
    pub line: usize,
    pub column: usize,
    /// The kebab-case name of its kind, such as `unknown-label`.
    pub code: &'static str,
    /// `error` or `warning`.
    pub severity: &'static str,
    pub message: String,
    /// What the caret of the rendered snippet says.
    pub label: String,
    pub hint: Option<String>,
}

/// `diagnostics` of the file `path` whose text is `source`, located, in the order the command
/// line shows them.
pub fn locate(path: &str, source: &str, diagnostics: &[Diagnostic]) -> Vec<Located> {
    let file = SimpleFile::new(path, source);
    dynarole_core::diagnostic::shown(diagnostics)
        .into_iter()
        .map(|d| {
            let at = d.span.range().start.min(source.len());
            let location = file.location((), at).ok();
            let described = d.describe();
            Located {
                file: path.to_string(),
                line: location.as_ref().map_or(1, |l| l.line_number),
                column: location.as_ref().map_or(1, |l| l.column_number),
                code: described.code,
                severity: match described.severity {
                    Severity::Error => "error",
                    Severity::Warning => "warning",
                },
                message: described.title,
                label: described.label,
                hint: described.hint,
            }
        })
        .collect()
}

/// Options as the command line takes them after the subcommand's name (`argv`), parsed by
/// that subcommand's definitions; a usage error is clap's message.
fn parse<T: Args + FromArgMatches>(command: &'static str, argv: &[String]) -> Result<T, Failure> {
    let cli = T::augment_args(clap::Command::new(command).no_binary_name(true));
    // clap's text starts with the `error: ` every failure is printed with.
    let usage = |e: clap::Error| {
        let text = e.render().to_string();
        Failure::Usage(text.trim_start_matches("error: ").trim_end().to_string())
    };
    let matches = cli.try_get_matches_from(argv).map_err(usage)?;
    T::from_arg_matches(&matches).map_err(usage)
}

/// `dynarole check ARGV...` for one file: every diagnostic, errors and warnings (a file that
/// cannot be read or a configuration that cannot be used is a `Failure`).
pub fn check(argv: &[String]) -> Result<Vec<Located>, Failure> {
    let args: CheckArgs = parse("check", argv)?;
    let [path] = args.files.as_slice() else {
        return Err(Failure::Usage("check takes one file".into()));
    };
    let source = crate::load::read_source(path)?;
    let on = args
        .from
        .as_deref()
        .map(|from| crate::check::OnConfiguration {
            path: from,
            sequences: &args.sequences,
        });
    let diagnostics = check_one(path, &source, &args.plugins, args.protocol, on.as_ref())?;
    let display = path.display().to_string();
    if has_errors(&diagnostics) {
        return Err(Failure::checked(&display, &source, diagnostics));
    }
    Ok(locate(&display, &source, &diagnostics))
}

/// `dynarole reverse FILE SEQUENCE`: the text the command prints.
pub fn reverse(
    path: &Path,
    sequence: &str,
    name: Option<&str>,
    plugins: &[std::path::PathBuf],
) -> Result<String, Failure> {
    let plugins = crate::load::PluginArgs {
        plugins: plugins.to_vec(),
    };
    crate::reverse::reverse_text(path, sequence, name, &plugins)
}

/// `dynarole simulate ARGV... --json`: each run's report as the command prints it, handed to
/// `each` as it ends (an error from `each`, such as an interrupt, ends the simulation).
pub fn simulate(
    argv: &[String],
    each: &mut dyn FnMut(serde_json::Value) -> Result<(), Failure>,
) -> Result<(), Failure> {
    let args: SimulateArgs = parse("simulate", argv)?;
    let mut sink = Collected { each };
    simulate_into(&args, &mut sink).map(|_| ())
}

/// The library's sink: every report as its JSON value.
struct Collected<'a> {
    each: &'a mut dyn FnMut(serde_json::Value) -> Result<(), Failure>,
}

impl RunSink for Collected<'_> {
    fn report(
        &mut self,
        _args: &SimulateArgs,
        (report, firmware): (&dynarole_sim::Report, Option<&dynarole_sim::FirmwareReport>),
        _wall: f64,
        _k: u64,
    ) -> Result<(), Failure> {
        (self.each)(report_json(report, firmware)?)
    }
}

/// `dynarole replay ARGV...`: the sequences run on the model. `steps`: each statement as run
/// (after any reversal) with its source line; `diagnostics`: the refused statements (errors)
/// and the warnings; `matches_expected` and `difference` with `--expect`.
pub fn replay(argv: &[String]) -> Result<Value, Failure> {
    let args: ReplayArgs = parse("replay", argv)?;
    crate::load::with_program(&args.file, &args.plugins, |program, source| {
        let found = crate::replay::replayed_on(&args, program, source)?;
        let display = args.file.display().to_string();
        let file = SimpleFile::new(display.as_str(), source);
        let steps: Vec<Value> = (found.prepared.statements().iter())
            .map(|s| {
                let line = file.location((), s.span.range().start.min(source.len()));
                json!({
                    "statement": s.describe(&program.robot),
                    "line": line.map_or(1, |l| l.line_number),
                })
            })
            .collect();
        let compared = found.expected.as_ref().map(|(_, c)| c);
        Ok(json!({
            "sequences": found.prepared.names,
            "statements": found.result.n_statements,
            "rejected": found.result.n_rejected,
            "diagnostics": locate(&display, source, &found.diagnostics),
            "steps": steps,
            "final_configuration": configuration_value(&found.final_configuration)?,
            "matches_expected": compared.map(Result::is_ok),
            "difference": compared.and_then(|c| c.as_ref().err()).map(ToString::to_string),
        }))
    })
}

/// A configuration as the JSON object of its data file.
fn configuration_value(c: &dynarole_world::Configuration) -> Result<Value, Failure> {
    serde_json::from_str(&c.to_json_string())
        .map_err(|e| Failure::Internal(format!("a configuration's JSON does not read back: {e}")))
}

/// `dynarole parallelise ARGV...`: the `.dr` file it writes (`text`), the new sequence's name,
/// statements and groups, and the critical path before and after (`null` where it cannot be
/// estimated, the reason in `not_estimated`).
pub fn parallelise(argv: &[String]) -> Result<Value, Failure> {
    let args: ParalleliseArgs = parse("parallelise", argv)?;
    let found = crate::parallelise::found(&args)?;
    if let Some(path) = &args.out {
        std::fs::write(path, &found.text)
            .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))?;
    }
    let reasons: Vec<&String> = [&found.before, &found.after]
        .into_iter()
        .filter_map(|e| e.as_ref().err())
        .collect();
    Ok(json!({
        "text": found.text,
        "name": found.name,
        "statements": found.statements,
        "groups": found.groups,
        "critical_path_before_ms": found.before.as_ref().ok(),
        "critical_path_after_ms": found.after.as_ref().ok(),
        "not_estimated": reasons,
    }))
}

/// `dynarole verify ARGV...`: `verdict` (`verified`, `violated`, `inconclusive`) and `report`,
/// the text the command prints on standard output.
pub fn verify(argv: &[String]) -> Result<Value, Failure> {
    verify_until(argv, &AtomicBool::new(false))
}

/// [`verify`], stopped (the tool running killed, an `interrupted:` failure) once `stop` is set.
pub fn verify_until(argv: &[String], stop: &AtomicBool) -> Result<Value, Failure> {
    let args: VerifyArgs = parse("verify", argv)?;
    let mut report = Reported {
        text: String::new(),
        stop,
    };
    let verdict = crate::verify::verified(&args, &mut report)?;
    let name = match verdict {
        dynarole_verify::Verdict::Verified => "verified",
        dynarole_verify::Verdict::Violated => "violated",
        dynarole_verify::Verdict::Inconclusive => "inconclusive",
    };
    report.text.push_str(&verdict.to_string());
    Ok(json!({ "verdict": name, "report": report.text }))
}

/// The report of a check kept as the text the command line prints, and whether the caller
/// asks the check to stop.
struct Reported<'s> {
    text: String,
    stop: &'s AtomicBool,
}

impl dynarole_verify::Observer for Reported<'_> {
    fn stop_requested(&mut self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    fn header(&mut self, header: &dynarole_verify::Header) {
        self.text.push_str(&header.to_string());
    }

    fn entry(&mut self, entry: &dynarole_verify::Entry) {
        self.text.push_str(&entry.to_string());
    }
}

/// `dynarole campaign FILE ARGV...`: the runs done, told to `progress` as they end (its
/// `stop_requested` interrupts them, keeping the runs recorded); the files written (`runs.csv`
/// first), the runs in the campaign, found at the start and done now.
pub fn campaign(argv: &[String], progress: &mut dyn Progress) -> Result<Value, Failure> {
    let args: CampaignArgs = parse("campaign", argv)?;
    let (None, Some(file), None) = (&args.action, &args.file, args.emit) else {
        return Err(Failure::Usage(
            "campaign here runs a campaign file: not merge, status or --emit".into(),
        ));
    };
    let done = crate::campaign::ran(&args, file, progress)?;
    let files: Vec<String> = done.files.iter().map(|f| f.display().to_string()).collect();
    Ok(json!({
        "total": done.total,
        "already": done.already,
        "ran": done.ran,
        "files": files,
        "wall_seconds": done.wall_seconds,
    }))
}

/// What the command line prints on standard error for `failure` (no colours).
pub fn failure_text(failure: &Failure) -> String {
    let mut out = codespan_reporting::term::termcolor::NoColor::new(Vec::new());
    crate::render::write_failure(&mut out, failure);
    String::from_utf8_lossy(&out.into_inner())
        .trim_end()
        .to_string()
}

/// The viewer's page (the file `--html` writes) of the recording at `path`.
pub fn view_html(path: &Path) -> Result<String, Failure> {
    let text = dynarole_input::read_recording(path).map_err(|e| Failure::Input(e.to_string()))?;
    let recording = dynarole_recording::Recording::from_json(&text)
        .map_err(|e| Failure::Input(format!("{}: {e}", path.display())))?;
    dynarole_viewer::html(&recording).map_err(Failure::Internal)
}
