//! The commands as functions that return values, for programs that embed dynarole (the Python
//! package in `python/`): the code the command line runs, its options parsed by the same
//! definitions, so that defaults and checks are decided in one place.

use crate::check::{check_one, CheckArgs};
use crate::simulate::{simulate_into, RunSink, SimulateArgs};
use clap::{Args, FromArgMatches};
use codespan_reporting::files::{Files, SimpleFile};
use dynarole_core::diagnostic::{has_errors, Severity};
use dynarole_core::Diagnostic;
use std::path::Path;

pub use crate::failure::Failure;
pub use crate::simulate::report_json;

/// One diagnostic of a `.dr` file, located by line and column (1-based, columns in
/// characters) as the command line shows it.
#[derive(Clone, Debug, PartialEq, Eq)]
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
    let usage = |e: clap::Error| Failure::Usage(e.render().to_string().trim_end().to_string());
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
