//! Golden cases: every `.dr` file in `tests/golden/` is checked (for the three protocols), and
//! when it has no errors also formatted and reversed; all output goes into one snapshot.

use codespan_reporting::term::termcolor::NoColor;
use dynarole_cli::check::{check_one, OnConfiguration};
use dynarole_cli::load::{self, PluginArgs};
use dynarole_cli::render::write_diagnostics;
use dynarole_codegen::Protocol;
use dynarole_core::diagnostic::{all_codes, has_errors, shown, DiagnosticCode};
use dynarole_core::format::{format_file, format_items};
use dynarole_core::{analyze, parse, Diagnostic};
use std::collections::BTreeSet;
use std::path::Path;

fn render(name: &str, source: &str, diagnostics: &[Diagnostic]) -> String {
    let mut out = NoColor::new(Vec::new());
    write_diagnostics(&mut out, name, source, diagnostics);
    String::from_utf8_lossy(&out.into_inner()).into_owned()
}

/// Check output for both protocols, then (for correct files) `fmt` and every reverse.
fn golden_output(path: &Path, source: &str, codes: &mut BTreeSet<DiagnosticCode>) -> String {
    let name = format!(
        "golden/{}",
        path.file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
    );
    let plugins = PluginArgs::default();
    let mut out = String::new();
    // A configuration beside the case (same name, `.json`) is used as `--from`.
    let config = path.with_extension("json");
    let on = config.is_file().then(|| OnConfiguration {
        path: &config,
        sequences: &[],
    });
    let lattice =
        check_one(path, source, &plugins, Protocol::Lattice, on.as_ref()).unwrap_or_default();
    let paper = check_one(path, source, &plugins, Protocol::Paper, on.as_ref()).unwrap_or_default();
    let token = check_one(path, source, &plugins, Protocol::Token, on.as_ref()).unwrap_or_default();
    codes.extend(
        [&lattice, &paper, &token]
            .into_iter()
            .flat_map(|d| shown(d))
            .map(|d| d.code()),
    );
    out.push_str(&section("check", &render(&name, source, &lattice)));
    if paper != lattice {
        out.push_str(&section(
            "check --protocol paper",
            &render(&name, source, &paper),
        ));
    }
    if token != lattice {
        out.push_str(&section(
            "check --protocol token",
            &render(&name, source, &token),
        ));
    }
    if has_errors(&lattice) {
        return out;
    }
    let parsed = parse(source);
    let formatted = format_file(&parsed.file, source);
    let fmt_text = if formatted == source {
        "(already formatted)\n".to_string()
    } else {
        formatted
    };
    out.push_str(&section("fmt", &fmt_text));
    out.push_str(&reverses(path, &parsed.file));
    out
}

fn reverses(path: &Path, file: &dynarole_core::ast::SourceFile) -> String {
    let Ok(registry) = load::registry(&PluginArgs::default(), path, load::robot_name(file)) else {
        return section("reverse", "(plugin failed to load)\n");
    };
    let (Some(program), _) = analyze(file, &registry) else {
        return String::new();
    };
    let mut out = String::new();
    for decl in file.sequences() {
        let name = &decl.name.name;
        let new_name = program.reverse_name(name);
        let text = match program.reverse_sequence(name, &new_name) {
            Some(Ok(decl)) => format_items(vec![dynarole_core::ast::Item::Sequence(decl)]),
            Some(Err(errors)) => format!("{} operation(s) without inverse\n", errors.len()),
            None => "missing\n".into(),
        };
        out.push_str(&section(&format!("reverse {name}"), &text));
    }
    out
}

fn section(title: &str, body: &str) -> String {
    let body = if body.is_empty() { "(nothing)\n" } else { body };
    format!("----- {title} -----\n{body}")
}

#[test]
fn golden_cases() {
    let mut codes = BTreeSet::new();
    insta::glob!("golden/*.dr", |path| {
        let source = std::fs::read_to_string(path).unwrap_or_default();
        let output = golden_output(path, &source, &mut codes);
        insta::assert_snapshot!(format!("{source}\n{output}"));
    });
    let missing: Vec<&str> = all_codes()
        .filter(|c| !codes.contains(c))
        .map(DiagnosticCode::name)
        .collect();
    assert!(
        missing.is_empty(),
        "diagnostic kinds with no golden case: {missing:?}"
    );
}
