//! Which of RoFI's formats a text is, decided from its content in this one place, and the
//! text read as a plan (configurations, each with the line it starts at): RoFI's old text
//! format (`C`, `M` and `E` lines; the `length`/`queue`/`cfgs` trailer of `rofi-reconfig`
//! stripped), a RofiWorld JSON object (one configuration) or an array of them (a plan), and
//! voxel JSON (one world or an array; `voxel.rs`).
//! dynarole's own RoFI file (a JSON object with a `robot` field) is the registry's to read.

use crate::module::RofiConfiguration;
use crate::old_format::read_old_format;
use crate::rofiworld::read_rofiworld;
use crate::voxel::read_voxel;
use serde_json::value::RawValue;
use std::fmt;

/// A format of RoFI's own tools.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The old ("Viki") text format: one or more `C` blocks of `M` and `E` lines.
    OldText,
    /// RofiWorld JSON: one world, or an array of worlds.
    RofiWorld,
    /// Voxel JSON (`bodies`, what `rofi-voxel` reads and writes): one world, or an array.
    Voxel,
}

impl Format {
    pub fn name(self) -> &'static str {
        match self {
            Format::OldText => "RoFI's old text format",
            Format::RofiWorld => "RofiWorld JSON",
            Format::Voxel => "RoFI's voxel JSON",
        }
    }

    /// Whether the format names its modules (voxel worlds do not: their modules are numbered
    /// in the order of their bodies, and compared by shape alone).
    pub fn names_modules(self) -> bool {
        self != Format::Voxel
    }
}

/// The format `text` is in, or `None` when it is none of RoFI's: JSON whose world (the
/// object, or the array's first element) has a `bodies` field is voxel JSON; other JSON that
/// opens with `[`, or with `{` and has no top-level `robot` field, is RofiWorld; text whose first line that
/// is not blank or a comment starts with `C`, `M` or `E` is the old format.
pub fn recognise(text: &str) -> Option<Format> {
    let start = text.trim_start();
    let json = start.starts_with('[') || start.starts_with('{');
    if json && crate::voxel::is_voxel_json(text) {
        return Some(Format::Voxel);
    }
    if start.starts_with('[') {
        return Some(Format::RofiWorld);
    }
    if start.starts_with('{') {
        return (!has_robot_field(text)).then_some(Format::RofiWorld);
    }
    let first = text
        .lines()
        .map(str::trim)
        .find(|line| !line.is_empty() && !line.starts_with('#'))?;
    // A `C` line alone, or `M`/`E` and a number: another tool's text that starts with one of
    // these letters (a scenario named `M-shape`, `C` of something) is not taken for RoFI's.
    let mut words = first.split_whitespace();
    let numeric = |w: Option<&str>| w.is_some_and(|w| w.parse::<f64>().is_ok());
    let old = match words.next()? {
        "C" => words.next().is_none_or(|w| w.starts_with('#')),
        "M" | "E" => numeric(words.next()),
        _ => false,
    };
    old.then_some(Format::OldText)
}

/// Whether a JSON object has a top-level `robot` field (dynarole's own files do). A text that
/// is not a JSON object of fields says no.
fn has_robot_field(text: &str) -> bool {
    serde_json::from_str::<std::collections::BTreeMap<String, &RawValue>>(text)
        .is_ok_and(|fields| fields.contains_key("robot"))
}

/// Where in a file a reading error is: 1-based line and column, and the JSON path where the
/// format has one.
#[derive(Clone, Debug, PartialEq)]
pub struct FormatError {
    pub line: usize,
    pub column: usize,
    pub path: Option<String>,
    pub message: String,
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.path {
            Some(path) => write!(f, "at `{path}`: {}", self.message),
            None => self.message.fmt(f),
        }
    }
}

/// A plan as read: its configurations, each with the 1-based line where it starts, and for
/// each the index of the configuration of the file it stands for (the same index twice where
/// one configuration of the file is two steps: a voxel world whose turn makes connections).
#[derive(Clone, Debug, PartialEq)]
pub struct ReadPlan {
    pub configurations: Vec<(usize, RofiConfiguration)>,
    pub indices: Vec<usize>,
}

/// The configurations of `text` in `format`.
pub fn read_plan(text: &str, format: Format) -> Result<ReadPlan, FormatError> {
    let one_each = |configurations: Vec<(usize, RofiConfiguration)>| ReadPlan {
        indices: (0..configurations.len()).collect(),
        configurations,
    };
    match format {
        Format::OldText => read_old_format(text)
            .map(|plan| one_each(plan.configurations))
            .map_err(|e| FormatError {
                line: e.line,
                column: e.column,
                path: None,
                message: e.message,
            }),
        Format::RofiWorld => {
            let worlds = read_rofiworld(text)
                .map_err(|e| located_in_worlds(text, (e.path, e.line, e.column), e.message))?;
            let lines = world_lines(text, worlds.len());
            Ok(one_each(lines.into_iter().zip(worlds).collect()))
        }
        Format::Voxel => {
            let plan = read_voxel(text)
                .map_err(|e| located_in_worlds(text, (e.path, e.line, e.column), e.message))?;
            let count = plan.configurations.last().map_or(0, |(k, _)| k + 1);
            let lines = world_lines(text, count);
            let (indices, configurations) = (plan.configurations.into_iter())
                .map(|(k, config)| (k, (lines.get(k).copied().unwrap_or(1), config)))
                .unzip();
            Ok(ReadPlan {
                configurations,
                indices,
            })
        }
    }
}

/// An error of a JSON format where the file has it: the JSON's own line and column for a
/// syntax error, else the line where the world its path names (`[k]...`) starts.
fn located_in_worlds(
    text: &str,
    (path, line, column): (String, usize, usize),
    message: String,
) -> FormatError {
    let (line, column) = if line > 0 {
        (line, column)
    } else {
        let world: Option<usize> = (path.strip_prefix('['))
            .and_then(|rest| rest.split(']').next())
            .and_then(|k| k.parse().ok());
        let lines = world_lines(text, world.map_or(1, |k| k + 1));
        (world.and_then(|k| lines.get(k).copied()).unwrap_or(1), 1)
    };
    FormatError {
        line,
        column,
        path: (!path.is_empty()).then_some(path),
        message,
    }
}

/// The line each of the `count` worlds starts at: the array's elements, or line 1 for one
/// world (the text was read already, so it is valid JSON).
fn world_lines(text: &str, count: usize) -> Vec<usize> {
    let line_at = |offset: usize| text[..offset.min(text.len())].matches('\n').count() + 1;
    match serde_json::from_str::<Vec<&RawValue>>(text) {
        Ok(items) => (items.iter())
            .map(|item| line_at(item.get().as_ptr() as usize - text.as_ptr() as usize))
            .collect(),
        Err(_) => {
            let first = text.len() - text.trim_start().len();
            vec![line_at(first); count]
        }
    }
}
