//! The syntax tree of a `.dr` file, as written (before names are resolved).

use crate::lexer::Comment;
use crate::span::Span;
use std::collections::BTreeMap;

/// A whole source file: its items in order, and its comments (for the formatter).
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct SourceFile {
    pub items: Vec<Item>,
    pub comments: Vec<Comment>,
    /// Built from `items` on first look-up; the items must not change after.
    pub names: NameIndex,
}

/// For each declared name, the item of its first role and of its first sequence, so that a
/// look-up costs a logarithm, not a scan of the file (which made files with many
/// declarations and statements quadratic). Not part of a file's value: any two compare equal.
#[derive(Clone, Debug, Default)]
pub struct NameIndex(std::sync::OnceLock<BTreeMap<String, Declared>>);

/// The item of the first role, and of the first sequence, of one name.
type Declared = (Option<usize>, Option<usize>);

impl PartialEq for NameIndex {
    fn eq(&self, _: &NameIndex) -> bool {
        true
    }
}

impl Eq for NameIndex {}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Item {
    /// `robot NAME;`
    Robot(RobotDecl),
    /// `role Wheel requires connected($CONNECTOR_0) && id != 3;`
    Role(RoleDecl),
    /// `sequence eight2car { ... }` or `sequence car2eight = reverse eight2car;`
    Sequence(SequenceDecl),
}

impl Item {
    pub fn span(&self) -> Span {
        match self {
            Item::Robot(decl) => decl.span,
            Item::Role(decl) => decl.span,
            Item::Sequence(decl) => decl.span,
        }
    }
}

/// A name as written, with where it was written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RobotDecl {
    pub name: Ident,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RoleDecl {
    pub name: Ident,
    pub predicate: Expr,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SequenceDecl {
    pub name: Ident,
    pub definition: SequenceDef,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SequenceDef {
    /// `{ statement sep statement sep ... }`
    Body(Body),
    /// `= reverse other;`
    Reverse(Ident),
}

/// The word before a synchronous group's `{` (not a keyword: a name elsewhere). The parser
/// and the formatter both read it here.
pub const SYNC: &str = "sync";

/// The inside of a sequence or of a block: elements, each closed by a separator.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Body {
    pub elements: Vec<Element>,
    /// From the `{` to the `}`.
    pub span: Span,
    /// `sync { A & B; }`: the `sync` word, when the block is a synchronous group (its
    /// motions start at one agreed instant and move in lock-step; docs/language.md).
    pub synchronous: Option<Span>,
}

/// One element of a body and the separator that follows it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Element {
    pub kind: ElementKind,
    pub separator: Separator,
    /// The element without its separator.
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ElementKind {
    /// `M3.Joint.rotateFromToBy(0, 324, false, 150)`
    Statement(Statement),
    /// `{ A; B }`: a nested body, run as one element of the enclosing group; also
    /// `sync { A & B; }` (the body says it is synchronous).
    Block(Body),
    /// `eight2snake` or `reverse eight2snake`: another sequence, run in place.
    Call(Call),
}

/// `;` (the next element depends on this one) or `&` (it does not).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeparatorKind {
    Sequential,
    Parallel,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Separator {
    pub kind: SeparatorKind,
    /// Empty when the separator is missing (already reported by the parser).
    pub span: Span,
}

/// `LABEL.Part[INDEX].method(ARGS)` or `LABEL.Part.method(ARGS)`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Statement {
    pub label: Ident,
    pub part: Ident,
    pub index: Option<Arg>,
    pub method: Ident,
    pub args: Vec<Arg>,
    /// From `(` to `)`, used to point at a wrong number of arguments.
    pub args_span: Span,
}

/// A use of another sequence inside a body.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Call {
    /// The `reverse` keyword, when the call runs the other sequence backwards.
    pub reverse: Option<Span>,
    pub name: Ident,
}

/// An argument of an operation, or the index of a part.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Arg {
    pub kind: ArgKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ArgKind {
    Int(i64),
    Bool(bool),
    /// `$NAME`, defined by the robot plugin.
    Constant(String),
}

/// A role predicate, over the module's local state and its immediate neighbours.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ExprKind {
    Int(i64),
    Bool(bool),
    Constant(String),
    /// A query with no arguments, such as `id` or `neighbours`.
    Name(Ident),
    /// A query with arguments, such as `connected($CONNECTOR_0)`.
    Call {
        function: Ident,
        args: Vec<Expr>,
    },
    Unary {
        op: UnaryOp,
        operand: Box<Expr>,
    },
    Binary {
        op: BinaryOp,
        lhs: Box<Expr>,
        rhs: Box<Expr>,
    },
    /// Kept so that the formatter can print the parentheses the author wrote.
    Paren(Box<Expr>),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnaryOp {
    Not,
    Negate,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinaryOp {
    Or,
    And,
    Eq,
    NotEq,
    Lt,
    Le,
    Gt,
    Ge,
}

impl BinaryOp {
    pub fn symbol(self) -> &'static str {
        match self {
            BinaryOp::Or => "||",
            BinaryOp::And => "&&",
            BinaryOp::Eq => "==",
            BinaryOp::NotEq => "!=",
            BinaryOp::Lt => "<",
            BinaryOp::Le => "<=",
            BinaryOp::Gt => ">",
            BinaryOp::Ge => ">=",
        }
    }

    /// Binding strength: `||` < `&&` < comparisons.
    pub fn precedence(self) -> u8 {
        match self {
            BinaryOp::Or => 1,
            BinaryOp::And => 2,
            _ => 3,
        }
    }
}

impl SourceFile {
    pub fn sequences(&self) -> impl Iterator<Item = &SequenceDecl> {
        self.items.iter().filter_map(|item| match item {
            Item::Sequence(decl) => Some(decl),
            _ => None,
        })
    }

    pub fn roles(&self) -> impl Iterator<Item = &RoleDecl> {
        self.items.iter().filter_map(|item| match item {
            Item::Role(decl) => Some(decl),
            _ => None,
        })
    }

    pub fn sequence(&self, name: &str) -> Option<&SequenceDecl> {
        let (_, item) = self.declared(name)?;
        match self.items.get(item?)? {
            Item::Sequence(decl) => Some(decl),
            _ => None,
        }
    }

    /// The first role named `name`, with its place among the items (declaration order).
    pub fn role(&self, name: &str) -> Option<(usize, &RoleDecl)> {
        let (item, _) = self.declared(name)?;
        let item = item?;
        match self.items.get(item)? {
            Item::Role(decl) => Some((item, decl)),
            _ => None,
        }
    }

    /// Whether a role is named `name`.
    pub fn has_role(&self, name: &str) -> bool {
        self.declared(name).is_some_and(|(role, _)| role.is_some())
    }

    /// The items of the first role and the first sequence named `name`.
    fn declared(&self, name: &str) -> Option<Declared> {
        let index = self.names.0.get_or_init(|| {
            let mut index: BTreeMap<String, Declared> = BTreeMap::new();
            for (i, item) in self.items.iter().enumerate() {
                let (name, is_role) = match item {
                    Item::Role(d) => (&d.name.name, true),
                    Item::Sequence(d) => (&d.name.name, false),
                    Item::Robot(_) => continue,
                };
                let entry = index.entry(name.clone()).or_default();
                let slot = if is_role { &mut entry.0 } else { &mut entry.1 };
                slot.get_or_insert(i);
            }
            index
        });
        index.get(name).copied()
    }
}
