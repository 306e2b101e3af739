//! Sizes that passes on different levels check against (docs/limits.md), each defined once
//! below every pass that uses it: the lexer and the parser share the syntax-error budget, and
//! the checker counts an expanded sequence against the lowering's statement limit.

/// Syntax errors recorded before the rest of a file is skipped (lexer and parser each).
pub const MAX_SYNTAX_ERRORS: usize = 1000;

/// Most statements a program can have: indices are 16 bits and 65,535 is reserved.
pub const MAX_STATEMENTS: usize = u16::MAX as usize - 1;
