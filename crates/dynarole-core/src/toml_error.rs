//! Errors in the TOML files users write (robot plugins, scenarios, campaigns) as data: the
//! field, what is wrong, where in the text, and a hint. The CLI renders them with a snippet and
//! a caret, like the diagnostics of `.dr` files.

use std::ops::Range;

/// An error in a TOML file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TomlError {
    /// Dotted path of the field, such as `part[1].operation[0].inverse`; empty when the error is
    /// about the text itself (it does not parse).
    pub field: String,
    /// What is wrong, and what was expected.
    pub message: String,
    /// The bytes of the text the error is about (the field's value when it is written),
    /// `None` until [`TomlError::locate`] found it.
    pub span: Option<Range<usize>>,
    /// A likely fix (the closest known name for an unknown one).
    pub hint: Option<String>,
}

impl std::fmt::Display for TomlError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.field.is_empty() {
            f.write_str(&self.message)
        } else {
            write!(f, "field `{}`: {}", self.field, self.message)
        }
    }
}

impl std::error::Error for TomlError {}

impl TomlError {
    /// An error found after parsing, in `field`; its span comes from [`TomlError::locate`].
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> TomlError {
        TomlError {
            field: field.into(),
            message: message.into(),
            span: None,
            hint: None,
        }
    }

    /// An error of the TOML parser or of the typed reading of its tables, at the place toml
    /// reports, with the closest name as a hint for an unknown key or variant.
    pub fn from_de(e: &toml::de::Error) -> TomlError {
        // The parser's message may take several lines ("invalid string", "expected ..."), or
        // none at all (a control character inside a comment).
        let message = e
            .message()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join("; ");
        let message = if message.is_empty() {
            "this is not valid TOML here (a control character, or a broken line)".to_string()
        } else {
            message
        };
        TomlError {
            field: String::new(),
            message,
            span: e.span(),
            hint: unknown_name_hint(e.message()),
        }
    }

    /// The same error for a field of a table nested at `prefix` (a scenario inside a campaign).
    pub fn nested_in(mut self, prefix: &str) -> TomlError {
        self.field = match self.field.is_empty() {
            true => prefix.to_string(),
            false => format!("{prefix}.{}", self.field),
        };
        self
    }

    /// Finds the span of the field in `text` when it is not known yet: the field's value when
    /// it is written, else the nearest enclosing table or key that is.
    pub fn locate(mut self, text: &str) -> TomlError {
        if self.span.is_none() && !self.field.is_empty() {
            self.span = field_span(text, &self.field);
        }
        self
    }
}

/// serde writes ``unknown field `x`, expected one of `a`, `b` `` (and the same for variants,
/// and the protocol table for its names: ``unknown protocol `x`, expected ...``): the first
/// quoted name is the unknown one, the others are the candidates.
fn unknown_name_hint(message: &str) -> Option<String> {
    if !message.starts_with("unknown ") || !message.contains("`, expected ") {
        return None;
    }
    let quoted: Vec<&str> = message.split('`').skip(1).step_by(2).collect();
    let (unknown, candidates) = quoted.split_first()?;
    // The message already lists the candidates; the hint only adds a likely typo's fix.
    crate::suggest::did_you_mean(unknown, candidates.iter().copied())
}

/// One step of a field path: `name` or `[index]`.
enum Step<'a> {
    Key(&'a str),
    Index(usize),
}

/// `part[1].operation[0].inverse` as keys and indices; `None` for a malformed path.
fn steps(field: &str) -> Option<Vec<Step<'_>>> {
    let mut out = Vec::new();
    for segment in field.split('.') {
        let (name, indices) = segment.split_at(segment.find('[').unwrap_or(segment.len()));
        if !name.is_empty() {
            out.push(Step::Key(name));
        }
        for index in indices.split('[').filter(|s| !s.is_empty()) {
            out.push(Step::Index(index.strip_suffix(']')?.parse().ok()?));
        }
    }
    Some(out)
}

/// A place in a parsed TOML document.
#[derive(Clone, Copy)]
enum Node<'a> {
    Item(&'a toml_edit::Item),
    Value(&'a toml_edit::Value),
    Table(&'a toml_edit::Table),
}

impl<'a> Node<'a> {
    fn span(self) -> Option<Range<usize>> {
        match self {
            Node::Item(i) => i.span(),
            Node::Value(v) => v.span(),
            Node::Table(t) => t.span(),
        }
    }

    /// The child at `step`, with the span of its key when it has one.
    fn child(self, step: &Step) -> Option<(Node<'a>, Option<Range<usize>>)> {
        let keyed = |found: Option<(&'a toml_edit::Key, &'a toml_edit::Item)>| {
            found.map(|(key, item)| (Node::Item(item), key.span()))
        };
        match (self, step) {
            (Node::Item(i), Step::Key(k)) => keyed(i.as_table_like()?.get_key_value(k)),
            (Node::Value(v), Step::Key(k)) => keyed(v.as_inline_table()?.get_key_value(k)),
            (Node::Table(t), Step::Key(k)) => keyed(t.get_key_value(k)),
            (Node::Item(i), Step::Index(n)) => match i.as_array_of_tables() {
                Some(tables) => tables.get(*n).map(|t| (Node::Table(t), None)),
                None => i.as_array()?.get(*n).map(|v| (Node::Value(v), None)),
            },
            (Node::Value(v), Step::Index(n)) => {
                v.as_array()?.get(*n).map(|v| (Node::Value(v), None))
            }
            (Node::Table(_), Step::Index(_)) => None,
        }
    }
}

/// The span of `field`'s value in `text`, or of the deepest part of its path that is written.
fn field_span(text: &str, field: &str) -> Option<Range<usize>> {
    let document = toml_edit::ImDocument::parse(text).ok()?;
    let mut node = Node::Item(document.as_item());
    let mut best = None;
    for step in steps(field)? {
        let Some((child, key_span)) = node.child(&step) else {
            break;
        };
        best = child.span().or(key_span).or(best);
        node = child;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "name = \"g\"\n[[part]]\nname = \"P\"\n[[part]]\nname = \"Q\"\nmale = [1, 7]\nops = { inverse = \"x\" }\n";

    fn located(field: &str) -> Option<&'static str> {
        let span = TomlError::new(field, "m").locate(TEXT).span?;
        TEXT.get(span)
    }

    #[test]
    fn fields_are_found_down_to_their_value() {
        assert_eq!(located("name"), Some("\"g\""));
        assert_eq!(located("part[1].name"), Some("\"Q\""));
        assert_eq!(located("part[1].male[1]"), Some("7"));
        assert_eq!(located("part[1].ops.inverse"), Some("\"x\""));
        // Not written: the deepest written part of the path.
        assert_eq!(located("part[1].count"), located("part[1]"));
        assert_eq!(located("nothing"), None);
    }

    #[test]
    fn unknown_keys_get_the_closest_name() {
        let e = toml::from_str::<toml::Table>("a = ").expect_err("syntax");
        assert!(TomlError::from_de(&e).span.is_some());
        assert_eq!(
            unknown_name_hint("unknown field `conectors`, expected one of `name`, `connectors`"),
            Some("did you mean `connectors`?".into())
        );
        assert_eq!(
            unknown_name_hint("unknown field `zzz`, expected `name` or `joints`"),
            None
        );
        assert_eq!(
            unknown_name_hint("unknown merge `jav`, expected one of `printed`, `java`, `c-port`"),
            Some("did you mean `java`?".into())
        );
        assert_eq!(unknown_name_hint("unknown module `M9`"), None);
    }
}
