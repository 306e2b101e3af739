//! Recursive-descent parser: tokens to [`SourceFile`], never stopping at the first error.
//!
//! Every syntax error becomes a [`Diagnostic`]; the parser then skips to a point where it can
//! go on (the next separator, closing brace or item keyword), so one run reports every error.
//! Nesting is bounded by [`MAX_NESTING`] so that no input can exhaust the stack.

use crate::ast::*;
use crate::diagnostic::{Diagnostic, DiagnosticKind};
use crate::lexer::{lex, Token};
use crate::span::Span;

/// Deepest nesting of blocks or of predicate sub-expressions the parser accepts.
pub const MAX_NESTING: usize = 64;

pub use crate::limits::MAX_SYNTAX_ERRORS;

/// Most binary operators in one role predicate. A chain `a || b || ...` is a tree as deep as it
/// is long, and later passes walk trees recursively.
pub const MAX_OPERATORS: usize = 1000;

/// The tree (with the well-formed parts of a broken file) and the syntax diagnostics.
#[derive(Debug)]
pub struct Parsed {
    pub file: SourceFile,
    pub diagnostics: Vec<Diagnostic>,
}

pub fn parse(source: &str) -> Parsed {
    let lexed = lex(source);
    let mut parser = Parser {
        tokens: lexed.tokens,
        pos: 0,
        diagnostics: lexed.errors,
        depth: 0,
        operators: 0,
    };
    let items = parser.items();
    let mut diagnostics = parser.diagnostics;
    diagnostics.sort_by_key(|d| d.span);
    Parsed {
        file: SourceFile {
            items,
            comments: lexed.comments,
            names: NameIndex::default(),
        },
        diagnostics,
    }
}

struct Parser {
    tokens: Vec<(Token, Span)>,
    pos: usize,
    diagnostics: Vec<Diagnostic>,
    depth: usize,
    /// Binary operators read so far in the current role predicate.
    operators: usize,
}

/// Marker for "this construct is broken and already reported".
struct Broken;

type Parse<T> = Result<T, Broken>;

impl Parser {
    // ---------- token access ----------

    fn peek(&self) -> &Token {
        self.tokens.get(self.pos).map_or(&Token::Eof, |(t, _)| t)
    }

    fn peek_at(&self, ahead: usize) -> &Token {
        self.tokens
            .get(self.pos + ahead)
            .map_or(&Token::Eof, |(t, _)| t)
    }

    fn span(&self) -> Span {
        self.tokens
            .get(self.pos)
            .or(self.tokens.last())
            .map_or(Span::default(), |(_, s)| *s)
    }

    fn previous_span(&self) -> Span {
        match self.pos.checked_sub(1).and_then(|i| self.tokens.get(i)) {
            Some((_, span)) => *span,
            None => self.span(),
        }
    }

    fn bump(&mut self) -> (Token, Span) {
        let current = self
            .tokens
            .get(self.pos)
            .cloned()
            .unwrap_or((Token::Eof, Span::default()));
        if current.0 != Token::Eof {
            self.pos += 1;
        }
        current
    }

    fn at(&self, token: &Token) -> bool {
        self.peek() == token
    }

    fn eat(&mut self, token: &Token) -> Option<Span> {
        if self.at(token) {
            Some(self.bump().1)
        } else {
            None
        }
    }

    /// Records a syntax error; past [`MAX_SYNTAX_ERRORS`] the parser says so once and skips
    /// to the end, so that a hostile file costs bounded memory and time.
    fn report(&mut self, kind: DiagnosticKind, span: Span) {
        if self.diagnostics.len() < MAX_SYNTAX_ERRORS {
            self.diagnostics.push(Diagnostic::new(kind, span));
            return;
        }
        let what = format!("more than {MAX_SYNTAX_ERRORS} syntax errors");
        self.diagnostics.push(Diagnostic::new(
            DiagnosticKind::InputTooLarge { what },
            span,
        ));
        self.pos = self.tokens.len().saturating_sub(1);
    }

    fn unexpected(&mut self, expected: &str) -> Broken {
        let found = self.peek().describe();
        let span = self.span();
        self.report(
            DiagnosticKind::UnexpectedToken {
                expected: expected.to_string(),
                found,
            },
            span,
        );
        Broken
    }

    fn expect(&mut self, token: &Token, expected: &str) -> Parse<Span> {
        match self.eat(token) {
            Some(span) => Ok(span),
            None => Err(self.unexpected(expected)),
        }
    }

    fn ident(&mut self, expected: &str) -> Parse<Ident> {
        match self.peek().clone() {
            Token::Ident(name) => {
                let span = self.bump().1;
                Ok(Ident { name, span })
            }
            _ => Err(self.unexpected(expected)),
        }
    }

    // ---------- recovery ----------

    /// Skips tokens until `stop` says so at brace depth 0; braces opened meanwhile are skipped
    /// whole. Never consumes an unmatched `}` or the end of the file.
    fn skip_until(&mut self, stop: impl Fn(&Token) -> bool) {
        let mut depth = 0usize;
        loop {
            let token = self.peek();
            if *token == Token::Eof || (depth == 0 && (stop(token) || *token == Token::RBrace)) {
                return;
            }
            match token {
                Token::LBrace => depth += 1,
                Token::RBrace => depth -= 1,
                _ => {}
            }
            self.bump();
        }
    }

    fn is_item_start(token: &Token) -> bool {
        matches!(token, Token::Robot | Token::Role | Token::Sequence)
    }

    // ---------- items ----------

    fn items(&mut self) -> Vec<Item> {
        let mut items = Vec::new();
        while !self.at(&Token::Eof) {
            let start = self.pos;
            let item = match self.peek() {
                Token::Robot => self.robot().map(Item::Robot),
                Token::Role => self.role().map(Item::Role),
                Token::Sequence => self.sequence().map(Item::Sequence),
                _ => Err(self.unexpected("`robot`, `role` or `sequence`")),
            };
            match item {
                Ok(item) => items.push(item),
                Err(Broken) => self.recover_item(),
            }
            if self.pos == start {
                // A stray `}` at top level: skip it so the loop always advances.
                self.bump();
            }
        }
        items
    }

    fn recover_item(&mut self) {
        self.skip_until(|t| *t == Token::Semi || Self::is_item_start(t));
        self.eat(&Token::Semi);
    }

    fn robot(&mut self) -> Parse<RobotDecl> {
        let start = self.bump().1;
        let name = self.ident("the robot's name (its plugin's `name`)")?;
        let end = self.expect(&Token::Semi, "`;`")?;
        Ok(RobotDecl {
            name,
            span: start.to(end),
        })
    }

    fn role(&mut self) -> Parse<RoleDecl> {
        let start = self.bump().1;
        let name = self.ident("the role's name")?;
        self.expect(&Token::Requires, "`requires`")?;
        let predicate = self.expr()?;
        let end = self.expect(&Token::Semi, "`;` after the predicate")?;
        Ok(RoleDecl {
            name,
            predicate,
            span: start.to(end),
        })
    }

    fn sequence(&mut self) -> Parse<SequenceDecl> {
        let start = self.bump().1;
        let name = self.ident("the sequence's name")?;
        if self.eat(&Token::Eq).is_some() {
            self.expect(&Token::Reverse, "`reverse`")?;
            let target = self.ident("the name of the sequence to reverse")?;
            let end = self.expect(&Token::Semi, "`;`")?;
            return Ok(SequenceDecl {
                name,
                definition: SequenceDef::Reverse(target),
                span: start.to(end),
            });
        }
        if !self.at(&Token::LBrace) {
            return Err(self.unexpected("`{` or `= reverse`"));
        }
        let errors_before = self.diagnostics.len();
        let body = self.body()?;
        let span = start.to(body.span);
        // An empty body that only looks empty because its statements were broken is not news.
        if body.elements.is_empty() && self.diagnostics.len() == errors_before {
            self.report(
                DiagnosticKind::EmptySequence {
                    name: name.name.clone(),
                },
                body.span,
            );
        }
        Ok(SequenceDecl {
            name,
            definition: SequenceDef::Body(body),
            span,
        })
    }

    // ---------- bodies ----------

    /// `{ element sep element sep ... }`, starting at the `{`.
    fn body(&mut self) -> Parse<Body> {
        let open = self.bump().1;
        if self.depth >= MAX_NESTING {
            self.report(DiagnosticKind::NestingTooDeep { limit: MAX_NESTING }, open);
            self.skip_until(|_| false);
            let close = self.eat(&Token::RBrace).unwrap_or(self.span());
            return Ok(Body {
                elements: Vec::new(),
                span: open.to(close),
                synchronous: None,
            });
        }
        self.depth += 1;
        let elements = self.elements();
        self.depth -= 1;
        let close = match self.eat(&Token::RBrace) {
            Some(span) => span,
            None => {
                self.unexpected("`}`");
                self.previous_span()
            }
        };
        Ok(Body {
            elements,
            span: open.to(close),
            synchronous: None,
        })
    }

    fn elements(&mut self) -> Vec<Element> {
        let mut elements: Vec<Element> = Vec::new();
        while !matches!(self.peek(), Token::RBrace | Token::Eof) {
            if Self::is_item_start(self.peek()) {
                break; // a missing `}`; reported by the caller
            }
            let start = self.span();
            match self.element_kind() {
                Ok(kind) => {
                    let span = start.to(self.previous_span());
                    let separator = self.separator(span);
                    elements.push(Element {
                        kind,
                        separator,
                        span,
                    });
                }
                Err(Broken) => {
                    self.skip_until(|t| matches!(t, Token::Semi | Token::Amp));
                    if matches!(self.peek(), Token::Semi | Token::Amp) {
                        self.bump();
                    }
                }
            }
        }
        if let Some(last) = elements.last() {
            if last.separator.kind == SeparatorKind::Parallel {
                self.report(DiagnosticKind::UnclosedParallelGroup, last.separator.span);
            }
        }
        elements
    }

    fn separator(&mut self, element: Span) -> Separator {
        match self.peek() {
            Token::Semi => Separator {
                kind: SeparatorKind::Sequential,
                span: self.bump().1,
            },
            Token::Amp => Separator {
                kind: SeparatorKind::Parallel,
                span: self.bump().1,
            },
            _ => {
                self.report(DiagnosticKind::MissingSeparator, element);
                Separator {
                    kind: SeparatorKind::Sequential,
                    span: element.after(),
                }
            }
        }
    }

    fn element_kind(&mut self) -> Parse<ElementKind> {
        match self.peek() {
            Token::LBrace => self.body().map(ElementKind::Block),
            // `sync` is a word only before `{`: elsewhere it stays a name (a sequence may be
            // called `sync`), and a name followed by `{` means nothing else.
            Token::Ident(word) if word == SYNC && *self.peek_at(1) == Token::LBrace => {
                let keyword = self.bump().1;
                let mut body = self.body()?;
                body.synchronous = Some(keyword);
                Ok(ElementKind::Block(body))
            }
            Token::Reverse => {
                let keyword = self.bump().1;
                let name = self.ident("the name of a sequence")?;
                Ok(ElementKind::Call(Call {
                    reverse: Some(keyword),
                    name,
                }))
            }
            Token::Ident(_) if *self.peek_at(1) == Token::Dot => {
                self.statement().map(ElementKind::Statement)
            }
            Token::Ident(_) => {
                let name = self.ident("a name")?;
                Ok(ElementKind::Call(Call {
                    reverse: None,
                    name,
                }))
            }
            _ => Err(self.unexpected("a statement, a block `{ ... }` or a sequence name")),
        }
    }

    fn statement(&mut self) -> Parse<Statement> {
        let label = self.ident("a module label")?;
        self.expect(&Token::Dot, "`.`")?;
        let part = self.ident("a part such as `Connector` or `Joint`")?;
        let mut index = None;
        if self.eat(&Token::LBracket).is_some() {
            index = Some(self.arg()?);
            self.expect(&Token::RBracket, "`]`")?;
        }
        self.expect(&Token::Dot, "`.` and an operation")?;
        let method = self.ident("an operation such as `extend`")?;
        let open = self.expect(&Token::LParen, "`(`")?;
        let mut args = Vec::new();
        if !self.at(&Token::RParen) {
            loop {
                args.push(self.arg()?);
                if self.eat(&Token::Comma).is_none() {
                    break;
                }
            }
        }
        let close = self.expect(&Token::RParen, "`,` or `)`")?;
        Ok(Statement {
            label,
            part,
            index,
            method,
            args,
            args_span: open.to(close),
        })
    }

    fn arg(&mut self) -> Parse<Arg> {
        let start = self.span();
        let kind = match self.peek().clone() {
            Token::Int(value) => {
                self.bump();
                ArgKind::Int(self.checked_int(value, start))
            }
            Token::Minus => {
                self.bump();
                let span = self.span();
                match self.peek().clone() {
                    Token::Int(value) => {
                        self.bump();
                        ArgKind::Int(-self.checked_int(value, span))
                    }
                    _ => return Err(self.unexpected("a number after `-`")),
                }
            }
            Token::True => {
                self.bump();
                ArgKind::Bool(true)
            }
            Token::False => {
                self.bump();
                ArgKind::Bool(false)
            }
            Token::Constant(name) => {
                self.bump();
                ArgKind::Constant(self.joined_constant(name, start))
            }
            _ => return Err(self.unexpected("a number, `true`, `false` or a `$CONSTANT`")),
        };
        Ok(Arg {
            kind,
            span: start.to(self.previous_span()),
        })
    }

    fn checked_int(&mut self, value: Option<i64>, span: Span) -> i64 {
        value.unwrap_or_else(|| {
            self.report(DiagnosticKind::IntegerTooLarge, span);
            0
        })
    }

    /// `$CONNECTOR 4` is read as `$CONNECTOR_4` after saying so, so checking can go on.
    fn joined_constant(&mut self, name: String, start: Span) -> String {
        let (Token::Int(Some(n)), true) =
            (self.peek().clone(), name.ends_with(char::is_alphabetic))
        else {
            return name;
        };
        let joined = format!("{name}_{n}");
        let span = start.to(self.bump().1);
        self.report(
            DiagnosticKind::SpaceInConstant {
                joined: joined.clone(),
            },
            span,
        );
        joined
    }

    // ---------- role predicates ----------

    /// A whole role predicate.
    fn expr(&mut self) -> Parse<Expr> {
        self.operators = 0;
        self.binary(1)
    }

    /// Precedence climbing over `||` (1), `&&` (2) and comparisons (3).
    fn binary(&mut self, min_precedence: u8) -> Parse<Expr> {
        let mut lhs = self.unary()?;
        while let Some((op, slip)) = self.binary_op() {
            if op.precedence() < min_precedence {
                break;
            }
            let (_, span) = self.bump();
            if let Some(kind) = slip {
                self.report(kind, span);
            }
            self.operators += 1;
            if self.operators > MAX_OPERATORS {
                self.report(
                    DiagnosticKind::PredicateTooLong {
                        limit: MAX_OPERATORS,
                    },
                    span,
                );
                return Err(Broken);
            }
            let rhs = self.binary(op.precedence() + 1)?;
            let span = lhs.span.to(rhs.span);
            lhs = Expr {
                kind: ExprKind::Binary {
                    op,
                    lhs: Box::new(lhs),
                    rhs: Box::new(rhs),
                },
                span,
            };
        }
        Ok(lhs)
    }

    /// The operator at the cursor; near-misses (`&`, `|`, `=`) come with the diagnostic to
    /// report if the operator is taken, and are read as meant.
    fn binary_op(&self) -> Option<(BinaryOp, Option<DiagnosticKind>)> {
        let (op, slip) = match self.peek() {
            Token::OrOr => (BinaryOp::Or, None),
            Token::AndAnd => (BinaryOp::And, None),
            Token::EqEq => (BinaryOp::Eq, None),
            Token::NotEq => (BinaryOp::NotEq, None),
            Token::Lt => (BinaryOp::Lt, None),
            Token::Le => (BinaryOp::Le, None),
            Token::Gt => (BinaryOp::Gt, None),
            Token::Ge => (BinaryOp::Ge, None),
            Token::Amp => (BinaryOp::And, Some(DiagnosticKind::SingleAmpersand)),
            Token::Pipe => (BinaryOp::Or, Some(DiagnosticKind::SinglePipe)),
            Token::Eq => (BinaryOp::Eq, Some(DiagnosticKind::AssignmentInPredicate)),
            _ => return None,
        };
        Some((op, slip))
    }

    fn unary(&mut self) -> Parse<Expr> {
        let op = match self.peek() {
            Token::Bang => UnaryOp::Not,
            Token::Minus => UnaryOp::Negate,
            _ => return self.primary(),
        };
        let start = self.bump().1;
        let operand = self.nested(Self::unary)?;
        let span = start.to(operand.span);
        Ok(Expr {
            kind: ExprKind::Unary {
                op,
                operand: Box::new(operand),
            },
            span,
        })
    }

    /// Runs `parse` one nesting level deeper, refusing beyond [`MAX_NESTING`].
    fn nested(&mut self, parse: fn(&mut Self) -> Parse<Expr>) -> Parse<Expr> {
        if self.depth >= MAX_NESTING {
            let span = self.span();
            self.report(DiagnosticKind::NestingTooDeep { limit: MAX_NESTING }, span);
            return Err(Broken);
        }
        self.depth += 1;
        let result = parse(self);
        self.depth -= 1;
        result
    }

    fn primary(&mut self) -> Parse<Expr> {
        let start = self.span();
        let kind = match self.peek().clone() {
            Token::Int(value) => {
                self.bump();
                ExprKind::Int(self.checked_int(value, start))
            }
            Token::True => {
                self.bump();
                ExprKind::Bool(true)
            }
            Token::False => {
                self.bump();
                ExprKind::Bool(false)
            }
            Token::Constant(name) => {
                self.bump();
                ExprKind::Constant(self.joined_constant(name, start))
            }
            Token::Ident(_) => self.query()?,
            Token::LParen => {
                self.bump();
                let inner = self.nested(|p| p.binary(1))?;
                self.expect(&Token::RParen, "`)`")?;
                ExprKind::Paren(Box::new(inner))
            }
            _ => return Err(self.unexpected("a condition, such as `id == 3`")),
        };
        Ok(Expr {
            kind,
            span: start.to(self.previous_span()),
        })
    }

    fn query(&mut self) -> Parse<ExprKind> {
        let name = self.ident("a query")?;
        if self.eat(&Token::LParen).is_none() {
            return Ok(ExprKind::Name(name));
        }
        let mut args = Vec::new();
        if !self.at(&Token::RParen) {
            loop {
                args.push(self.nested(|p| p.binary(1))?);
                if self.eat(&Token::Comma).is_none() {
                    break;
                }
            }
        }
        self.expect(&Token::RParen, "`,` or `)`")?;
        Ok(ExprKind::Call {
            function: name,
            args,
        })
    }
}
