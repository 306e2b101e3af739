//! Printing diagnostics (with file, line, column and a source snippet) and failures.

use crate::load::Failure;
use codespan_reporting::diagnostic::{Diagnostic as Report, Label, Severity as ReportSeverity};
use codespan_reporting::files::SimpleFile;
use codespan_reporting::term::{
    self,
    termcolor::{ColorChoice, StandardStream, WriteColor},
};
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
    for diagnostic in diagnostics {
        let report = to_report(diagnostic);
        // A failing write to stderr leaves nothing better to report to.
        let _ = term::emit(out, &config, &file, &report);
    }
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
    eprintln!("error: {}", failure.message());
}
