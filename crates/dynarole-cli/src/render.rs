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

/// Longest line of a message printed whole. Messages quote what users wrote (a name, a
/// plugin's expression), and a hostile file can make that millions of bytes: the middle of a
/// longer line is left out, and said to be.
const MAX_MESSAGE_LINE: usize = 400;

/// `text` with the middle of each line longer than [`MAX_MESSAGE_LINE`] replaced by a note of
/// how much was left out. Every message the commands print goes through here.
pub fn elide(text: &str) -> String {
    text.split('\n')
        .map(elide_line)
        .collect::<Vec<_>>()
        .join("\n")
}

fn elide_line(line: &str) -> String {
    if line.len() <= MAX_MESSAGE_LINE {
        return line.to_string();
    }
    let head = floor_boundary(line, MAX_MESSAGE_LINE * 2 / 3);
    let tail = ceil_boundary(line, line.len() - MAX_MESSAGE_LINE / 4);
    format!(
        "{} [... {} bytes not shown ...] {}",
        &line[..head],
        tail - head,
        &line[tail..]
    )
}

fn floor_boundary(s: &str, mut at: usize) -> usize {
    while !s.is_char_boundary(at) {
        at -= 1;
    }
    at
}

fn ceil_boundary(s: &str, mut at: usize) -> usize {
    while !s.is_char_boundary(at) {
        at += 1;
    }
    at
}

fn to_report(diagnostic: &Diagnostic) -> Report<()> {
    let d = diagnostic.describe();
    let severity = match d.severity {
        Severity::Error => ReportSeverity::Error,
        Severity::Warning => ReportSeverity::Warning,
    };
    let mut labels =
        vec![Label::primary((), diagnostic.span.range()).with_message(elide(&d.label))];
    for (span, text) in d.secondary {
        labels.push(Label::secondary((), span.range()).with_message(elide(&text)));
    }
    let notes = d
        .hint
        .map(|h| vec![elide(&format!("hint: {h}"))])
        .unwrap_or_default();
    Report::new(severity)
        .with_code(d.code)
        .with_message(elide(&d.title))
        .with_labels(labels)
        .with_notes(notes)
}

pub fn failure(failure: &Failure) {
    let writer = StandardStream::stderr(color_choice());
    write_failure(&mut writer.lock(), failure);
}

/// Writes `failure` as the command line shows it on standard error, to any writer (the
/// library API keeps it as the text of its error).
pub fn write_failure(out: &mut dyn WriteColor, failure: &Failure) {
    // A failing write to stderr leaves nothing better to report to.
    let _ = match failure {
        Failure::Input(message) | Failure::Usage(message) => {
            writeln!(out, "error: {}", elide(message))
        }
        Failure::Internal(message) => writeln!(out, "internal error: {}", elide(message)),
        Failure::Toml { path, text, error } => {
            write_toml_error(out, path, text, error);
            Ok(())
        }
        Failure::Checked {
            path,
            source,
            diagnostics: found,
            conclusion,
        } => {
            write_diagnostics(out, path, source, found);
            match conclusion {
                Some(message) => writeln!(out, "error: {}", elide(message)),
                None => Ok(()),
            }
        }
    };
}

/// For an error on a TOML line too long to print: where it is, in words.
fn toml_place_too_long(file: &SimpleFile<&str, &str>, at: usize) -> Option<String> {
    let line = file.line_index((), at).ok()?;
    let range = file.line_range((), line).ok()?;
    if range.len() <= MAX_SHOWN_LINE {
        return None;
    }
    let column = file.column_number((), line, at).ok()?;
    Some(format!(
        "at {}:{}:{column} (the line is longer than {MAX_SHOWN_LINE} bytes and is not shown)",
        file.name(),
        line + 1
    ))
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
    let message = elide(&error.to_string());
    let mut notes = Vec::new();
    let report = match span {
        Some(span) => match toml_place_too_long(&file, span.start) {
            Some(place) => {
                notes.push(place);
                Report::error().with_message(message)
            }
            None => Report::error()
                .with_message(message)
                .with_labels(vec![Label::primary((), span)]),
        },
        None => Report::error().with_message(elide(&format!("{path}: {error}"))),
    };
    notes.extend(error.hint.as_ref().map(|h| elide(&format!("hint: {h}"))));
    if term::emit(
        out,
        &term::Config::default(),
        &file,
        &report.with_notes(notes),
    )
    .is_err()
    {
        // Nothing better to report to than the plain message.
        let _ = writeln!(out, "error: {}", elide(&format!("{path}: {error}")));
    }
}

#[cfg(test)]
mod tests {
    use super::elide;

    #[test]
    fn long_lines_lose_their_middle_and_short_ones_nothing() {
        assert_eq!(elide("short\nlines"), "short\nlines");
        // Two-byte characters: the cuts fall on character boundaries.
        let long = "é".repeat(1_000);
        let shown = elide(&format!("first\n{long}\nlast"));
        let lines: Vec<&str> = shown.lines().collect();
        assert_eq!(lines[0], "first");
        assert_eq!(lines[2], "last");
        assert!(lines[1].len() < 500, "{}", lines[1].len());
        assert!(lines[1].contains("bytes not shown"), "{}", lines[1]);
    }
}
