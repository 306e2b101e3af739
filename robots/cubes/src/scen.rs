//! MRWT's scenario files (`.scen`, the format its WebVis viewer plays) read strictly into a
//! [`Scenario`] and written back: every value keeps the line it came from, and every line the
//! viewer would misread or guess at is refused with its line, column and what was expected.
//!
//! # The format
//!
//! A `\r` anywhere is dropped, and lines are split on `\n`. Lines 1 to 3 are the header, taken
//! as written (spaces kept, `//` is no comment there): the scenario's name, a description and
//! the module type. Line 4 is empty. Every later line is a data line: its spaces are stripped
//! (tabs are not), everything from the first `//` on is dropped, and what is left is read as
//! comma-separated integers. A data line left empty (a line of spaces, a comment) is blank.
//! Blank lines end blocks: block 0 declares groups `id, red, green, blue, size%` (display
//! only), block 1 declares modules `id, group, x, y, z`, and each later run of lines is one
//! move set of lines `[*]id, anchor code, dx, dy, dz` that run together. A `*` before a move's
//! id makes its set a checkpoint; the first set always is one.
//!
//! # Where dynarole refuses what the viewer guesses
//!
//! - **Header.** The name may be empty. The description may not: an empty line 2 would end
//!   the viewer's header there. The type line must be exactly `CUBE`: dynarole models cubes
//!   only, so `RHOMBIC_DODECAHEDRON` and `CATOM` are refused, and so is anything else (which
//!   the viewer would play as cubes). Line 4 must be empty, not merely blank: the viewer ends
//!   its header at the first empty line only, so spaces or a comment there would make it
//!   swallow the groups.
//! - **Blank lines.** Exactly one: the viewer counts blank lines to tell the blocks apart, so a
//!   second blank line after the header or after the groups would shift every later block.
//!   Both are refused at the second blank line, as are a file without groups and one without
//!   modules. After the module block, any number of blank lines separate (or end) move sets.
//! - **Fields.** Exactly five on every data line (the viewer ignores extra fields and reads
//!   missing ones as NaN). Each is a decimal integer: an optional `+` or `-`, then one or more
//!   ASCII digits; leading zeros are fine (`007` is 7). JavaScript's `parseInt` would read
//!   `1.5` as 1 and `0x10` as 16, and a tab-only line as NaN; all are refused here.
//! - **Ranges.** Group ids within ±(2⁵³ − 1), JavaScript's exact integers, beyond which two
//!   ids could become one; colours and sizes likewise (display only, kept as written: the
//!   planners' own files have components above 255); module ids 0 to `u32::MAX`; coordinates and displacements within ±1,000,000; anchor codes
//!   within `i32`.
//! - **References.** A group or a module declared twice, a module of an undeclared group and a
//!   move of an undeclared module are refused. A `*` anywhere but at the start of a move line
//!   is refused (the viewer would drop it without effect).
//! - **Not checked here:** whether two modules share a cell, whether a module moves twice in
//!   one set and whether a move is legal; those belong to the lattice and the moves.
//!
//! Lines count from 1. Columns count characters (not bytes) from 1 in the line as written,
//! before spaces and `\r` are stripped, and point at the offending field's first character; an
//! empty field is placed just after the comma before it, and a missing field just after the
//! line's last character before any comment. Reading is one pass over the text with hash-map
//! lookups, linear in its length, and never slices a string by bytes.
//!
//! # The writer
//!
//! [`write_scen`] writes what the viewer plays: the header with type `CUBE`, the groups, the
//! modules and one block per move set, lines joined by `\n` with a trailing `\n` and fields
//! joined by `", "`. Ids are written plainly, without the zero padding of MRWT's pathfinder
//! (both read the same). A `*` goes on the first line of every checkpoint set and of the first
//! set, and nowhere else: a `*` on a later line means no more than one on the first. Sets
//! without moves are left out (a block cannot be empty). Since the header is three lines, line
//! breaks in the name or the description are written as spaces, and an empty description as
//! `-`. A scenario that [`read_scen`] returns comes back from `read_scen(&write_scen(s))` equal
//! but for line numbers, once its stars are in that normal form.

use std::collections::HashMap;
use std::fmt;

/// A scenario file's content, in file order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Scenario {
    pub name: String,
    pub description: String,
    pub groups: Vec<Group>,
    pub modules: Vec<ScenModule>,
    pub sets: Vec<MoveSet>,
}

/// A display group: colour and size of the modules that name it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Group {
    pub line: usize,
    pub id: i64,
    pub colour: [i64; 3],
    pub size_percent: i64,
}

/// A module's declaration: its id, group and starting cell.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScenModule {
    pub line: usize,
    pub id: u32,
    pub group: i64,
    pub position: [i32; 3],
}

/// Moves that run together; `line` is the set's first line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MoveSet {
    pub line: usize,
    pub checkpoint: bool,
    pub moves: Vec<MoveLine>,
}

/// One move: module `id` moves by `d` cells, with the anchor direction code `code`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MoveLine {
    pub line: usize,
    pub starred: bool,
    pub id: u32,
    pub code: i64,
    pub d: [i32; 3],
}

/// Why a text is not a scenario dynarole reads: where (1-based line and character column)
/// and what was expected there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScenError {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl fmt::Display for ScenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}, column {}: {}",
            self.line, self.column, self.message
        )
    }
}

impl std::error::Error for ScenError {}

fn error(line: usize, column: usize, message: String) -> ScenError {
    ScenError {
        line,
        column,
        message,
    }
}

const CUBE_TYPE: &str = "CUBE";
const OTHER_TYPES: [&str; 2] = ["RHOMBIC_DODECAHEDRON", "CATOM"];

/// Beyond JavaScript's exact integers the viewer, whose numbers are doubles, could take two
/// group ids for one.
const MAX_GROUP_ID: i64 = (1 << 53) - 1;
const MAX_COORDINATE: i64 = 1_000_000;

/// Whether `text` looks like a scenario, so that an importer of several formats can tell them
/// apart by content. Only the first five lines are looked at: line 4 must be empty, and then
/// either line 3 is one of the viewer's module types (`CUBE`, `RHOMBIC_DODECAHEDRON`, `CATOM`:
/// a bare word, which no JSON text has as a line), or line 5 is a group line (five
/// comma-separated decimal integers, read as a data line) and the text starts neither like
/// JSON (`{` or `[` after white space) nor like RoFI's text format (a first non-blank line of
/// `C` or `M` followed only by numbers). Every text [`write_scen`] writes has `CUBE` on line 3
/// and an empty line 4, whatever its name.
pub fn looks_like_scen(text: &str) -> bool {
    let first_lines: Vec<String> = text.split('\n').take(5).map(without_cr).collect();
    let [_, _, module_type, separator, first_group] = first_lines.as_slice() else {
        return false;
    };
    if !separator.is_empty() {
        return false;
    }
    if module_type == CUBE_TYPE || OTHER_TYPES.contains(&module_type.as_str()) {
        return true;
    }
    is_group_shaped(first_group) && !starts_like_json(text) && !starts_like_rofi(text)
}

fn without_cr(raw: &str) -> String {
    raw.replace('\r', "")
}

fn is_group_shaped(line: &str) -> bool {
    let line = DataLine::new(0, line);
    let fields = split_fields(&line.chars, line.first_column());
    fields.len() == 5
        && fields
            .iter()
            .all(|field| !matches!(decimal(field.chars), Decimal::NotAnInteger))
}

fn starts_like_json(text: &str) -> bool {
    // A byte-order mark is no white space to `trim_start`, but a decoder would drop it.
    let start = text.trim_start_matches(|c: char| c.is_whitespace() || c == '\u{feff}');
    start.starts_with('{') || start.starts_with('[')
}

/// A first non-blank line `C …` or `M …` of numbers only, as RoFI's old text format opens.
fn starts_like_rofi(text: &str) -> bool {
    let Some(first) = text.lines().find(|line| !line.trim().is_empty()) else {
        return false;
    };
    let mut words = first.split_whitespace();
    matches!(words.next(), Some("C" | "M")) && words.all(|word| word.parse::<f64>().is_ok())
}

/// Reads a whole scenario, or says where and why it is not one dynarole reads.
pub fn read_scen(text: &str) -> Result<Scenario, ScenError> {
    let mut lines = Lines::new(text);
    let (name, description) = read_header(&mut lines)?;
    let groups = read_groups(&mut lines)?;
    let modules = read_modules(&mut lines, &groups)?;
    let sets = read_sets(&mut lines, &modules)?;
    Ok(Scenario {
        name,
        description,
        groups,
        modules,
        sets,
    })
}

/// The text's lines in order, numbered from 1, with one data line of look-ahead so that a
/// block can stop at a blank line without consuming it.
struct Lines<'a> {
    rest: std::str::SplitTerminator<'a, char>,
    next_number: usize,
    peeked: Option<DataLine>,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        // A final `\n` ends the last line rather than opening an empty one, so that a file
        // that stops short is reported as ending, not as having a stray blank line.
        Lines {
            rest: text.split_terminator('\n'),
            next_number: 1,
            peeked: None,
        }
    }

    fn next_raw(&mut self) -> Option<(usize, &'a str)> {
        let raw = self.rest.next()?;
        let number = self.next_number;
        self.next_number += 1;
        Some((number, raw))
    }

    /// The number a line after the last one would have: where the end of the file is reported.
    fn end_line(&self) -> usize {
        self.next_number
    }

    fn peek_data(&mut self) -> Option<&DataLine> {
        if self.peeked.is_none() {
            self.peeked = self
                .next_raw()
                .map(|(number, raw)| DataLine::new(number, raw));
        }
        self.peeked.as_ref()
    }

    fn next_data(&mut self) -> Option<DataLine> {
        self.peek_data();
        self.peeked.take()
    }

    /// The next data line if it belongs to the current block; a blank line is left in place.
    fn next_in_block(&mut self) -> Option<DataLine> {
        match self.peek_data() {
            Some(line) if !line.is_blank() => self.next_data(),
            _ => None,
        }
    }

    fn skip_blank_lines(&mut self) {
        while self.peek_data().is_some_and(DataLine::is_blank) {
            self.peeked = None;
        }
    }
}

fn read_header(lines: &mut Lines) -> Result<(String, String), ScenError> {
    let (_, name) = header_line(lines, "the scenario's name (line 1)")?;
    let (number, description) = header_line(lines, "the description (line 2)")?;
    if description.is_empty() {
        return Err(error(
            number,
            1,
            "expected a description: line 2 must not be empty, since the viewer would end \
             the header at an empty line there"
                .to_owned(),
        ));
    }
    let (number, module_type) = header_line(lines, "the module type `CUBE` (line 3)")?;
    check_module_type(number, &module_type)?;
    match lines.next_raw() {
        None => Err(error(
            lines.end_line(),
            1,
            "the file ends after the header; expected an empty line, then the groups".to_owned(),
        )),
        Some((number, raw)) if !without_cr(raw).is_empty() => Err(error(
            number,
            1,
            format!(
                "expected an empty line after the three header lines (name, description, \
                 type), found {}: the viewer ends the header only at an empty line",
                shown(raw.chars())
            ),
        )),
        Some(_) => Ok((name, description)),
    }
}

fn header_line(lines: &mut Lines, what: &str) -> Result<(usize, String), ScenError> {
    match lines.next_raw() {
        Some((number, raw)) => Ok((number, without_cr(raw))),
        None => Err(error(
            lines.end_line(),
            1,
            format!("the file ends before {what}"),
        )),
    }
}

fn check_module_type(number: usize, module_type: &str) -> Result<(), ScenError> {
    if module_type == CUBE_TYPE {
        return Ok(());
    }
    let message = if OTHER_TYPES.contains(&module_type) {
        format!(
            "this is a {module_type} scenario, and dynarole reads only cube scenarios \
             (module type `CUBE`)"
        )
    } else {
        format!(
            "expected the module type `CUBE` (dynarole reads only cube scenarios), found {}",
            shown(module_type.chars())
        )
    };
    Err(error(number, 1, message))
}

/// Where a block must begin: refuses the end of the file and a second blank line, which
/// would make the viewer read this block as the next kind.
fn expect_block_start(lines: &mut Lines, block: &str, shift: &str) -> Result<(), ScenError> {
    match lines.peek_data() {
        None => Err(error(
            lines.end_line(),
            1,
            format!("the file ends before {block}"),
        )),
        Some(line) if line.is_blank() => Err(error(
            line.number,
            1,
            format!("expected {block}, found a second blank line: {shift}"),
        )),
        Some(_) => Ok(()),
    }
}

fn read_groups(lines: &mut Lines) -> Result<Vec<Group>, ScenError> {
    expect_block_start(
        lines,
        "the groups (`id, red, green, blue, size%`)",
        "exactly one empty line follows the header, and after a second one the viewer \
         would read the groups as modules",
    )?;
    let mut groups = Vec::new();
    let mut declared = HashMap::new();
    while let Some(line) = lines.next_in_block() {
        let group = parse_group(&line, &declared)?;
        declared.insert(group.id, group.line);
        groups.push(group);
    }
    Ok(groups)
}

fn read_modules(lines: &mut Lines, groups: &[Group]) -> Result<Vec<ScenModule>, ScenError> {
    // The blank line that ended the groups (if the file goes on).
    lines.next_data();
    expect_block_start(
        lines,
        "the modules (`id, group, x, y, z`)",
        "exactly one blank line follows the groups, and after a second one the viewer \
         would read the modules as moves",
    )?;
    let group_ids: HashMap<i64, usize> = groups.iter().map(|g| (g.id, g.line)).collect();
    let mut modules = Vec::new();
    let mut declared = HashMap::new();
    while let Some(line) = lines.next_in_block() {
        let module = parse_module(&line, &group_ids, &declared)?;
        declared.insert(module.id, module.line);
        modules.push(module);
    }
    Ok(modules)
}

fn read_sets(lines: &mut Lines, modules: &[ScenModule]) -> Result<Vec<MoveSet>, ScenError> {
    let declared: HashMap<u32, usize> = modules.iter().map(|m| (m.id, m.line)).collect();
    let mut sets = Vec::new();
    loop {
        lines.skip_blank_lines();
        match read_set(lines, &declared, sets.is_empty())? {
            Some(set) => sets.push(set),
            None => return Ok(sets),
        }
    }
}

/// The next set, or `None` at the end of the file.
fn read_set(
    lines: &mut Lines,
    modules: &HashMap<u32, usize>,
    first: bool,
) -> Result<Option<MoveSet>, ScenError> {
    let mut moves = Vec::new();
    while let Some(line) = lines.next_in_block() {
        moves.push(parse_move(&line, modules)?);
    }
    let Some(line) = moves.first().map(|m| m.line) else {
        return Ok(None);
    };
    Ok(Some(MoveSet {
        line,
        checkpoint: first || moves.iter().any(|m| m.starred),
        moves,
    }))
}

fn parse_group(line: &DataLine, declared: &HashMap<i64, usize>) -> Result<Group, ScenError> {
    let (_, [id, red, green, blue, size]) = line.numbers(&GROUP_LINE)?;
    if let Some(first) = declared.get(&id.value) {
        return Err(line.error(
            id.column,
            format!(
                "group {} is declared twice (first on line {first})",
                id.value
            ),
        ));
    }
    Ok(Group {
        line: line.number,
        id: id.value,
        colour: [red.value, green.value, blue.value],
        size_percent: size.value,
    })
}

fn parse_module(
    line: &DataLine,
    groups: &HashMap<i64, usize>,
    declared: &HashMap<u32, usize>,
) -> Result<ScenModule, ScenError> {
    let (_, [id, group, x, y, z]) = line.numbers(&MODULE_LINE)?;
    let module_id = id.as_u32();
    if let Some(first) = declared.get(&module_id) {
        return Err(line.error(
            id.column,
            format!("module {module_id} is declared twice (first on line {first})"),
        ));
    }
    if !groups.contains_key(&group.value) {
        return Err(line.error(
            group.column,
            format!(
                "expected the id of a group declared in the group block, found group {}",
                group.value
            ),
        ));
    }
    Ok(ScenModule {
        line: line.number,
        id: module_id,
        group: group.value,
        position: [x.as_i32(), y.as_i32(), z.as_i32()],
    })
}

fn parse_move(line: &DataLine, modules: &HashMap<u32, usize>) -> Result<MoveLine, ScenError> {
    let (starred, [id, code, dx, dy, dz]) = line.numbers(&MOVE_LINE)?;
    let module_id = id.as_u32();
    if !modules.contains_key(&module_id) {
        return Err(line.error(
            id.column,
            format!(
                "expected the id of a module declared in the module block, found module \
                 {module_id}"
            ),
        ));
    }
    Ok(MoveLine {
        line: line.number,
        starred,
        id: module_id,
        code: code.value,
        d: [dx.as_i32(), dy.as_i32(), dz.as_i32()],
    })
}

/// A data line as the viewer reads it: the characters left once spaces and `\r` are stripped
/// and a comment is dropped, each with its column in the line as written.
struct DataLine {
    number: usize,
    chars: Vec<(usize, char)>,
}

impl DataLine {
    fn new(number: usize, raw: &str) -> Self {
        let mut chars: Vec<(usize, char)> = (1..)
            .zip(raw.chars())
            .filter(|&(_, c)| c != ' ' && c != '\r')
            .collect();
        // As in the viewer, the comment is looked for after spaces are gone, so `/ /` opens
        // one too.
        if let Some(start) = chars
            .windows(2)
            .position(|pair| matches!(pair, [(_, '/'), (_, '/')]))
        {
            chars.truncate(start);
        }
        DataLine { number, chars }
    }

    fn is_blank(&self) -> bool {
        self.chars.is_empty()
    }

    fn first_column(&self) -> usize {
        self.chars.first().map_or(1, |&(column, _)| column)
    }

    /// Just past the last character that counts: where a missing field is reported.
    fn end_column(&self) -> usize {
        self.chars.last().map_or(1, |&(column, _)| column + 1)
    }

    fn error(&self, column: usize, message: String) -> ScenError {
        error(self.number, column, message)
    }

    /// The line's five numbers as `shape` wants them, and whether a `*` opened the line.
    fn numbers(&self, shape: &LineShape) -> Result<(bool, [Number; 5]), ScenError> {
        let (star, rest, first_column) = match self.chars.split_first() {
            Some((&(column, '*'), rest)) => (true, rest, column + 1),
            _ => (false, self.chars.as_slice(), self.first_column()),
        };
        if star && !shape.star_allowed {
            return Err(self.error(
                self.first_column(),
                format!(
                    "expected {}: a `*` marks a checkpoint and belongs only at the start of \
                     a move line",
                    shape.layout
                ),
            ));
        }
        let fields = split_fields(rest, first_column);
        Ok((star, self.read_fields(&fields, shape)?))
    }

    fn read_fields(&self, fields: &[Field], shape: &LineShape) -> Result<[Number; 5], ScenError> {
        let mut numbers = [Number::default(); 5];
        for (index, (number, spec)) in numbers.iter_mut().zip(&shape.specs).enumerate() {
            let Some(field) = fields.get(index) else {
                return Err(self.wrong_count(self.end_column(), fields.len(), shape));
            };
            *number = field.number(self.number, spec)?;
        }
        match fields.get(shape.specs.len()) {
            Some(extra) => Err(self.wrong_count(extra.column, fields.len(), shape)),
            None => Ok(numbers),
        }
    }

    fn wrong_count(&self, column: usize, found: usize, shape: &LineShape) -> ScenError {
        self.error(
            column,
            format!(
                "expected 5 comma-separated fields {}, found {found}",
                shape.layout
            ),
        )
    }
}

/// A comma-separated field: its characters and the column it is reported at.
#[derive(Clone, Copy)]
struct Field<'a> {
    column: usize,
    chars: &'a [(usize, char)],
}

impl Field<'_> {
    fn number(&self, line: usize, spec: &FieldSpec) -> Result<Number, ScenError> {
        let expected_range = || {
            format!(
                "expected {} from {} to {}, found {}",
                spec.what,
                spec.min,
                spec.max,
                shown(self.chars.iter().map(|&(_, c)| c))
            )
        };
        match decimal(self.chars) {
            Decimal::Value(value) if (spec.min..=spec.max).contains(&value) => Ok(Number {
                value,
                column: self.column,
            }),
            Decimal::Value(_) | Decimal::TooLarge => {
                Err(error(line, self.column, expected_range()))
            }
            Decimal::NotAnInteger => Err(error(
                line,
                self.column,
                format!(
                    "expected {} written as a decimal integer (digits, with an optional sign), \
                     found {}",
                    spec.what,
                    shown(self.chars.iter().map(|&(_, c)| c))
                ),
            )),
        }
    }
}

/// Splits on commas. An empty field is placed just after the comma (or `*`) before it, where
/// its digits should have been.
fn split_fields(chars: &[(usize, char)], first_column: usize) -> Vec<Field<'_>> {
    let mut fields = Vec::new();
    let mut start = 0;
    let mut empty_column = first_column;
    for (index, &(column, c)) in chars.iter().enumerate() {
        if c == ',' {
            fields.push(field(chars.get(start..index).unwrap_or(&[]), empty_column));
            start = index + 1;
            empty_column = column + 1;
        }
    }
    fields.push(field(chars.get(start..).unwrap_or(&[]), empty_column));
    fields
}

fn field(chars: &[(usize, char)], empty_column: usize) -> Field<'_> {
    Field {
        column: chars.first().map_or(empty_column, |&(column, _)| column),
        chars,
    }
}

enum Decimal {
    Value(i64),
    /// Digits beyond `i64`: out of every field's range.
    TooLarge,
    NotAnInteger,
}

/// An optional sign, then one or more ASCII digits, and nothing else.
fn decimal(chars: &[(usize, char)]) -> Decimal {
    let (negative, digits) = match chars.split_first() {
        Some((&(_, '-'), rest)) => (true, rest),
        Some((&(_, '+'), rest)) => (false, rest),
        _ => (false, chars),
    };
    if digits.is_empty() || !digits.iter().all(|&(_, c)| c.is_ascii_digit()) {
        return Decimal::NotAnInteger;
    }
    let mut value: i64 = 0;
    for &(_, c) in digits {
        let digit = i64::from(c.to_digit(10).unwrap_or(0));
        // Negative values are built downwards so that every representable one is reached.
        let next = value.checked_mul(10).and_then(|tens| {
            if negative {
                tens.checked_sub(digit)
            } else {
                tens.checked_add(digit)
            }
        });
        match next {
            Some(next) => value = next,
            None => return Decimal::TooLarge,
        }
    }
    Decimal::Value(value)
}

/// A field's value, already inside its field's range, and the column it came from.
#[derive(Clone, Copy, Default)]
struct Number {
    value: i64,
    column: usize,
}

impl Number {
    // The field specs keep every value inside the target type; the clamp lets the cast say
    // so without a path that could panic.
    fn as_u32(self) -> u32 {
        self.value.clamp(0, i64::from(u32::MAX)) as u32
    }

    fn as_i32(self) -> i32 {
        self.value.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
    }
}

/// What a field holds, for messages, and the values it may take.
struct FieldSpec {
    what: &'static str,
    min: i64,
    max: i64,
}

/// The fields of one kind of data line.
struct LineShape {
    layout: &'static str,
    star_allowed: bool,
    specs: [FieldSpec; 5],
}

const GROUP_ID: FieldSpec = FieldSpec {
    what: "a group id",
    min: -MAX_GROUP_ID,
    max: MAX_GROUP_ID,
};
const COLOUR: FieldSpec = FieldSpec {
    what: "a colour component",
    min: -MAX_GROUP_ID,
    max: MAX_GROUP_ID,
};
const SIZE: FieldSpec = FieldSpec {
    what: "a size in percent of a cell",
    min: -MAX_GROUP_ID,
    max: MAX_GROUP_ID,
};
const MODULE_ID: FieldSpec = FieldSpec {
    what: "a module id",
    min: 0,
    max: u32::MAX as i64,
};
const COORDINATE: FieldSpec = FieldSpec {
    what: "a coordinate",
    min: -MAX_COORDINATE,
    max: MAX_COORDINATE,
};
const ANCHOR_CODE: FieldSpec = FieldSpec {
    what: "an anchor direction code",
    min: i32::MIN as i64,
    max: i32::MAX as i64,
};
const DISPLACEMENT: FieldSpec = FieldSpec {
    what: "a displacement",
    min: -MAX_COORDINATE,
    max: MAX_COORDINATE,
};

const GROUP_LINE: LineShape = LineShape {
    layout: "`id, red, green, blue, size%` of a group",
    star_allowed: false,
    specs: [GROUP_ID, COLOUR, COLOUR, COLOUR, SIZE],
};
const MODULE_LINE: LineShape = LineShape {
    layout: "`id, group, x, y, z` of a module",
    star_allowed: false,
    specs: [MODULE_ID, GROUP_ID, COORDINATE, COORDINATE, COORDINATE],
};
const MOVE_LINE: LineShape = LineShape {
    layout: "`[*]id, anchor code, dx, dy, dz` of a move",
    star_allowed: true,
    specs: [
        MODULE_ID,
        ANCHOR_CODE,
        DISPLACEMENT,
        DISPLACEMENT,
        DISPLACEMENT,
    ],
};

/// Text as a message shows it: quoted and escaped so that tabs and control characters stay
/// visible, and cut short so that one enormous field cannot make an enormous message.
fn shown(text: impl Iterator<Item = char>) -> String {
    const SHOWN_CHARS: usize = 24;
    let mut text = text.peekable();
    if text.peek().is_none() {
        return "nothing".to_owned();
    }
    let head: String = text.by_ref().take(SHOWN_CHARS).collect();
    let cut = if text.peek().is_some() { "…" } else { "" };
    format!("{head:?}{cut}")
}

/// A scenario as text the viewer plays; see the module documentation for the layout.
pub fn write_scen(s: &Scenario) -> String {
    let mut lines = vec![
        one_line(&s.name),
        description_line(&s.description),
        CUBE_TYPE.to_owned(),
        String::new(),
    ];
    lines.extend(s.groups.iter().map(group_line));
    lines.push(String::new());
    lines.extend(s.modules.iter().map(module_line));
    let written_sets = s.sets.iter().filter(|set| !set.moves.is_empty());
    for (index, set) in written_sets.enumerate() {
        lines.push(String::new());
        let starred = index == 0 || set.checkpoint;
        lines.extend(
            (0..)
                .zip(&set.moves)
                .map(|(position, m)| move_line(m, starred && position == 0)),
        );
    }
    let mut text = lines.join("\n");
    text.push('\n');
    text
}

/// A header field kept on its line: a line break would end it and shift the header.
fn one_line(text: &str) -> String {
    text.replace(['\r', '\n'], " ")
}

/// An empty description would end the viewer's header a line early.
fn description_line(description: &str) -> String {
    if description.is_empty() {
        "-".to_owned()
    } else {
        one_line(description)
    }
}

fn group_line(group: &Group) -> String {
    let [red, green, blue] = group.colour;
    format!(
        "{}, {red}, {green}, {blue}, {}",
        group.id, group.size_percent
    )
}

fn module_line(module: &ScenModule) -> String {
    let [x, y, z] = module.position;
    format!("{}, {}, {x}, {y}, {z}", module.id, module.group)
}

fn move_line(m: &MoveLine, starred: bool) -> String {
    let [dx, dy, dz] = m.d;
    let star = if starred { "*" } else { "" };
    format!("{star}{}, {}, {dx}, {dy}, {dz}", m.id, m.code)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Our own small scenario, with `\r\n` line ends, stray spaces, comments, a comment-only
    /// line between sets, two blank lines between sets, and a `*` on a later line of a set.
    const EXAMPLE: &str = "Two towers\r\n\
        A pivot, two slides together, then two more\r\n\
        CUBE\r\n\
        \r\n\
        \x201, 200, 200, 200, 100 // the ground\r\n\
        7,255,0,0,85\r\n\
        \r\n\
        001, 1, 0, 0, 0\r\n\
        002, 1, 1, 0, 0\r\n\
        003, 1, 2, 0, 0\r\n\
        10, 7, 0, 0, 1 // the movers\r\n\
        11, 7, 2, 0, 1\r\n\
        \r\n\
        *10, 6, 1, 0, 0 // the first set\r\n\
        \r\n\
        // a comment-only line is blank\r\n\
        11, -1, 0, 1, 0\r\n\
        10, 0, 0, 1, 0\r\n\
        \r\n\
        \r\n\
        \x2011 , -2 , -1 , 0 , 1\r\n\
        * 10, 3, 1, 0, -1\r\n";

    fn group(line: usize, id: i64, colour: [i64; 3], size_percent: i64) -> Group {
        Group {
            line,
            id,
            colour,
            size_percent,
        }
    }

    fn module(line: usize, id: u32, group: i64, position: [i32; 3]) -> ScenModule {
        ScenModule {
            line,
            id,
            group,
            position,
        }
    }

    fn step(line: usize, starred: bool, id: u32, code: i64, d: [i32; 3]) -> MoveLine {
        MoveLine {
            line,
            starred,
            id,
            code,
            d,
        }
    }

    fn example() -> Scenario {
        Scenario {
            name: "Two towers".to_owned(),
            description: "A pivot, two slides together, then two more".to_owned(),
            groups: vec![
                group(5, 1, [200, 200, 200], 100),
                group(6, 7, [255, 0, 0], 85),
            ],
            modules: vec![
                module(8, 1, 1, [0, 0, 0]),
                module(9, 2, 1, [1, 0, 0]),
                module(10, 3, 1, [2, 0, 0]),
                module(11, 10, 7, [0, 0, 1]),
                module(12, 11, 7, [2, 0, 1]),
            ],
            sets: vec![
                MoveSet {
                    line: 14,
                    checkpoint: true,
                    moves: vec![step(14, true, 10, 6, [1, 0, 0])],
                },
                MoveSet {
                    line: 17,
                    checkpoint: false,
                    moves: vec![
                        step(17, false, 11, -1, [0, 1, 0]),
                        step(18, false, 10, 0, [0, 1, 0]),
                    ],
                },
                MoveSet {
                    line: 21,
                    checkpoint: true,
                    moves: vec![
                        step(21, false, 11, -2, [-1, 0, 1]),
                        step(22, true, 10, 3, [1, 0, -1]),
                    ],
                },
            ],
        }
    }

    /// The scenario with every line number set to 0, to compare contents only.
    fn without_lines(mut s: Scenario) -> Scenario {
        s.groups.iter_mut().for_each(|g| g.line = 0);
        s.modules.iter_mut().for_each(|m| m.line = 0);
        for set in &mut s.sets {
            set.line = 0;
            set.moves.iter_mut().for_each(|m| m.line = 0);
        }
        s
    }

    /// The stars as the writer puts them: on the first line of each checkpoint set.
    fn with_normal_stars(mut s: Scenario) -> Scenario {
        for set in &mut s.sets {
            for (index, m) in set.moves.iter_mut().enumerate() {
                m.starred = set.checkpoint && index == 0;
            }
        }
        s
    }

    #[test]
    fn reads_the_example() {
        assert_eq!(read_scen(EXAMPLE), Ok(example()));
    }

    #[test]
    fn writes_the_viewer_layout() {
        let written = write_scen(&example());
        assert_eq!(
            written,
            "Two towers\nA pivot, two slides together, then two more\nCUBE\n\n\
             1, 200, 200, 200, 100\n7, 255, 0, 0, 85\n\n\
             1, 1, 0, 0, 0\n2, 1, 1, 0, 0\n3, 1, 2, 0, 0\n10, 7, 0, 0, 1\n11, 7, 2, 0, 1\n\n\
             *10, 6, 1, 0, 0\n\n11, -1, 0, 1, 0\n10, 0, 0, 1, 0\n\n\
             *11, -2, -1, 0, 1\n10, 3, 1, 0, -1\n"
        );
    }

    #[test]
    fn round_trips_up_to_lines_and_stars() {
        let original = example();
        let again = read_scen(&write_scen(&original)).expect("the written example reads");
        assert_eq!(
            without_lines(again),
            without_lines(with_normal_stars(original))
        );
    }

    #[test]
    fn writes_a_readable_header_from_awkward_text() {
        let mut s = example();
        s.name = "two\nlines".to_owned();
        s.description = String::new();
        let again = read_scen(&write_scen(&s)).expect("the written text reads");
        assert_eq!(again.name, "two lines");
        assert_eq!(again.description, "-");
    }

    #[test]
    fn recognises_scenarios_by_content() {
        assert!(looks_like_scen(EXAMPLE));
        assert!(looks_like_scen(&write_scen(&example())));
        assert!(looks_like_scen(BASE));
        assert!(looks_like_scen("[draft]\nd\nCUBE\n\n"));
        assert!(looks_like_scen("x\nd\nCATOM\n\n1, 2, 3, 4, 5\n"));
        assert!(looks_like_scen("x\nd\ncube\n\n1, 2, 3, 4, 5\n"));
        assert!(!looks_like_scen("{\"modules\": []}"));
        assert!(!looks_like_scen(" [\n[\n[\n\n1,2,3,4,5\n]]]"));
        assert!(!looks_like_scen("C 1\nM 1 0 0 0\nM 2\n\n1,2,3,4,5\n"));
        assert!(!looks_like_scen("M 1 2 3\nE 1 2\nx\n\n"));
        assert!(!looks_like_scen(""));
        assert!(!looks_like_scen(
            "x\nd\nCUBE\n // not empty\n1, 2, 3, 4, 5\n"
        ));
    }

    /// Lines: 1 name, 2 description, 3 type, 4 empty, 5–6 groups, 7 blank, 8–9 modules,
    /// 10 blank, 11 a checkpoint set, 12–13 blank, 14 a second set.
    const BASE: &str = "name\ndescription\nCUBE\n\n\
        1, 10, 20, 30, 90\n2, 40, 50, 60, 100\n\n\
        1, 1, 0, 0, 0\n2, 2, 1, 0, 0\n\n\
        *2, 0, 1, 0, 0\n\n\n1, -1, 0, 1, 0\n";

    /// `BASE` with its 1-based line `number` replaced by `with` (which may hold several lines).
    fn replaced(number: usize, with: &str) -> String {
        BASE.split('\n')
            .enumerate()
            .map(|(index, line)| if index + 1 == number { with } else { line })
            .collect::<Vec<_>>()
            .join("\n")
    }

    fn assert_refused(text: &str, line: usize, column: usize, words: &str) {
        let refusal = read_scen(text).expect_err("the text is refused");
        assert_eq!(
            (refusal.line, refusal.column),
            (line, column),
            "refusal: {refusal}"
        );
        assert!(
            refusal.message.contains(words),
            "{words:?} is not in: {refusal}"
        );
    }

    #[test]
    fn reads_the_base() {
        let s = read_scen(BASE).expect("the base reads");
        assert_eq!(s.sets.len(), 2);
        assert!(s.sets.iter().all(|set| set.moves.len() == 1));
        assert_eq!((s.sets[0].line, s.sets[0].checkpoint), (11, true));
        assert_eq!((s.sets[1].line, s.sets[1].checkpoint), (14, false));
    }

    #[test]
    fn accepts_signs_leading_zeros_comments_and_trailing_blank_lines() {
        let text = replaced(8, "+001, 1, -0, +0, 0 / / spaces make this a comment too");
        let s = read_scen(&format!("{text}\n \n// end\n\n")).expect("the text reads");
        assert_eq!(s.modules[0].id, 1);
        assert_eq!(s.modules[0].position, [0, 0, 0]);
        assert_eq!(s.sets.len(), 2);
    }

    #[test]
    fn accepts_the_bounds() {
        let text = replaced(8, "4294967295, 1, -1000000, 1000000, 0");
        let text = text.replace("1, -1, 0, 1, 0", "4294967295, -2147483648, 0, 0, -1000000");
        let s = read_scen(&text).expect("the bounds read");
        assert_eq!(s.modules[0].id, u32::MAX);
        assert_eq!(s.sets[1].moves[0].code, i64::from(i32::MIN));
        let groups = replaced(5, "1, 0, 255, 0, 0\n-9007199254740991, 0, 0, 0, 0");
        assert_eq!(
            read_scen(&groups).map(|s| s.groups[1].id),
            Ok(-MAX_GROUP_ID)
        );
    }

    #[test]
    fn refuses_what_parse_int_would_guess() {
        assert_refused(&replaced(8, "1, 1, 1.5, 0, 0"), 8, 7, "decimal integer");
        assert_refused(
            &replaced(5, "0x10, 10, 20, 30, 90"),
            5,
            1,
            "decimal integer",
        );
        assert_refused(&replaced(14, "1, -1, 0, 1, 1e3"), 14, 14, "found \"1e3\"");
        assert_refused(&replaced(8, "1, 1, --1, 0, 0"), 8, 7, "decimal integer");
    }

    #[test]
    fn refuses_a_wrong_number_of_fields() {
        assert_refused(&replaced(5, "1, 10, 20, 30, 90, 5"), 5, 20, "found 6");
        assert_refused(&replaced(9, "2, 2, 1, 0 // no z"), 9, 11, "found 4");
        assert_refused(&replaced(8, "1, 1, 0, 0, 0,"), 8, 15, "found 6");
        assert_refused(&replaced(14, "*"), 14, 2, "found nothing");
    }

    #[test]
    fn refuses_empty_fields_where_the_digits_should_be() {
        assert_refused(&replaced(8, "1, , 0, 0, 0"), 8, 3, "found nothing");
        assert_refused(&replaced(8, ",1, 0, 0, 0"), 8, 1, "found nothing");
    }

    #[test]
    fn refuses_tabs_which_are_not_stripped() {
        assert_refused(&replaced(12, "\t"), 12, 1, "\"\\t\"");
        assert_refused(&replaced(10, "\t"), 10, 1, "a module id");
        assert_refused(&replaced(8, "1,\t1, 0, 0, 0"), 8, 3, "a group id");
    }

    #[test]
    fn counts_columns_in_characters_of_the_line_as_written() {
        assert_refused(&replaced(8, "1, é, 0, 0, 0"), 8, 4, "\"é\"");
        assert_refused(&replaced(8, "1, 1, 0, 0, 0é"), 8, 13, "\"0é\"");
        assert_refused(&replaced(9, "   2, 9, 1, 0, 0"), 9, 7, "found group 9");
        assert_refused(&replaced(9, "2,\r9, 1, 0, 0"), 9, 4, "found group 9");
    }

    #[test]
    fn refuses_duplicates_and_undeclared_ids() {
        assert_refused(&replaced(9, "001, 2, 1, 0, 0"), 9, 1, "first on line 8");
        assert_refused(
            &replaced(6, " 1, 40, 50, 60, 100"),
            6,
            2,
            "group 1 is declared twice",
        );
        assert_refused(&replaced(9, "2, 3, 1, 0, 0"), 9, 4, "found group 3");
        assert_refused(&replaced(14, "3, -1, 0, 1, 0"), 14, 1, "found module 3");
        assert_refused(&replaced(11, "  *5, 0, 1, 0, 0"), 11, 4, "found module 5");
    }

    #[test]
    fn refuses_values_out_of_range() {
        assert_refused(
            &replaced(8, "1, 1, 1000001, 0, 0"),
            8,
            7,
            "a coordinate from",
        );
        assert_refused(
            &replaced(8, "4294967296, 1, 0, 0, 0"),
            8,
            1,
            "a module id from 0",
        );
        assert_refused(&replaced(8, "-1, 1, 0, 0, 0"), 8, 1, "a module id from 0");
        assert_refused(
            &replaced(14, "1, 99999999999999999999999999999999, 0, 1, 0"),
            14,
            4,
            "\"999999999999999999999999\"…",
        );
        assert_refused(&replaced(14, "1, 2147483648, 0, 1, 0"), 14, 4, "anchor");
        assert_refused(
            &replaced(14, "1, 0, 0, -1000001, 0"),
            14,
            10,
            "displacement",
        );
        // Display only, kept as written: the planners' own files have components above 255.
        let bright = read_scen(&replaced(5, "1, 512, 20, 30, 101")).expect("read");
        assert_eq!(
            (bright.groups[0].colour, bright.groups[0].size_percent),
            ([512, 20, 30], 101)
        );
        assert_refused(
            &replaced(5, "1, 9007199254740992, 20, 30, 90"),
            5,
            4,
            "colour",
        );
        assert_refused(
            &replaced(5, "9007199254740992, 1, 2, 3, 4"),
            5,
            1,
            "group id",
        );
    }

    #[test]
    fn refuses_stars_outside_move_lines() {
        assert_refused(&replaced(5, "*1, 10, 20, 30, 90"), 5, 1, "checkpoint");
        assert_refused(&replaced(8, " *1, 1, 0, 0, 0"), 8, 2, "checkpoint");
        assert_refused(&replaced(14, "**1, -1, 0, 1, 0"), 14, 2, "decimal integer");
    }

    #[test]
    fn refuses_a_broken_header() {
        assert_refused("", 1, 1, "ends before the scenario's name");
        assert_refused("name", 2, 1, "ends before the description");
        assert_refused("name\n", 2, 1, "ends before the description");
        assert_refused("name\ndescription", 3, 1, "ends before the module type");
        assert_refused("name\ndescription\nCUBE", 4, 1, "ends after the header");
        assert_refused(&replaced(2, ""), 2, 1, "must not be empty");
        assert_refused(&replaced(2, "\r"), 2, 1, "must not be empty");
        assert_refused(&replaced(4, "   "), 4, 1, "empty line after the three");
        assert_refused(
            &replaced(4, "// groups"),
            4,
            1,
            "empty line after the three",
        );
    }

    #[test]
    fn refuses_other_module_types() {
        for other in ["RHOMBIC_DODECAHEDRON", "CATOM"] {
            assert_refused(&replaced(3, other), 3, 1, "reads only cube scenarios");
        }
        assert_refused(&replaced(3, "cube"), 3, 1, "found \"cube\"");
        assert_refused(&replaced(3, "CUBE "), 3, 1, "found \"CUBE \"");
        assert_refused(&replaced(3, ""), 3, 1, "found nothing");
    }

    #[test]
    fn refuses_a_second_blank_line_before_the_modules() {
        assert_refused(&replaced(4, "\n"), 5, 1, "read the groups as modules");
        assert_refused(&replaced(4, "\n // groups"), 5, 1, "second blank line");
        assert_refused(&replaced(7, "\n"), 8, 1, "read the modules as moves");
    }

    #[test]
    fn refuses_missing_blocks() {
        assert_refused(
            "name\ndescription\nCUBE\n\n",
            5,
            1,
            "ends before the groups",
        );
        assert_refused(
            "n\nd\nCUBE\n\n1, 2, 3, 4, 5",
            6,
            1,
            "ends before the modules",
        );
        assert_refused(
            "n\nd\nCUBE\n\n1, 2, 3, 4, 5\n",
            6,
            1,
            "ends before the modules",
        );
        assert_refused(
            "n\nd\nCUBE\n\n1, 2, 3, 4, 5\n\n",
            7,
            1,
            "ends before the modules",
        );
    }

    #[test]
    fn accepts_a_scenario_without_moves() {
        let s = read_scen("n\nd\nCUBE\n\n1, 2, 3, 4, 5\n\n0, 1, 0, 0, 0\n\n\n")
            .expect("a scenario without moves reads");
        assert!(s.sets.is_empty());
        assert_eq!(s.modules.len(), 1);
    }

    #[test]
    fn displays_where_and_why() {
        let refusal = read_scen(&replaced(8, "1, 1, 1.5, 0, 0")).expect_err("refused");
        assert!(refusal
            .to_string()
            .starts_with("line 8, column 7: expected a coordinate written as a decimal"));
    }
}
