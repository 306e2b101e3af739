//! The canonical layout of `.dr` source (`dynarole fmt`), keeping every comment.
//!
//! Layout: items separated by a blank line (one-line items may stay together), four-space
//! indentation, one element per line ending in `;` or ` &`, `, ` between arguments, blocks
//! opened and closed on their own lines. Blank lines between elements are kept (at most one).
//! Comments are put back before the node that follows them, or at the end of the line they
//! ended in the source.

use crate::ast::*;
use crate::lexer::Comment;
use std::fmt::Write;

const INDENT: &str = "    ";

/// Formats a whole file; `source` is the text it was parsed from (for comments and blank lines).
pub fn format_file(file: &SourceFile, source: &str) -> String {
    let mut printer = Printer {
        source,
        comments: &file.comments,
        next_comment: 0,
        out: String::new(),
    };
    let mut previous: Option<&Item> = None;
    for item in &file.items {
        if let Some(prev) = previous {
            let together = is_one_line(prev)
                && is_one_line(item)
                && !printer.blank_between(prev.span().end, item.span().start);
            printer.out.push_str(if together { "\n" } else { "\n\n" });
        }
        printer.leading_comments(item.span().start, 0);
        printer.item(item);
        printer.trailing_comment(item.span().end);
        previous = Some(item);
    }
    let rest = printer.comments.len();
    if printer.next_comment < rest && !file.items.is_empty() {
        printer.out.push('\n');
    }
    printer.leading_comments(u32::MAX, 0);
    let trimmed = printer.out.trim_end().len();
    printer.out.truncate(trimmed);
    if !printer.out.is_empty() {
        printer.out.push('\n');
    }
    printer.out
}

/// Formats items that have no source text (such as a generated reverse), without comments.
pub fn format_items(items: Vec<Item>) -> String {
    format_file(
        &SourceFile {
            items,
            comments: Vec::new(),
            names: Default::default(),
        },
        "",
    )
}

fn is_one_line(item: &Item) -> bool {
    !matches!(
        item,
        Item::Sequence(SequenceDecl {
            definition: SequenceDef::Body(_),
            ..
        })
    )
}

struct Printer<'a> {
    source: &'a str,
    comments: &'a [Comment],
    next_comment: usize,
    out: String,
}

impl Printer<'_> {
    /// Whether the source has an empty line between `from` and `to` (the first and last
    /// pieces of the gap are the ends of the lines the two nodes sit on, not lines of their own).
    fn blank_between(&self, from: u32, to: u32) -> bool {
        let gap = self.source.get(from as usize..to as usize).unwrap_or("");
        let lines: Vec<&str> = gap.split('\n').collect();
        lines.len() >= 3
            && lines[1..lines.len() - 1]
                .iter()
                .any(|l| l.trim().is_empty())
    }

    /// Prints, each on its own line, the comments that start before `offset`.
    fn leading_comments(&mut self, offset: u32, depth: usize) {
        while let Some(comment) = self.comments.get(self.next_comment) {
            if comment.span.start >= offset {
                break;
            }
            self.indent(depth);
            self.out.push_str(&comment.text);
            self.out.push('\n');
            self.next_comment += 1;
        }
    }

    /// Appends the comment that follows `offset` on the same source line, if any.
    fn trailing_comment(&mut self, offset: u32) {
        let Some(comment) = self.comments.get(self.next_comment) else {
            return;
        };
        let gap = self
            .source
            .get(offset as usize..comment.span.start as usize);
        let same_line = gap.is_some_and(|g| !g.contains('\n') && g.trim().is_empty());
        if comment.span.start >= offset && same_line && !comment.text.contains('\n') {
            self.out.push(' ');
            self.out.push_str(&comment.text);
            self.next_comment += 1;
        }
    }

    fn indent(&mut self, depth: usize) {
        for _ in 0..depth {
            self.out.push_str(INDENT);
        }
    }

    fn item(&mut self, item: &Item) {
        match item {
            Item::Robot(decl) => {
                let _ = write!(self.out, "robot {};", decl.name.name);
            }
            Item::Role(decl) => {
                let _ = write!(
                    self.out,
                    "role {} requires {};",
                    decl.name.name,
                    expr(&decl.predicate)
                );
            }
            Item::Sequence(decl) => match &decl.definition {
                SequenceDef::Reverse(target) => {
                    let _ = write!(
                        self.out,
                        "sequence {} = reverse {};",
                        decl.name.name, target.name
                    );
                }
                SequenceDef::Body(body) => {
                    let _ = write!(self.out, "sequence {} ", decl.name.name);
                    self.body(body, 0);
                }
            },
        }
    }

    /// Prints `{`, the elements one level deeper, and `}` at `depth`.
    fn body(&mut self, body: &Body, depth: usize) {
        self.out.push('{');
        let mut previous_end: Option<u32> = None;
        for element in &body.elements {
            self.out.push('\n');
            if previous_end.is_some_and(|end| self.blank_between(end, element.span.start)) {
                self.out.push('\n');
            }
            self.leading_comments(element.span.start, depth + 1);
            self.indent(depth + 1);
            self.element(element, depth + 1);
            let end = element.separator.span.end.max(element.span.end);
            self.trailing_comment(end);
            previous_end = Some(end);
        }
        self.out.push('\n');
        self.leading_comments(body.span.end.saturating_sub(1), depth + 1);
        self.indent(depth);
        self.out.push('}');
    }

    fn element(&mut self, element: &Element, depth: usize) {
        match &element.kind {
            ElementKind::Statement(s) => self.out.push_str(&statement(s)),
            ElementKind::Block(body) => {
                if body.synchronous.is_some() {
                    self.out.push_str(SYNC);
                    self.out.push(' ');
                }
                self.body(body, depth)
            }
            ElementKind::Call(call) => {
                if call.reverse.is_some() {
                    self.out.push_str("reverse ");
                }
                self.out.push_str(&call.name.name);
            }
        }
        self.out.push_str(match element.separator.kind {
            SeparatorKind::Sequential => ";",
            SeparatorKind::Parallel => " &",
        });
    }
}

/// `M3.Joint.rotateFromToBy(0, 324, false, 150)`
pub fn statement(s: &Statement) -> String {
    let index = s
        .index
        .as_ref()
        .map_or(String::new(), |i| format!("[{}]", arg(i)));
    let args: Vec<String> = s.args.iter().map(arg).collect();
    format!(
        "{}.{}{}.{}({})",
        s.label.name,
        s.part.name,
        index,
        s.method.name,
        args.join(", ")
    )
}

fn arg(a: &Arg) -> String {
    match &a.kind {
        ArgKind::Int(n) => n.to_string(),
        ArgKind::Bool(b) => b.to_string(),
        ArgKind::Constant(name) => format!("${name}"),
    }
}

pub fn expr(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Int(n) => n.to_string(),
        ExprKind::Bool(b) => b.to_string(),
        ExprKind::Constant(name) => format!("${name}"),
        ExprKind::Name(name) => name.name.clone(),
        ExprKind::Call { function, args } => {
            let args: Vec<String> = args.iter().map(expr).collect();
            format!("{}({})", function.name, args.join(", "))
        }
        ExprKind::Unary {
            op: UnaryOp::Not,
            operand,
        } => format!("!{}", expr(operand)),
        ExprKind::Unary {
            op: UnaryOp::Negate,
            operand,
        } => format!("-{}", expr(operand)),
        ExprKind::Binary { op, lhs, rhs } => format!("{} {} {}", expr(lhs), op.symbol(), expr(rhs)),
        ExprKind::Paren(inner) => format!("({})", expr(inner)),
    }
}
