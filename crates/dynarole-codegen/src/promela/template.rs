//! The Promela templates' small syntax. A `.pml` file of the runtime holds named parts, each
//! introduced by a line `@@ name` (what comes before the first is the file's own commentary).
//! In a part, `{{name}}` is replaced by a text, and a section `{{#flag}} .. {{/flag}}` (or
//! `{{^flag}} .. {{/flag}}`, its inverse) is kept or dropped by a flag. A section tag alone on
//! its line takes the whole line with it, so the template reads as the Promela it writes, and
//! so does a hole alone on its line whose value is empty (an empty list). Every
//! hole must be given and every value used: a part filled with the wrong names is an error
//! (the tests generate models with every option, which fills every part).

use std::fmt;

/// A `.pml` file of the runtime (`include_str!`ed), holding the parts.
#[derive(Debug)]
pub(crate) struct TemplateFile {
    pub path: &'static str,
    pub text: &'static str,
}

#[cfg(test)]
thread_local! {
    /// The parts rendered on this thread, for the test that every part is used.
    pub(crate) static RENDERED: std::cell::RefCell<Vec<(&'static str, &'static str)>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// The line that starts a part.
const PART: &str = "@@ ";

impl TemplateFile {
    /// The part `name` of the file.
    pub const fn part(&'static self, name: &'static str) -> Template {
        Template { file: self, name }
    }

    /// Every part: (name, the 1-based line of its first line, text).
    pub fn parts(&self) -> Vec<(&'static str, usize, &'static str)> {
        let text = self.text;
        let mut parts: Vec<(&'static str, usize, &'static str)> = Vec::new();
        // The part being read: (name, first line, first byte).
        let mut current: Option<(&'static str, usize, usize)> = None;
        let mut offset = 0;
        for (index, line) in text.split_inclusive('\n').enumerate() {
            if let Some(name) = line.strip_prefix(PART) {
                if let Some((n, l, start)) = current {
                    parts.push((n, l, text.get(start..offset).unwrap_or("")));
                }
                current = Some((name.trim(), index + 2, offset + line.len()));
            }
            offset += line.len();
        }
        if let Some((n, l, start)) = current {
            parts.push((n, l, text.get(start..).unwrap_or("")));
        }
        parts
    }
}

/// One part of a template file.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Template {
    file: &'static TemplateFile,
    name: &'static str,
}

/// The values of a template's holes and flags.
#[derive(Default)]
pub(crate) struct Holes<'a> {
    texts: Vec<(&'a str, String)>,
    flags: Vec<(&'a str, bool)>,
}

impl<'a> Holes<'a> {
    pub fn new() -> Self {
        Holes::default()
    }

    /// `{{name}}` is `value`.
    pub fn text(mut self, name: &'a str, value: impl fmt::Display) -> Self {
        self.texts.push((name, value.to_string()));
        self
    }

    /// Sections `{{#name}}` are kept when `value`, `{{^name}}` when not.
    pub fn flag(mut self, name: &'a str, value: bool) -> Self {
        self.flags.push((name, value));
        self
    }
}

/// A template and the values given to it do not match.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct TemplateError {
    pub file: &'static str,
    pub part: &'static str,
    /// 1-based, in the file; 0 when the error is not on one line (a value never used).
    pub line: usize,
    pub message: String,
}

impl fmt::Display for TemplateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "template {}:{} (part {}): {}",
            self.file, self.line, self.part, self.message
        )
    }
}

/// One piece of a line: text, or a tag between `{{` and `}}`.
#[derive(Debug, PartialEq, Eq)]
enum Piece<'t> {
    Text(&'t str),
    Hole(&'t str),
    Open(&'t str),
    Inverse(&'t str),
    Close(&'t str),
}

/// Splits a line into text and tags.
fn pieces<'t>(line: &'t str) -> Result<Vec<Piece<'t>>, String> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(at) = rest.find("{{") {
        if at > 0 {
            out.push(Piece::Text(&rest[..at]));
        }
        let after = &rest[at + 2..];
        let Some(end) = after.find("}}") else {
            return Err("`{{` without its `}}`".into());
        };
        let tag = &after[..end];
        let (kind, name): (fn(&'t str) -> Piece<'t>, &'t str) = match tag.as_bytes().first() {
            Some(b'#') => (Piece::Open, &tag[1..]),
            Some(b'^') => (Piece::Inverse, &tag[1..]),
            Some(b'/') => (Piece::Close, &tag[1..]),
            _ => (Piece::Hole, tag),
        };
        if name.is_empty()
            || !name
                .bytes()
                .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_')
        {
            return Err(format!(
                "`{{{{{tag}}}}}`: a name is lower-case letters, digits and `_`"
            ));
        }
        out.push(kind(name));
        rest = &after[end + 2..];
    }
    if !rest.is_empty() {
        out.push(Piece::Text(rest));
    }
    Ok(out)
}

/// Whether the pieces are one section tag and blanks (the line is the tag's own).
fn standalone(pieces: &[Piece<'_>]) -> bool {
    let tags = pieces
        .iter()
        .filter(|p| !matches!(p, Piece::Text(_)))
        .count();
    tags == 1
        && pieces.iter().all(|p| match p {
            Piece::Text(t) => t.trim().is_empty(),
            Piece::Hole(_) => false,
            _ => true,
        })
}

/// Whether the pieces are one hole and blanks and the hole's value is empty (an empty list:
/// the line goes, not only the value).
fn empty_list(pieces: &[Piece<'_>], holes: &Holes<'_>) -> bool {
    let mut names = pieces.iter().filter_map(|p| match p {
        Piece::Hole(name) => Some(*name),
        _ => None,
    });
    let (Some(name), None) = (names.next(), names.next()) else {
        return false;
    };
    pieces.iter().all(|p| match p {
        Piece::Text(t) => t.trim().is_empty(),
        Piece::Hole(_) => true,
        _ => false,
    }) && holes
        .texts
        .iter()
        .any(|(n, value)| *n == name && value.is_empty())
}

impl Template {
    /// The template with its holes filled; `Err` when a hole has no value, a value has no
    /// hole, a name is used both as a hole and as a section, or sections do not nest.
    pub fn render(&self, holes: &Holes<'_>) -> Result<String, TemplateError> {
        let err = |line: usize, message: String| TemplateError {
            file: self.file.path,
            part: self.name,
            line,
            message,
        };
        let parts = self.file.parts();
        let Some(&(_, first, text)) = parts.iter().find(|(name, _, _)| *name == self.name) else {
            return Err(err(0, "no such part in the file".into()));
        };
        let mut out = String::with_capacity(text.len());
        // The open sections: (name, kept).
        let mut open: Vec<(&str, bool)> = Vec::new();
        let mut used: Vec<&str> = Vec::new();
        for (index, line) in text.split_inclusive('\n').enumerate() {
            let number = first + index;
            let (body, newline) = match line.strip_suffix('\n') {
                Some(body) => (body, "\n"),
                None => (line, ""),
            };
            let pieces = pieces(body).map_err(|m| err(number, m))?;
            let alone = standalone(&pieces) || empty_list(&pieces, holes);
            for piece in &pieces {
                let kept = open.iter().all(|(_, k)| *k);
                match *piece {
                    Piece::Text(t) => {
                        if kept && !alone {
                            out.push_str(t);
                        }
                    }
                    Piece::Hole(name) => {
                        let Some((_, value)) = holes.texts.iter().find(|(n, _)| *n == name) else {
                            return Err(err(number, format!("no value for the hole `{name}`")));
                        };
                        used.push(name);
                        if kept {
                            out.push_str(value);
                        }
                    }
                    Piece::Open(name) | Piece::Inverse(name) => {
                        let Some((_, value)) = holes.flags.iter().find(|(n, _)| *n == name) else {
                            return Err(err(number, format!("no flag for the section `{name}`")));
                        };
                        used.push(name);
                        open.push((name, *value == matches!(piece, Piece::Open(_))));
                    }
                    Piece::Close(name) => match open.pop() {
                        Some((o, _)) if o == name => {}
                        Some((o, _)) => {
                            return Err(err(number, format!("`{{{{/{name}}}}}` closes `{o}`")))
                        }
                        None => {
                            return Err(err(number, format!("`{{{{/{name}}}}}` closes nothing")))
                        }
                    },
                }
            }
            if !alone && open.iter().all(|(_, k)| *k) {
                out.push_str(newline);
            }
        }
        if let Some((name, _)) = open.last() {
            return Err(err(0, format!("the section `{name}` is never closed")));
        }
        let names = holes.texts.iter().map(|(n, _)| *n);
        if let Some(unused) = names
            .chain(holes.flags.iter().map(|(n, _)| *n))
            .find(|n| !used.contains(n))
        {
            return Err(err(
                0,
                format!("`{unused}` is given but the template has no such hole or section"),
            ));
        }
        #[cfg(test)]
        RENDERED.with(|r| r.borrow_mut().push((self.file.path, self.name)));
        Ok(out)
    }

    /// [`Template::render`] for the writers, whose templates and values are fixed in the
    /// code: a mismatch is a bug, which every test run catches (debug builds stop on it); a
    /// release build writes a `#error` line, so that spin refuses the model with the reason.
    pub fn fill(&self, holes: &Holes<'_>) -> String {
        match self.render(holes) {
            Ok(text) => text,
            Err(e) => {
                if cfg!(debug_assertions) {
                    panic!("{e}");
                }
                format!("#error {e}\n")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: TemplateFile = TemplateFile {
        path: "test.pml",
        text: concat!(
            "commentary\n",
            "@@ list\nbefore\n    {{items}}\nafter\n",
            "@@ t\na {{x}} b\n    {{#f}}\nkept if f\n    {{/f}}\n",
            "{{^f}}\nkept if not f\n{{/f}}\nc{{#g}} and g{{/g}}.\n",
            "@@ bad\n{{#a}}\n{{#b}}\n{{/a}}\n{{/b}}\n",
            "@@ open\n{{#a}}\n",
            "@@ syntax\n{{A}}\n",
        ),
    };
    const T: Template = FILE.part("t");

    #[test]
    fn holes_and_sections_are_filled_and_section_lines_vanish() {
        let on = T.render(&Holes::new().text("x", 1).flag("f", true).flag("g", false));
        assert_eq!(on, Ok("a 1 b\nkept if f\nc.\n".to_string()));
        let off = T.render(&Holes::new().text("x", "y").flag("f", false).flag("g", true));
        assert_eq!(off, Ok("a y b\nkept if not f\nc and g.\n".to_string()));
    }

    #[test]
    fn an_empty_list_alone_on_its_line_takes_the_line() {
        let list = FILE.part("list");
        let empty = list.render(&Holes::new().text("items", ""));
        assert_eq!(empty, Ok("before\nafter\n".to_string()));
        let one = list.render(&Holes::new().text("items", "x"));
        assert_eq!(one, Ok("before\n    x\nafter\n".to_string()));
    }

    #[test]
    fn a_missing_or_unknown_hole_is_an_error() {
        let missing = T.render(&Holes::new().flag("f", true).flag("g", true));
        assert_eq!(missing.map_err(|e| e.line), Err(7));
        let unknown = T.render(
            &Holes::new()
                .text("x", 1)
                .flag("f", true)
                .flag("g", true)
                .text("z", 2),
        );
        assert!(unknown.is_err_and(|e| e.message.contains("`z`")));
        let as_flag = T.render(&Holes::new().flag("x", true).flag("f", true).flag("g", true));
        assert!(as_flag.is_err());
    }

    #[test]
    fn sections_must_nest_and_parts_exist() {
        let holes = Holes::new().flag("a", true).flag("b", true);
        assert_eq!(FILE.part("bad").render(&holes).map_err(|e| e.line), Err(18));
        assert!(FILE
            .part("open")
            .render(&Holes::new().flag("a", true))
            .is_err());
        assert!(FILE.part("syntax").render(&Holes::new()).is_err());
        assert!(FILE.part("none").render(&Holes::new()).is_err());
    }
}
