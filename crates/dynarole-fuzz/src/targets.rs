//! The fuzz targets: what each one runs on an input, and the properties it checks.

use dynarole_campaign::{plan, CampaignFile};
use dynarole_core::format::format_file;
use dynarole_core::{analyze, parse, Diagnostic, RobotApi, RobotRegistry};
use dynarole_sim::Scenario;
use dynarole_world::Configuration;
use std::path::Path;

/// Error text allowed on top of what is proportional to the input (a loader may quote the
/// offending line or name; a diagnostic may quote a token).
pub const ERROR_BASE_BYTES: usize = 4096;
/// Diagnostic text allowed per byte of source in [`Mode::Guarded`]: today every unknown
/// character is its own diagnostic (a title, a label and a hint).
pub const GUARDED_DIAGNOSTIC_BYTES_PER_INPUT_BYTE: usize = 256;
/// Diagnostic text allowed per byte of source in [`Mode::Hostile`]: a run of unknown
/// characters must not flood the output with one diagnostic per byte.
pub const DIAGNOSTIC_BYTES_PER_INPUT_BYTE: usize = 16;
/// Campaigns with more seeds than this are parsed but not planned in [`Mode::Guarded`]:
/// planning allocates one run per seed, and the limit on `seeds` has not landed yet.
pub const GUARDED_MAX_SEEDS: u64 = 1000;
/// Plugins with a part `count` above this are not loaded in [`Mode::Guarded`]: the loader
/// names every index before it checks the count, and the fix has not landed yet.
pub const GUARDED_MAX_PLUGIN_COUNT: i64 = 1 << 16;

/// A fuzz target; its name is its corpus folder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// Lexer and parser.
    Parse,
    /// Parser, checker, expansion, reversal and lowering to the IR.
    Check,
    /// The formatter: what parses cleanly formats to text that parses cleanly and formats
    /// to itself.
    Format,
    /// The configuration JSON loader, and writing a configuration back.
    Configuration,
    /// The scenario TOML loader.
    Scenario,
    /// The campaign TOML loader and the planning of its runs.
    Campaign,
    /// The robot plugin TOML loader, and a source naming the loaded robot.
    Plugin,
}

/// Which inputs may reach the code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Inputs that reach a path still waiting for its size limit (see the `GUARDED_*`
    /// constants) are counted as deferred instead of run.
    Guarded,
    /// Everything runs, as it will once the limits land.
    Hostile,
}

/// What became of an input that broke no property.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    Accepted,
    Rejected,
    /// Not run in [`Mode::Guarded`].
    Deferred,
}

/// What the targets share: the robots a source may name.
pub struct Context {
    pub registry: RobotRegistry,
}

impl Context {
    /// The built-in robots plus every plugin of `plugins` that loads (so the checker's corpus
    /// can use a custom robot).
    pub fn new(plugins: &[String]) -> Context {
        let mut registry = RobotRegistry::builtin();
        for text in plugins {
            if let Ok(api) = RobotApi::from_toml(text) {
                registry.add(api);
            }
        }
        Context { registry }
    }
}

/// Numeric extremes that blow-ups substitute into inputs.
pub const EXTREMES: &[&str] = &[
    "0",
    "-1",
    "1",
    "255",
    "256",
    "65535",
    "65536",
    "-65536",
    "0.0",
    "-0.0",
    "1e-300",
    "1e308",
    "0.999999999999",
    "nan",
    "inf",
    "-inf",
    "4294967295",
    "4294967296",
    "2147483648",
    "-2147483649",
    "1000000000",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775809",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999999",
    "1e999",
];

const SOURCE_WORDS: &[&str] = &[
    "robot",
    "atron",
    "mtran",
    "role",
    "requires",
    "sequence",
    "reverse",
    "{",
    "}",
    ";",
    "&",
    "&&",
    "|",
    "||",
    "!",
    "=",
    "==",
    "!=",
    "<",
    ">=",
    "(",
    ")",
    "[",
    "]",
    ",",
    ".",
    "-",
    "M0",
    "M3",
    "Connector",
    "Joint",
    "extend",
    "retract",
    "rotateFromToBy",
    "rotateToBy",
    "$CONNECTOR_0",
    "$CONNECTOR",
    "$JOINT_NORTH",
    "true",
    "false",
    "id",
    "connected",
    "joint",
    "neighbours",
    "neighbour_id",
    "/* c */",
    "// c\n",
    "/*",
    "*/",
    "@",
    "\u{e9}",
    "\n",
    "\t",
];

const TOML_WORDS: &[&str] = &[
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    "=",
    "\"",
    "'",
    "'''",
    "\"\"\"",
    ",",
    ".",
    "#",
    "\n",
    "true",
    "false",
    "nan",
    "inf",
    "-",
    "+",
    "_",
    "1979-05-27T07:32:00Z",
    "\\u0000",
    "[scenario]",
    "[network]",
    "[timing]",
    "[[block]]",
    "[[part]]",
    "[[part.operation]]",
    "[sweep]",
    "[options]",
    "name",
    "count",
    "male",
    "inverse",
    "seeds",
    "first_seed",
    "protocols",
    "\"lattice\"",
    "\"token-32\"",
    "loss",
    "step",
    "from",
    "to",
    "module",
    "connector",
    "from_ms",
    "to_ms",
    "timeout_ms",
    "\u{e9}",
];

const JSON_WORDS: &[&str] = &[
    "{",
    "}",
    "[",
    "]",
    ":",
    ",",
    "\"",
    "null",
    "true",
    "false",
    "-",
    "1e999",
    "\\u0000",
    "\"name\"",
    "\"id\"",
    "\"position\"",
    "\"orientation\"",
    "\"modules\"",
    "\"connections\"",
    "\"robot\"",
    "\"ATRON\"",
    "\"MTRAN\"",
    "\"joint\"",
    "\"spin\"",
    "\"axis\"",
    "\"M0\"",
    "\u{e9}",
];

impl Target {
    pub const ALL: [Target; 7] = [
        Target::Parse,
        Target::Check,
        Target::Format,
        Target::Configuration,
        Target::Scenario,
        Target::Campaign,
        Target::Plugin,
    ];

    /// The corpus folder's name.
    pub fn name(self) -> &'static str {
        match self {
            Target::Parse => "parse",
            Target::Check => "check",
            Target::Format => "format",
            Target::Configuration => "configuration",
            Target::Scenario => "scenario",
            Target::Campaign => "campaign",
            Target::Plugin => "plugin",
        }
    }

    /// Tokens that token insertions pick from.
    pub fn vocabulary(self) -> &'static [&'static str] {
        match self {
            Target::Parse | Target::Check | Target::Format => SOURCE_WORDS,
            Target::Configuration => JSON_WORDS,
            Target::Scenario | Target::Campaign | Target::Plugin => TOML_WORDS,
        }
    }

    /// Runs `text` through the target; `Err` names the property it broke.
    pub fn run(self, ctx: &Context, text: &str, mode: Mode) -> Result<Outcome, String> {
        match self {
            Target::Parse => front_end(text, mode),
            Target::Check => check(ctx, text, mode),
            Target::Format => format(text, mode),
            Target::Configuration => configuration(text),
            Target::Scenario => loader(text, Scenario::from_toml_str(text).map(|_| ())),
            Target::Campaign => campaign(text, mode),
            Target::Plugin => plugin(ctx, text, mode),
        }
    }
}

fn front_end(text: &str, mode: Mode) -> Result<Outcome, String> {
    let parsed = parse(text);
    well_formed(text, &parsed.diagnostics, mode)?;
    Ok(verdict(parsed.diagnostics.is_empty()))
}

fn verdict(clean: bool) -> Outcome {
    if clean {
        Outcome::Accepted
    } else {
        Outcome::Rejected
    }
}

fn check(ctx: &Context, text: &str, mode: Mode) -> Result<Outcome, String> {
    let parsed = parse(text);
    let (program, mut diagnostics) = analyze(&parsed.file, &ctx.registry);
    diagnostics.extend(parsed.diagnostics.iter().cloned());
    well_formed(text, &diagnostics, mode)?;
    let Some(program) = program else {
        return Ok(Outcome::Rejected);
    };
    for decl in parsed.file.sequences() {
        let name = &decl.name.name;
        if let Some(plan) = program.expand(name) {
            if let Err(d) = plan.flatten_for_paper() {
                well_formed(text, &[d], mode)?;
            }
            match program.lower(std::slice::from_ref(&plan)) {
                Ok(ir) => {
                    let waits: Vec<Vec<u16>> =
                        ir.statements.iter().map(|s| s.waits_for()).collect();
                    let _ = (waits, ir.dependents(), ir.paper_layout());
                }
                Err(limit) => span_inside(text, limit.span.start, limit.span.end)?,
            }
        }
        if let Some(Err(errors)) = program.reverse_sequence(name, "reversed") {
            well_formed(text, &errors, mode)?;
        }
    }
    Ok(verdict(diagnostics.is_empty()))
}

fn format(text: &str, mode: Mode) -> Result<Outcome, String> {
    let parsed = parse(text);
    well_formed(text, &parsed.diagnostics, mode)?;
    if !parsed.diagnostics.is_empty() {
        return Ok(Outcome::Rejected);
    }
    let formatted = format_file(&parsed.file, text);
    let reparsed = parse(&formatted);
    if let Some(d) = reparsed.diagnostics.first() {
        return Err(format!(
            "formatting made a valid file invalid ({}):\n{formatted}",
            d.describe().title
        ));
    }
    let again = format_file(&reparsed.file, &formatted);
    if again != formatted {
        return Err(format!(
            "formatting is not idempotent:\n{formatted}\n--- formatted again ---\n{again}"
        ));
    }
    Ok(Outcome::Accepted)
}

fn configuration(text: &str) -> Result<Outcome, String> {
    let config = match Configuration::from_json_str(text) {
        Ok(config) => config,
        Err(e) => return loader(text, Err(format!("{}: {}", e.path, e.message))),
    };
    let written = config.to_json_string();
    match Configuration::from_json_str(&written) {
        Ok(back) if back == config => Ok(Outcome::Accepted),
        Ok(_) => Err(format!(
            "written back, the configuration differs:\n{written}"
        )),
        Err(e) => Err(format!(
            "written back, the configuration does not load ({}: {}):\n{written}",
            e.path, e.message
        )),
    }
}

fn campaign(text: &str, mode: Mode) -> Result<Outcome, String> {
    let campaign = match CampaignFile::parse(text, Path::new("campaigns")) {
        Ok(campaign) => campaign,
        Err(e) => return loader(text, Err(e)),
    };
    if mode == Mode::Guarded && campaign.seeds > GUARDED_MAX_SEEDS {
        return Ok(Outcome::Deferred);
    }
    let runs = match plan(&campaign) {
        Ok(runs) => runs,
        Err(e) => return loader(text, Err(e)),
    };
    match runs.iter().enumerate().find(|(i, r)| r.index != *i as u64) {
        Some((i, r)) => Err(format!("planned run {i} has index {}", r.index)),
        None => Ok(Outcome::Accepted),
    }
}

fn plugin(ctx: &Context, text: &str, mode: Mode) -> Result<Outcome, String> {
    if mode == Mode::Guarded && plugin_count_above(text, GUARDED_MAX_PLUGIN_COUNT) {
        return Ok(Outcome::Deferred);
    }
    let api = match RobotApi::from_toml(text) {
        Ok(api) => api,
        Err(e) => return loader(text, Err(e)),
    };
    // The loaded robot must be usable by the checker: a file naming it checks cleanly.
    let source = format!("robot {};\n", api.name);
    let mut registry = ctx.registry.clone();
    registry.add(api);
    let parsed = parse(&source);
    let (_, diagnostics) = analyze(&parsed.file, &registry);
    match parsed.diagnostics.iter().chain(&diagnostics).next() {
        Some(d) => Err(format!(
            "a loaded plugin is refused by the checker: {}\n{source}",
            d.describe().title
        )),
        None => Ok(Outcome::Accepted),
    }
}

/// Whether some `[[part]]` of a plugin's TOML has a `count` above `bound`.
fn plugin_count_above(text: &str, bound: i64) -> bool {
    let Ok(table) = text.parse::<toml::Table>() else {
        return false;
    };
    let Some(parts) = table.get("part").and_then(|p| p.as_array()) else {
        return false;
    };
    parts
        .iter()
        .filter_map(|p| p.get("count").and_then(|c| c.as_integer()))
        .any(|c| c > bound)
}

/// A loader's result: accepted, or refused with an error of bounded size.
fn loader<E: std::fmt::Display>(text: &str, result: Result<(), E>) -> Result<Outcome, String> {
    let Err(e) = result else {
        return Ok(Outcome::Accepted);
    };
    let message = e.to_string();
    if message.trim().is_empty() {
        return Err("an empty error message".into());
    }
    let limit = ERROR_BASE_BYTES + text.len();
    if message.len() > limit {
        return Err(format!(
            "an error of {} bytes for an input of {} (limit {limit})",
            message.len(),
            text.len()
        ));
    }
    Ok(Outcome::Rejected)
}

/// Diagnostics point inside the source at character boundaries and their text is bounded.
fn well_formed(text: &str, diagnostics: &[Diagnostic], mode: Mode) -> Result<(), String> {
    let mut total = 0usize;
    for d in diagnostics {
        let description = d.describe();
        span_inside(text, d.span.start, d.span.end)?;
        for (span, label) in &description.secondary {
            span_inside(text, span.start, span.end)?;
            total += label.len();
        }
        total += description.title.len()
            + description.label.len()
            + description.hint.as_ref().map_or(0, String::len);
    }
    let per_byte = match mode {
        Mode::Guarded => GUARDED_DIAGNOSTIC_BYTES_PER_INPUT_BYTE,
        Mode::Hostile => DIAGNOSTIC_BYTES_PER_INPUT_BYTE,
    };
    let limit = ERROR_BASE_BYTES + per_byte * text.len();
    if total > limit {
        return Err(format!(
            "{} diagnostics, {total} bytes of text, for {} bytes of source (limit {limit})",
            diagnostics.len(),
            text.len()
        ));
    }
    Ok(())
}

fn span_inside(text: &str, start: u32, end: u32) -> Result<(), String> {
    let (start, end) = (start as usize, end as usize);
    let inside = start <= end && end <= text.len();
    if inside && text.is_char_boundary(start) && text.is_char_boundary(end) {
        return Ok(());
    }
    Err(format!(
        "span {start}..{end} is not a character range of the {}-byte source",
        text.len()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynarole_core::{DiagnosticKind, Span};

    fn unknown(start: u32, end: u32) -> Diagnostic {
        Diagnostic {
            kind: DiagnosticKind::UnknownCharacter { found: '@' },
            span: Span { start, end },
        }
    }

    #[test]
    fn spans_must_be_character_ranges_of_the_source() {
        let text = "robot \u{e9};";
        assert!(span_inside(text, 6, 8).is_ok());
        assert!(span_inside(text, 7, 8).is_err(), "inside a character");
        assert!(span_inside(text, 3, 2).is_err(), "reversed");
        assert!(span_inside(text, 0, 100).is_err(), "past the end");
    }

    #[test]
    fn diagnostic_floods_break_the_hostile_bound_only() {
        let text = "@".repeat(3000);
        let flood: Vec<Diagnostic> = (0..3000).map(|i| unknown(i, i + 1)).collect();
        assert!(well_formed(&text, &flood, Mode::Guarded).is_ok());
        assert!(well_formed(&text, &flood, Mode::Hostile).is_err());
        assert!(well_formed(&text, &[unknown(0, 3000)], Mode::Hostile).is_ok());
    }

    #[test]
    fn loader_errors_must_be_bounded_and_say_something() {
        assert_eq!(loader("x", Ok::<(), String>(())), Ok(Outcome::Accepted));
        assert_eq!(loader("x", Err("bad")), Ok(Outcome::Rejected));
        assert!(loader("x", Err("  ")).is_err());
        assert!(loader("x", Err("e".repeat(ERROR_BASE_BYTES + 2))).is_err());
    }

    #[test]
    fn guards_defer_only_what_waits_for_a_limit() {
        let big = "name = \"g\"\n[[part]]\nname = \"P\"\ncount = 70000\n";
        let ctx = Context::new(&[]);
        assert_eq!(
            Target::Plugin.run(&ctx, big, Mode::Guarded),
            Ok(Outcome::Deferred)
        );
        assert_eq!(
            Target::Plugin.run(&ctx, big, Mode::Hostile),
            Ok(Outcome::Rejected)
        );
    }
}
