//! Turns source text into tokens (and comments, kept aside for the formatter).

use crate::diagnostic::{Diagnostic, DiagnosticKind};
use crate::span::Span;
use logos::Logos;

/// The tokens of the dynarole language.
#[derive(Logos, Clone, Debug, PartialEq, Eq)]
#[logos(skip r"[ \t\r\n\f]+")]
pub enum Token {
    #[token("robot")]
    Robot,
    #[token("role")]
    Role,
    #[token("requires")]
    Requires,
    #[token("sequence")]
    Sequence,
    #[token("reverse")]
    Reverse,
    #[token("true")]
    True,
    #[token("false")]
    False,
    #[regex(r"[A-Za-z_][A-Za-z0-9_]*", |lex| lex.slice().to_string())]
    Ident(String),
    /// A robot constant such as `$CONNECTOR_0`; the text excludes the `$`.
    #[regex(r"\$[A-Za-z_][A-Za-z0-9_]*", |lex| lex.slice()[1..].to_string())]
    Constant(String),
    /// A lone `$` (or `$` followed by something that cannot start a name).
    #[token("$")]
    Dollar,
    /// A decimal integer; `None` when it does not fit in an `i64`.
    #[regex(r"[0-9]+", |lex| lex.slice().parse::<i64>().ok())]
    Int(Option<i64>),
    #[token(";")]
    Semi,
    #[token("&")]
    Amp,
    #[token("&&")]
    AndAnd,
    #[token("|")]
    Pipe,
    #[token("||")]
    OrOr,
    #[token("!")]
    Bang,
    #[token("==")]
    EqEq,
    #[token("!=")]
    NotEq,
    #[token("=")]
    Eq,
    #[token("<")]
    Lt,
    #[token("<=")]
    Le,
    #[token(">")]
    Gt,
    #[token(">=")]
    Ge,
    #[token("-")]
    Minus,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token("[")]
    LBracket,
    #[token("]")]
    RBracket,
    #[token("{")]
    LBrace,
    #[token("}")]
    RBrace,
    #[token(",")]
    Comma,
    #[token(".")]
    Dot,
    #[regex(r"//[^\n]*")]
    LineComment,
    #[token("/*", block_comment)]
    BlockComment,
    /// End of input (never produced by logos; appended by [`lex`]).
    Eof,
}

/// Consumes the rest of a `/* */` comment; fails when it is never closed.
fn block_comment(lex: &mut logos::Lexer<Token>) -> bool {
    match lex.remainder().find("*/") {
        Some(end) => {
            lex.bump(end + 2);
            true
        }
        None => {
            lex.bump(lex.remainder().len());
            false
        }
    }
}

/// A comment as written, kept so that `fmt` can put it back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Comment {
    pub text: String,
    pub span: Span,
}

/// The result of lexing: tokens ending with [`Token::Eof`], comments, and bad characters.
#[derive(Debug, Default)]
pub struct Lexed {
    pub tokens: Vec<(Token, Span)>,
    pub comments: Vec<Comment>,
    /// Text that is not a token of the language.
    pub errors: Vec<Diagnostic>,
}

/// Most tokens a file may have: 60,000 statements of 15 tokens with room to spare, and about
/// 60 MB of tokens at most.
pub const MAX_TOKENS: usize = 1_500_000;

pub fn lex(source: &str) -> Lexed {
    let mut out = Lexed::default();
    let mut lexer = Token::lexer(source);
    while let Some(result) = lexer.next() {
        let span = Span::new(lexer.span().start, lexer.span().end);
        if let Some(what) = too_much(&out) {
            out.errors.push(Diagnostic::new(
                DiagnosticKind::InputTooLarge { what },
                span,
            ));
            break;
        }
        match result {
            Ok(Token::LineComment) | Ok(Token::BlockComment) => out.comments.push(Comment {
                text: lexer.slice().trim_end().to_string(),
                span,
            }),
            Ok(token) => out.tokens.push((token, span)),
            Err(()) if lexer.slice().starts_with("/*") => {
                out.errors
                    .push(Diagnostic::new(DiagnosticKind::UnterminatedComment, span));
            }
            Err(()) => unknown_character(&mut out.errors, lexer.slice(), span),
        }
    }
    let end = Span::new(source.len(), source.len());
    out.tokens.push((Token::Eof, end));
    out
}

/// Why lexing must stop here, if it must: too many tokens or too many bad characters.
fn too_much(lexed: &Lexed) -> Option<String> {
    if lexed.tokens.len() >= MAX_TOKENS {
        return Some(format!("more than {MAX_TOKENS} tokens"));
    }
    let limit = crate::limits::MAX_SYNTAX_ERRORS;
    (lexed.errors.len() >= limit).then(|| format!("more than {limit} syntax errors"))
}

/// Whether `text` is a name of the language (a sequence, role or label): exactly one
/// identifier token, not a keyword. Decided by the lexer itself so that the rule is one.
pub fn is_identifier(text: &str) -> bool {
    let mut lexer = Token::lexer(text);
    matches!(lexer.next(), Some(Ok(Token::Ident(_))))
        && lexer.span() == (0..text.len())
        && lexer.next().is_none()
}

/// Reports bad text at `span`; a run of bad characters, one after the other, is one error,
/// so that the report stays short whatever the input.
fn unknown_character(errors: &mut Vec<Diagnostic>, text: &str, span: Span) {
    let count = text.chars().count();
    if let Some(Diagnostic {
        kind: DiagnosticKind::UnknownCharacter { count: before, .. },
        span: run,
    }) = errors.last_mut()
    {
        if run.end == span.start {
            *before += count;
            *run = run.to(span);
            return;
        }
    }
    let found = text.chars().next().unwrap_or(' ');
    errors.push(Diagnostic::new(
        DiagnosticKind::UnknownCharacter { found, count },
        span,
    ));
}

impl Token {
    /// How the token is named in "expected X, found Y" messages.
    pub fn describe(&self) -> String {
        match self {
            Token::Robot => "keyword `robot`".into(),
            Token::Role => "keyword `role`".into(),
            Token::Requires => "keyword `requires`".into(),
            Token::Sequence => "keyword `sequence`".into(),
            Token::Reverse => "keyword `reverse`".into(),
            Token::True => "`true`".into(),
            Token::False => "`false`".into(),
            Token::Ident(name) => format!("name `{name}`"),
            Token::Constant(name) => format!("constant `${name}`"),
            Token::Dollar => "`$`".into(),
            Token::Int(_) => "a number".into(),
            Token::Semi => "`;`".into(),
            Token::Amp => "`&`".into(),
            Token::AndAnd => "`&&`".into(),
            Token::Pipe => "`|`".into(),
            Token::OrOr => "`||`".into(),
            Token::Bang => "`!`".into(),
            Token::EqEq => "`==`".into(),
            Token::NotEq => "`!=`".into(),
            Token::Eq => "`=`".into(),
            Token::Lt => "`<`".into(),
            Token::Le => "`<=`".into(),
            Token::Gt => "`>`".into(),
            Token::Ge => "`>=`".into(),
            Token::Minus => "`-`".into(),
            Token::LParen => "`(`".into(),
            Token::RParen => "`)`".into(),
            Token::LBracket => "`[`".into(),
            Token::RBracket => "`]`".into(),
            Token::LBrace => "`{`".into(),
            Token::RBrace => "`}`".into(),
            Token::Comma => "`,`".into(),
            Token::Dot => "`.`".into(),
            Token::LineComment | Token::BlockComment => "a comment".into(),
            Token::Eof => "the end of the file".into(),
        }
    }
}
