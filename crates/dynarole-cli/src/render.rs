//! Printing diagnostics (with file, line, column and a source snippet) and failures.

use crate::failure::Failure;
use codespan_reporting::diagnostic::{Diagnostic as Report, Label, Severity as ReportSeverity};
use codespan_reporting::files::{Files, SimpleFile};
use codespan_reporting::term::{
    self,
    termcolor::{ColorChoice, StandardStream, WriteColor},
};
use dynarole_core::toml_error::TomlError;
use dynarole_core::{Diagnostic, Severity};
use std::io::IsTerminal;

fn color_choice() -> ColorChoice {
    if std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none() {
        ColorChoice::Auto
    } else {
        ColorChoice::Never
    }
}

/// Writes `diagnostics` of one source file to standard error.
pub fn diagnostics(path: &str, source: &str, diagnostics: &[Diagnostic]) {
    let writer = StandardStream::stderr(color_choice());
    let mut lock = writer.lock();
    write_diagnostics(&mut lock, path, source, diagnostics);
}

/// Writes `diagnostics` to any writer (tests use a plain buffer).
pub fn write_diagnostics(
    out: &mut dyn WriteColor,
    path: &str,
    source: &str,
    diagnostics: &[Diagnostic],
) {
    let file = SimpleFile::new(path, source);
    let config = term::Config::default();
    for diagnostic in dynarole_core::diagnostic::shown(diagnostics) {
        let mut report = to_report(&diagnostic);
        if let Some(place) = too_long_to_show(&file, &diagnostic) {
            report.labels.clear();
            report.notes.insert(0, place);
        }
        // A failing write to stderr leaves nothing better to report to.
        let _ = term::emit(out, &config, &file, &report);
    }
}

/// Longest source line printed under a message; a longer one is named, not printed, so that
/// the output of a hostile file stays small.
const MAX_SHOWN_LINE: usize = 300;

/// For a diagnostic on a line too long to print: where it is, in words.
fn too_long_to_show(file: &SimpleFile<&str, &str>, diagnostic: &Diagnostic) -> Option<String> {
    let d = diagnostic.describe();
    let spans = std::iter::once(diagnostic.span).chain(d.secondary.iter().map(|(s, _)| *s));
    let line_of = |at: u32| {
        let line = file.line_index((), at as usize).ok()?;
        let range = file.line_range((), line).ok()?;
        Some((line, range))
    };
    let long = spans
        .filter_map(|span| line_of(span.start))
        .any(|(_, range)| range.len() > MAX_SHOWN_LINE);
    if !long {
        return None;
    }
    let at = diagnostic.span.start as usize;
    let (line, _) = line_of(diagnostic.span.start)?;
    let column = file.column_number((), line, at).ok()?;
    Some(format!(
        "at {}:{}:{column}: {} (the line is longer than {MAX_SHOWN_LINE} bytes and is not shown)",
        file.name(),
        line + 1,
        d.label
    ))
}

fn to_report(diagnostic: &Diagnostic) -> Report<()> {
    let d = diagnostic.describe();
    let severity = match d.severity {
        Severity::Error => ReportSeverity::Error,
        Severity::Warning => ReportSeverity::Warning,
    };
    let mut labels = vec![Label::primary((), diagnostic.span.range()).with_message(d.label)];
    for (span, text) in d.secondary {
        labels.push(Label::secondary((), span.range()).with_message(text));
    }
    let notes = d
        .hint
        .map(|h| vec![format!("hint: {h}")])
        .unwrap_or_default();
    Report::new(severity)
        .with_code(d.code)
        .with_message(d.title)
        .with_labels(labels)
        .with_notes(notes)
}

pub fn failure(failure: &Failure) {
    match failure {
        Failure::Input(message) | Failure::Usage(message) => eprintln!("error: {message}"),
        Failure::Internal(message) => eprintln!("internal error: {message}"),
        Failure::Toml { path, text, error } => {
            let writer = StandardStream::stderr(color_choice());
            write_toml_error(&mut writer.lock(), path, text, error);
        }
    }
}

/// Writes an error of the TOML file `path` like a `.dr` diagnostic: file, line and column, the
/// snippet with a caret under the field's value, and the hint; with no span, the file and field.
pub fn write_toml_error(out: &mut dyn WriteColor, path: &str, text: &str, error: &TomlError) {
    let file = SimpleFile::new(path, text);
    let span = error
        .span
        .clone()
        .filter(|s| s.start <= s.end && text.get(s.clone()).is_some())
        .map(|s| {
            // A missing value's span runs to the next line; the caret belongs on this one.
            let trimmed = text[s.clone()].trim_end();
            s.start..s.start + trimmed.len()
        });
    let report = match span {
        Some(span) => Report::error()
            .with_message(error.to_string())
            .with_labels(vec![Label::primary((), span)]),
        None => Report::error().with_message(format!("{path}: {error}")),
    };
    let notes = error
        .hint
        .as_ref()
        .map(|h| vec![format!("hint: {h}")])
        .unwrap_or_default();
    if term::emit(
        out,
        &term::Config::default(),
        &file,
        &report.with_notes(notes),
    )
    .is_err()
    {
        // Nothing better to report to than the plain message.
        let _ = writeln!(out, "error: {path}: {error}");
    }
}
