//! RoFI's old ("Viki") text format of configurations and plans, read strictly into
//! [`RofiConfiguration`]s: every line that breaks a rule is refused with its line, column and
//! what was expected there, where RoFI's own reader would skip it or guess.
//!
//! A file is a list of configurations, each opened by a `C` line and made of `M` (module) and
//! `E` (edge) lines; a file without any `C` line is one configuration, as RoFI's newer reader
//! takes a single configuration. Blank lines and lines whose first field starts with `#` are
//! skipped. The planner's closing `length N`, `queue N` and `cfgs N` lines are accepted only
//! after the last configuration and carry nothing a configuration needs, so they are dropped.
//!
//! Lines are split on `\n` (a `\r` before it is dropped), fields on runs of spaces or tabs,
//! and columns count characters from 1. The work is one pass over the text plus one cheap
//! look for `C` lines, so it stays linear in the input whatever bytes it holds.

use crate::module::{
    ConfigurationError, Connection, Connector, Dock, Joint, Module, Orientation, Port,
    RofiConfiguration, Side,
};
use std::fmt;

/// The configurations of a file in order, each with the 1-based line of its `C` (1 for a
/// file without `C` lines), so that later checks can point back into the file.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub configurations: Vec<(usize, RofiConfiguration)>,
}

/// Why a file in the old format cannot be read: where (1-based line and character column)
/// and what was expected there.
#[derive(Clone, Debug, PartialEq)]
pub struct OldFormatError {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl fmt::Display for OldFormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}, column {}: {}",
            self.line, self.column, self.message
        )
    }
}

impl std::error::Error for OldFormatError {}

/// Reads a whole file: a plan of one or more configurations, or the first rule it breaks.
pub fn read_old_format(text: &str) -> Result<Plan, OldFormatError> {
    let lines: Vec<&str> = text.split('\n').map(without_carriage_return).collect();
    // Whether the file is a list of `C` blocks decides how its first lines are read, and a
    // stray line before the first `C` is reported at that line, so this is known up front.
    let has_starts = lines.iter().any(|line| first_field(line) == Some("C"));
    let mut reader = Reader::new(has_starts);
    for (index, line) in lines.iter().enumerate() {
        reader.read_line(index + 1, line)?;
    }
    reader.finish()
}

/// A `\r\n` line ending leaves a `\r` that is no part of the last field.
fn without_carriage_return(line: &str) -> &str {
    line.strip_suffix('\r').unwrap_or(line)
}

fn is_separator(c: char) -> bool {
    c == ' ' || c == '\t'
}

fn first_field(line: &str) -> Option<&str> {
    line.split(is_separator).find(|field| !field.is_empty())
}

/// A field of a line and the column of its first character.
#[derive(Clone, Copy, Debug)]
struct Field<'a> {
    column: usize,
    text: &'a str,
}

impl Field<'_> {
    /// The column just past the field: where a missing next field is reported.
    fn end_column(&self) -> usize {
        self.column + self.text.chars().count()
    }

    fn error(&self, line: usize, message: String) -> OldFormatError {
        OldFormatError {
            line,
            column: self.column,
            message,
        }
    }

    /// The usual complaint about a field: what it is, what it should have been, what it is.
    fn expected(&self, line: usize, spec: &FieldSpec) -> OldFormatError {
        self.error(
            line,
            format!(
                "{}: expected {}, found {}",
                spec.name,
                spec.expected,
                shown(self.text)
            ),
        )
    }
}

/// A field as a message shows it: quoted, escaped so that control characters stay visible,
/// and cut short so that one enormous field cannot make an enormous message.
fn shown(text: &str) -> String {
    const SHOWN_CHARS: usize = 24;
    let mut shown: String = text.chars().take(SHOWN_CHARS).collect();
    if text.chars().nth(SHOWN_CHARS).is_some() {
        shown.push('…');
    }
    format!("`{}`", shown.escape_debug())
}

/// The fields of a line with their character columns.
fn split_fields(line: &str) -> Vec<Field<'_>> {
    let mut fields = Vec::new();
    // The byte offset and column where the field being read began.
    let mut start: Option<(usize, usize)> = None;
    for (column, (byte, c)) in (1..).zip(line.char_indices()) {
        match (is_separator(c), start) {
            (true, Some((from, from_column))) => {
                fields.push(Field {
                    column: from_column,
                    text: line.get(from..byte).unwrap_or_default(),
                });
                start = None;
            }
            (false, None) => start = Some((byte, column)),
            _ => {}
        }
    }
    if let Some((from, from_column)) = start {
        fields.push(Field {
            column: from_column,
            text: line.get(from..).unwrap_or_default(),
        });
    }
    fields
}

/// What a field of a line kind is called and what it may hold, for messages.
struct FieldSpec {
    name: &'static str,
    expected: &'static str,
}

const MODULE_ID: &str = "a module id (a whole number from 0 to 4294967295)";
const ANGLE: &str = "an angle in degrees (a decimal number such as -15.5, 90 or 1e-05)";
const SIDE: &str = "a side: A, B, 0 or 1";
const DOCK: &str = "a dock: +X, -X, -Z, 0, 1 or 2";
const ORIENTATION: &str = "an orientation: N, E, S, W, 0, 1, 2 or 3";
const COUNT: &str = "a whole number";

const MODULE_FIELDS: [FieldSpec; 4] = [
    FieldSpec {
        name: "module id",
        expected: MODULE_ID,
    },
    FieldSpec {
        name: "alpha",
        expected: ANGLE,
    },
    FieldSpec {
        name: "beta",
        expected: ANGLE,
    },
    FieldSpec {
        name: "gamma",
        expected: ANGLE,
    },
];

/// An edge's fields in their mirrored order: id, side and dock of one end, the orientation,
/// then dock, side and id of the other end.
const EDGE_FIELDS: [FieldSpec; 7] = [
    FieldSpec {
        name: "first module id",
        expected: MODULE_ID,
    },
    FieldSpec {
        name: "first side",
        expected: SIDE,
    },
    FieldSpec {
        name: "first dock",
        expected: DOCK,
    },
    FieldSpec {
        name: "orientation",
        expected: ORIENTATION,
    },
    FieldSpec {
        name: "second dock",
        expected: DOCK,
    },
    FieldSpec {
        name: "second side",
        expected: SIDE,
    },
    FieldSpec {
        name: "second module id",
        expected: MODULE_ID,
    },
];

const TRAILER_FIELDS: [FieldSpec; 1] = [FieldSpec {
    name: "count",
    expected: COUNT,
}];

/// The fields after a line's first one, exactly as many as `specs` describes, or an error at
/// the first missing or extra field.
fn exact_fields<'a, const N: usize>(
    line: usize,
    keyword: Field<'a>,
    rest: &[Field<'a>],
    specs: &[FieldSpec; N],
) -> Result<[Field<'a>; N], OldFormatError> {
    if let Some(extra) = rest.get(N) {
        let last = specs
            .last()
            .map_or(shown(keyword.text), |spec| spec.name.to_owned());
        let message = format!(
            "expected the end of the line after {last}, found {}",
            shown(extra.text)
        );
        return Err(extra.error(line, message));
    }
    <[Field<'a>; N]>::try_from(rest).map_err(|_| {
        let last = rest.last().copied().unwrap_or(keyword);
        let spec = specs.get(rest.len());
        let (name, expected) = spec.map_or(("a field", "more"), |s| (s.name, s.expected));
        OldFormatError {
            line,
            column: last.end_column(),
            message: format!("missing {name}: expected {expected}, found the end of the line"),
        }
    })
}

fn parse_module_id(line: usize, field: Field, spec: &FieldSpec) -> Result<u32, OldFormatError> {
    // `u32::from_str` would also take a leading `+`; the format writes bare digits.
    if !field.text.bytes().all(|b| b.is_ascii_digit()) {
        return Err(field.expected(line, spec));
    }
    field.text.parse().map_err(|_| field.expected(line, spec))
}

/// An angle: a decimal number with an optional sign, fraction and exponent. Exponents are
/// accepted because RoFI writes angles with C++ stream defaults, which print small values
/// such as `1e-05`; `inf`, `nan` and hexadecimal, which `f64::from_str` or C++ might take,
/// are refused. A number too large for `f64` reads as infinite and is refused by the
/// configuration as not finite.
fn parse_angle(line: usize, field: Field, spec: &FieldSpec) -> Result<f64, OldFormatError> {
    if !is_decimal_number(field.text) {
        return Err(field.expected(line, spec));
    }
    field.text.parse().map_err(|_| field.expected(line, spec))
}

/// `[+-]? (digits [. digits?] | . digits) ([eE] [+-]? digits)?`, checked by hand so that
/// only this grammar reaches the float parser.
fn is_decimal_number(text: &str) -> bool {
    let unsigned = text.strip_prefix(['+', '-']).unwrap_or(text);
    let (mantissa, exponent) = match unsigned.split_once(['e', 'E']) {
        Some((mantissa, exponent)) => (mantissa, Some(exponent)),
        None => (unsigned, None),
    };
    let (whole, fraction) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let all_digits = |part: &str| part.bytes().all(|b| b.is_ascii_digit());
    let mantissa_ok =
        all_digits(whole) && all_digits(fraction) && !(whole.is_empty() && fraction.is_empty());
    let exponent_ok = exponent.is_none_or(|exponent| {
        let digits = exponent.strip_prefix(['+', '-']).unwrap_or(exponent);
        !digits.is_empty() && all_digits(digits)
    });
    mantissa_ok && exponent_ok
}

fn parse_side(line: usize, field: Field, spec: &FieldSpec) -> Result<Side, OldFormatError> {
    named(field.text, &[Side::A, Side::B], |s| (s.letter(), s as u8))
        .ok_or_else(|| field.expected(line, spec))
}

fn parse_dock(line: usize, field: Field, spec: &FieldSpec) -> Result<Dock, OldFormatError> {
    named(field.text, &Dock::ALL, |d| (d.old_name(), d as u8))
        .ok_or_else(|| field.expected(line, spec))
}

fn parse_orientation(
    line: usize,
    field: Field,
    spec: &FieldSpec,
) -> Result<Orientation, OldFormatError> {
    named(field.text, &Orientation::ALL, |o| {
        (o.letter(), o.quarter_turns())
    })
    .ok_or_else(|| field.expected(line, spec))
}

/// The value whose name (the vocabulary of `module.rs`) or number `text` is.
fn named<T: Copy>(text: &str, all: &[T], name: impl Fn(T) -> (&'static str, u8)) -> Option<T> {
    all.iter().copied().find(|&value| {
        let (word, number) = name(value);
        text == word || text.parse::<u8>().ok() == Some(number) && text.len() == 1
    })
}

/// The configurations in this format: a `C` block each, modules in ID order, each connection
/// once, from the end it was made from, by names. Angles are written as Rust writes a float
/// (the shortest text that reads back to the same number), so reading the text gives the
/// same configurations.
pub fn write_old_format(configurations: &[RofiConfiguration]) -> String {
    let mut out = String::new();
    for (k, config) in configurations.iter().enumerate() {
        if k > 0 {
            out.push('\n');
        }
        out.push_str("C\n");
        for m in config.modules() {
            out.push_str(&format!("M {} {} {} {}\n", m.id, m.alpha, m.beta, m.gamma));
        }
        for c in config.connections() {
            let ((id1, c1), (id2, c2)) = (c.from, c.to);
            out.push_str(&format!(
                "E {id1} {} {} {} {} {} {id2}\n",
                c1.side().letter(),
                c1.dock().old_name(),
                c.orientation.letter(),
                c2.dock().old_name(),
                c2.side().letter()
            ));
        }
    }
    out
}

/// The kinds of line, by their first field.
enum LineKind {
    /// Blank or a comment.
    Skipped,
    Start,
    Module,
    Edge,
    Trailer,
}

fn line_kind(line: usize, keyword: Field) -> Result<LineKind, OldFormatError> {
    match keyword.text {
        "C" => Ok(LineKind::Start),
        "M" => Ok(LineKind::Module),
        "E" => Ok(LineKind::Edge),
        "length" | "queue" | "cfgs" => Ok(LineKind::Trailer),
        text if text.starts_with('#') => Ok(LineKind::Skipped),
        text => Err(keyword.error(
            line,
            format!(
                "expected a line `C`, `M <id> <alpha> <beta> <gamma>`, \
                 `E <id> <side> <dock> <orientation> <dock> <side> <id>`, \
                 `length N`, `queue N`, `cfgs N` or a `#` comment, found {}",
                shown(text)
            ),
        )),
    }
}

/// The configuration being read and the line where it began.
struct Block {
    line: usize,
    configuration: RofiConfiguration,
}

/// The state of a file read so far.
struct Reader {
    /// Whether the file has `C` lines; if not, the whole file is one block opened at line 1.
    has_starts: bool,
    done: Vec<(usize, RofiConfiguration)>,
    current: Option<Block>,
    in_trailer: bool,
}

impl Reader {
    fn new(has_starts: bool) -> Reader {
        let current = (!has_starts).then(|| Block {
            line: 1,
            configuration: RofiConfiguration::new(),
        });
        Reader {
            has_starts,
            done: Vec::new(),
            current,
            in_trailer: false,
        }
    }

    fn read_line(&mut self, line: usize, text: &str) -> Result<(), OldFormatError> {
        let fields = split_fields(text);
        let Some((&keyword, rest)) = fields.split_first() else {
            return Ok(());
        };
        match line_kind(line, keyword)? {
            LineKind::Skipped => Ok(()),
            LineKind::Trailer => self.read_trailer(line, keyword, rest),
            kind if self.in_trailer => Err(after_trailer(line, keyword, kind)),
            LineKind::Start => self.read_start(line, keyword, rest),
            LineKind::Module => self.read_module(line, keyword, rest),
            LineKind::Edge => self.read_edge(line, keyword, rest),
        }
    }

    /// The block a module or edge line belongs to; in a file with `C` lines, there is none
    /// before the first `C`.
    fn block(&mut self, line: usize, keyword: Field) -> Result<&mut Block, OldFormatError> {
        self.current
            .as_mut()
            .ok_or_else(|| before_first_start(line, keyword))
    }

    fn read_start(
        &mut self,
        line: usize,
        keyword: Field,
        rest: &[Field],
    ) -> Result<(), OldFormatError> {
        exact_fields(line, keyword, rest, &[])?;
        self.close_block()?;
        self.current = Some(Block {
            line,
            configuration: RofiConfiguration::new(),
        });
        Ok(())
    }

    fn read_module(
        &mut self,
        line: usize,
        keyword: Field,
        rest: &[Field],
    ) -> Result<(), OldFormatError> {
        let block = self.block(line, keyword)?;
        let fields = exact_fields(line, keyword, rest, &MODULE_FIELDS)?;
        let [id, alpha, beta, gamma] = fields;
        let [id_spec, alpha_spec, beta_spec, gamma_spec] = &MODULE_FIELDS;
        let module = Module {
            id: parse_module_id(line, id, id_spec)?,
            alpha: parse_angle(line, alpha, alpha_spec)?,
            beta: parse_angle(line, beta, beta_spec)?,
            gamma: parse_angle(line, gamma, gamma_spec)?,
        };
        block.configuration.add_module(module).map_err(|error| {
            let field = match &error {
                ConfigurationError::JointOutOfRange { joint, .. }
                | ConfigurationError::NotFinite { joint, .. } => match joint {
                    Joint::Alpha => alpha,
                    Joint::Beta => beta,
                    Joint::Gamma => gamma,
                },
                _ => id,
            };
            field.error(line, configuration_message(&error))
        })
    }

    fn read_edge(
        &mut self,
        line: usize,
        keyword: Field,
        rest: &[Field],
    ) -> Result<(), OldFormatError> {
        let block = self.block(line, keyword)?;
        let fields = exact_fields(line, keyword, rest, &EDGE_FIELDS)?;
        let [id1, side1, dock1, ori, dock2, side2, id2] = fields;
        let [id1_spec, side1_spec, dock1_spec, ori_spec, dock2_spec, side2_spec, id2_spec] =
            &EDGE_FIELDS;
        let from: Port = (
            parse_module_id(line, id1, id1_spec)?,
            Connector::new(
                parse_side(line, side1, side1_spec)?,
                parse_dock(line, dock1, dock1_spec)?,
            ),
        );
        let orientation = parse_orientation(line, ori, ori_spec)?;
        let to: Port = (
            parse_module_id(line, id2, id2_spec)?,
            Connector::new(
                parse_side(line, side2, side2_spec)?,
                parse_dock(line, dock2, dock2_spec)?,
            ),
        );
        let connection = Connection {
            from,
            orientation,
            to,
        };
        block.configuration.connect(connection).map_err(|error| {
            // The first field of the end at fault: its id for the first end, its dock for
            // the mirrored second end.
            let field = match &error {
                ConfigurationError::UnknownModule(id) if *id != from.0 => id2,
                ConfigurationError::ConnectorInUse(port) if *port != from => dock2,
                _ => id1,
            };
            field.error(line, configuration_message(&error))
        })
    }

    fn read_trailer(
        &mut self,
        line: usize,
        keyword: Field,
        rest: &[Field],
    ) -> Result<(), OldFormatError> {
        if self.current.is_none() && !self.in_trailer {
            return Err(before_first_start(line, keyword));
        }
        let [count] = exact_fields(line, keyword, rest, &TRAILER_FIELDS)?;
        let [count_spec] = &TRAILER_FIELDS;
        // Only checked, never converted: the counts are not used, so no size limits them.
        if count.text.is_empty() || !count.text.bytes().all(|b| b.is_ascii_digit()) {
            return Err(count.expected(line, count_spec));
        }
        self.close_block()?;
        self.in_trailer = true;
        Ok(())
    }

    /// Moves the block being read, if any, to the finished ones; a block without modules is
    /// an error, at its `C` line (or, in a file without `C`, at line 1).
    fn close_block(&mut self) -> Result<(), OldFormatError> {
        let Some(block) = self.current.take() else {
            return Ok(());
        };
        if block.configuration.is_empty() {
            return Err(self.empty_block(block.line));
        }
        self.done.push((block.line, block.configuration));
        Ok(())
    }

    fn empty_block(&self, line: usize) -> OldFormatError {
        let message = if self.has_starts {
            "expected at least one `M <id> <alpha> <beta> <gamma>` line in this configuration \
             before the next `C`, the trailer or the end of the file"
        } else {
            "expected at least one `M <id> <alpha> <beta> <gamma>` line: the file declares no \
             module"
        };
        OldFormatError {
            line,
            column: 1,
            message: message.to_owned(),
        }
    }

    fn finish(mut self) -> Result<Plan, OldFormatError> {
        self.close_block()?;
        // Every closed block has a module, so this list is empty only if no block was ever
        // opened, which a file with `C` lines cannot do; refused anyway rather than assumed.
        if self.done.is_empty() {
            return Err(self.empty_block(1));
        }
        Ok(Plan {
            configurations: self.done,
        })
    }
}

fn before_first_start(line: usize, keyword: Field) -> OldFormatError {
    keyword.error(
        line,
        format!(
            "expected `C` before {}: this file's configurations start with `C` lines",
            shown(keyword.text)
        ),
    )
}

fn after_trailer(line: usize, keyword: Field, kind: LineKind) -> OldFormatError {
    let what = match kind {
        LineKind::Start => "a configuration",
        LineKind::Module => "a module",
        _ => "an edge",
    };
    keyword.error(
        line,
        format!(
            "expected only `length N`, `queue N`, `cfgs N`, blank or `#` lines after the \
             trailer, found {what} ({})",
            shown(keyword.text)
        ),
    )
}

/// A configuration rule's message, with what the format expects instead.
fn configuration_message(error: &ConfigurationError) -> String {
    let expected = match error {
        ConfigurationError::DuplicateModule(_) => "each module id once in a configuration",
        ConfigurationError::UnknownModule(_) => {
            "an `M` line for each module of an edge earlier in the same configuration"
        }
        ConfigurationError::ConnectorInUse(_) => "each connector in at most one edge",
        ConfigurationError::SameConnector(_) => "an edge between two different connectors",
        ConfigurationError::JointOutOfRange { .. } => "alpha and beta within -90..90 degrees",
        ConfigurationError::NotFinite { .. } => "a finite angle",
    };
    format!("{error}; expected {expected}")
}
