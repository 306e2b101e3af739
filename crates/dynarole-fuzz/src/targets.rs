//! The fuzz targets: what each one runs on an input, and the properties it checks.

use dynarole_campaign::{plan, CampaignFile};
use dynarole_core::diagnostic::MAX_SHOWN;
use dynarole_core::format::format_file;
use dynarole_core::{analyze, driver, parse, Diagnostic, RobotApi, RobotRegistry};
use dynarole_sim::Scenario;
use std::convert::Infallible;
use std::path::Path;
use std::sync::OnceLock;

/// Error text allowed on top of what is proportional to the input (a loader may quote the
/// offending line or name; a diagnostic may quote a token).
pub const ERROR_BASE_BYTES: usize = 4096;
/// Text allowed per shown diagnostic (title, label, hint), besides what it may quote.
pub const DIAGNOSTIC_BYTES: usize = 256;
/// Quoted text allowed per byte of source, over all shown diagnostics: a diagnostic that
/// quotes the whole source, shown fifty times, breaks it.
pub const DIAGNOSTIC_BYTES_PER_INPUT_BYTE: usize = 16;

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
    /// A planner's plan file, imported by the robot whose planners' format its content is
    /// (`Robots::import_plan`: reading, the steps and their sweeps), and read as one
    /// configuration (`--from`).
    Plan,
}

/// What became of an input that broke no property.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    Accepted,
    Rejected,
}

/// What the targets share: the robots a source may name.
pub struct Context {
    pub registry: RobotRegistry,
}

impl Context {
    /// The built-in robots plus every plugin of `plugins` that loads (so the checker's corpus
    /// can use a custom robot).
    pub fn new(plugins: &[String]) -> Context {
        let loaded = plugins
            .iter()
            .filter_map(|text| RobotApi::from_toml(text).ok());
        let built_in = dynarole_robots::plugins();
        let registry = driver::registry(built_in, None, loaded, |_| Ok::<_, Infallible>(None));
        match registry {
            Ok(registry) => Context { registry },
            Err(never) => match never {},
        }
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

/// Words of the language (and near misses) that mutations insert and token soup is made of;
/// the robots' names come after the first (`source_words`).
pub const SOURCE_WORDS: &[&str] = &[
    "robot",
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

/// [`SOURCE_WORDS`] with every built-in robot's name after `robot`.
fn source_words() -> &'static [&'static str] {
    static WORDS: OnceLock<Vec<&'static str>> = OnceLock::new();
    WORDS.get_or_init(|| {
        let names = dynarole_robots::BUILT_IN.iter().map(|k| k.name());
        with_after_first(SOURCE_WORDS, names)
    })
}

/// [`JSON_WORDS`] with every built-in robot's `robot` field value (quoted) after `"robot"`.
fn json_words() -> &'static [&'static str] {
    static TAGS: OnceLock<Vec<String>> = OnceLock::new();
    static WORDS: OnceLock<Vec<&'static str>> = OnceLock::new();
    WORDS.get_or_init(|| {
        let tags = TAGS.get_or_init(|| {
            (dynarole_robots::BUILT_IN.iter())
                .map(|k| format!("\"{}\"", k.file_tag()))
                .collect()
        });
        let at = JSON_WORDS
            .iter()
            .position(|w| *w == "\"robot\"")
            .map_or(0, |i| i + 1);
        let (before, after) = JSON_WORDS.split_at(at);
        before
            .iter()
            .copied()
            .chain(tags.iter().map(String::as_str))
            .chain(after.iter().copied())
            .collect()
    })
}

/// `words` with `inserted` after its first word.
fn with_after_first(
    words: &'static [&'static str],
    inserted: impl Iterator<Item = &'static str>,
) -> Vec<&'static str> {
    let (first, rest) = words.split_at(words.len().min(1));
    first
        .iter()
        .copied()
        .chain(inserted)
        .chain(rest.iter().copied())
        .collect()
}

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
    "\"joint\"",
    "\"spin\"",
    "\"axis\"",
    "\"M0\"",
    "\u{e9}",
];

impl Target {
    pub const ALL: [Target; 8] = [
        Target::Parse,
        Target::Check,
        Target::Format,
        Target::Configuration,
        Target::Scenario,
        Target::Campaign,
        Target::Plugin,
        Target::Plan,
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
            Target::Plan => "plan",
        }
    }

    /// Tokens that token insertions pick from.
    pub fn vocabulary(self) -> &'static [&'static str] {
        match self {
            Target::Parse | Target::Check | Target::Format => source_words(),
            Target::Configuration => json_words(),
            Target::Plan => PLAN_WORDS,
            Target::Scenario | Target::Campaign | Target::Plugin => TOML_WORDS,
        }
    }

    /// Runs `text` through the target; `Err` names the property it broke.
    pub fn run(self, ctx: &Context, text: &str) -> Result<Outcome, String> {
        match self {
            Target::Parse => front_end(text),
            Target::Check => check(ctx, text),
            Target::Format => format(text),
            Target::Configuration => configuration(text),
            Target::Scenario => loader(text, Scenario::from_toml_str(text).map(|_| ())),
            Target::Campaign => campaign(text),
            Target::Plugin => plugin(ctx, text),
            Target::Plan => planner_plan(text),
        }
    }
}

fn front_end(text: &str) -> Result<Outcome, String> {
    let parsed = parse(text);
    well_formed(text, &parsed.diagnostics)?;
    Ok(verdict(parsed.diagnostics.is_empty()))
}

fn verdict(clean: bool) -> Outcome {
    if clean {
        Outcome::Accepted
    } else {
        Outcome::Rejected
    }
}

fn check(ctx: &Context, text: &str) -> Result<Outcome, String> {
    let parsed = parse(text);
    let (program, diagnostics) = driver::analyze_all(&parsed, &ctx.registry);
    well_formed(text, &diagnostics)?;
    let Some(program) = program else {
        return Ok(Outcome::Rejected);
    };
    for decl in parsed.file.sequences() {
        let name = &decl.name.name;
        if let Some(plan) = program.expand(name) {
            if let Err(d) = plan.flatten_for_paper() {
                well_formed(text, &[d])?;
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
            well_formed(text, &errors)?;
        }
    }
    Ok(verdict(diagnostics.is_empty()))
}

fn format(text: &str) -> Result<Outcome, String> {
    let parsed = parse(text);
    well_formed(text, &parsed.diagnostics)?;
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
    let config = match dynarole_robots::read_configuration(text) {
        Ok(config) => config,
        Err(e) => return loader(text, Err(format!("{}: {}", e.path, e.message))),
    };
    let written = config.to_json_string();
    match dynarole_robots::read_configuration(&written) {
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

/// Tokens of the planners' formats the robots import (text lines and JSON worlds).
const PLAN_WORDS: &[&str] = &[
    "C",
    "M",
    "E",
    "A",
    "B",
    "+X",
    "-X",
    "-Z",
    "N",
    "E",
    "S",
    "W",
    "#",
    "length",
    "queue",
    "cfgs",
    "CUBE",
    "*",
    ",",
    "//",
    "\n\n",
    "\n",
    "\r\n",
    "\"modules\"",
    "\"moduleJoints\"",
    "\"spaceJoints\"",
    "\"universal\"",
    "\"A-X\"",
    "\"B+X\"",
    "\"North\"",
    "\"bodies\"",
    "\"body_dir\"",
    "\"axis\"",
    "\"is_positive\"",
    "\"joint_pos\"",
    "\"pos\"",
    "\"shoe_rotated\"",
    "\"Z\"",
    "true",
    "false",
    "90",
    "-90",
    "180",
    "1e999",
];

/// A plan read as the content says, by the robot whose planners' format it is, and the same
/// text as one configuration: no panic, an error of bounded size.
fn planner_plan(text: &str) -> Result<Outcome, String> {
    let robots = dynarole_robots::robots();
    let imported = match robots.import_plan(text, "plan", &dynarole_world::ImportOptions::default())
    {
        Some(result) => result.map(|_| ()).map_err(|e| e.to_string()),
        None => Err("no robot's planners write this format".to_string()),
    };
    let outcome = loader(text, imported)?;
    loader(text, robots.read_configuration(text).map(|_| ()))?;
    Ok(outcome)
}

fn campaign(text: &str) -> Result<Outcome, String> {
    let campaign = match CampaignFile::parse(text, Path::new("campaigns")) {
        Ok(campaign) => campaign,
        Err(e) => return loader(text, Err(e)),
    };
    let runs = match plan(&campaign) {
        Ok(runs) => runs,
        Err(e) => return loader(text, Err(e)),
    };
    // The plan is computed run by run: probe its first thousand runs and its last one.
    let n = runs.len();
    for i in (0..n.min(1000)).chain(n.checked_sub(1)) {
        match runs.get(i) {
            Some(r) if r.index == i => {}
            Some(r) => return Err(format!("planned run {i} has index {}", r.index)),
            None => return Err(format!("planned run {i} of {n} is missing")),
        }
    }
    Ok(Outcome::Accepted)
}

fn plugin(ctx: &Context, text: &str) -> Result<Outcome, String> {
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

/// Diagnostics point inside the source at character boundaries, and the text of those a user
/// is shown (the first `MAX_SHOWN`, then "N more") is bounded.
fn well_formed(text: &str, diagnostics: &[Diagnostic]) -> Result<(), String> {
    let mut total = 0usize;
    for (i, d) in diagnostics.iter().enumerate() {
        let description = d.describe();
        span_inside(text, d.span.start, d.span.end)?;
        for (span, label) in &description.secondary {
            span_inside(text, span.start, span.end)?;
            if i < MAX_SHOWN {
                total += label.len();
            }
        }
        if i < MAX_SHOWN {
            total += description.title.len()
                + description.label.len()
                + description.hint.as_ref().map_or(0, String::len);
        }
    }
    let shown = diagnostics.len().min(MAX_SHOWN);
    let limit =
        ERROR_BASE_BYTES + shown * DIAGNOSTIC_BYTES + DIAGNOSTIC_BYTES_PER_INPUT_BYTE * text.len();
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

    #[test]
    fn spans_must_be_character_ranges_of_the_source() {
        let text = "robot \u{e9};";
        assert!(span_inside(text, 6, 8).is_ok());
        assert!(span_inside(text, 7, 8).is_err(), "inside a character");
        assert!(span_inside(text, 3, 2).is_err(), "reversed");
        assert!(span_inside(text, 0, 100).is_err(), "past the end");
    }

    #[test]
    fn long_shown_diagnostics_break_the_bound() {
        // Diagnostics quoting more text than the source could justify.
        let text = "@".repeat(100);
        let quoting = |n: usize| Diagnostic {
            kind: DiagnosticKind::UnexpectedToken {
                expected: "x".repeat(n),
                found: "@".into(),
            },
            span: Span { start: 0, end: 1 },
        };
        assert!(well_formed(&text, &[quoting(10_000)]).is_err());
        assert!(well_formed(&text, &[quoting(10)]).is_ok());
    }

    #[test]
    fn a_run_of_bad_characters_is_one_diagnostic() {
        let parsed = parse(&"@".repeat(3000));
        assert_eq!(
            parsed.diagnostics.len(),
            1,
            "{:?}",
            parsed.diagnostics.first()
        );
    }

    #[test]
    fn loader_errors_must_be_bounded_and_say_something() {
        assert_eq!(loader("x", Ok::<(), String>(())), Ok(Outcome::Accepted));
        assert_eq!(loader("x", Err("bad")), Ok(Outcome::Rejected));
        assert!(loader("x", Err("  ")).is_err());
        assert!(loader("x", Err("e".repeat(ERROR_BASE_BYTES + 2))).is_err());
    }

    #[test]
    fn a_huge_plugin_count_is_rejected() {
        let big = "name = \"g\"\n[[part]]\nname = \"P\"\ncount = 70000\n";
        let ctx = Context::new(&[]);
        assert_eq!(Target::Plugin.run(&ctx, big), Ok(Outcome::Rejected));
    }
}
