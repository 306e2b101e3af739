//! Reversal of sequences (paper, Sec. IV-C): statement order reversed, separators kept
//! between each pair, every operation inverted by the robot plugin, blocks reversed inside.

use crate::ast::*;
use crate::check::{non_invertible, resolve_statement, Program};
use crate::diagnostic::{Diagnostic, DiagnosticKind};
use crate::robot::{Template, Value};

impl Program<'_> {
    /// The reverse of sequence `name` as a declaration named `new_name`.
    ///
    /// Fails, pointing at each operation without an inverse, when the sequence (or one it
    /// uses) cannot be reversed; `None` in the error list means `name` is not a sequence.
    pub fn reverse_sequence(
        &self,
        name: &str,
        new_name: &str,
    ) -> Option<Result<SequenceDecl, Vec<Diagnostic>>> {
        let decl = self.file.sequence(name)?;
        let blockers = non_invertible(self.file, &self.robot, name);
        if !blockers.is_empty() {
            let errors = blockers
                .into_iter()
                .map(|(span, method)| {
                    let kind = DiagnosticKind::NotInvertible {
                        method,
                        sequence: name.to_string(),
                        reversed_at: decl.name.span,
                    };
                    Diagnostic::new(kind, span)
                })
                .collect();
            return Some(Err(errors));
        }
        let body = match &decl.definition {
            SequenceDef::Body(body) => self.reverse_body(body),
            // Reversing `X = reverse Y` gives Y back.
            SequenceDef::Reverse(target) => {
                match self.file.sequence(&target.name).map(|d| &d.definition) {
                    Some(SequenceDef::Body(body)) => body.clone(),
                    Some(SequenceDef::Reverse(_)) | None => Body {
                        elements: vec![call_element(&target.name, false, target.span)],
                        span: decl.span,
                        synchronous: None,
                    },
                }
            }
        };
        Some(Ok(SequenceDecl {
            name: Ident {
                name: new_name.to_string(),
                span: decl.name.span,
            },
            definition: SequenceDef::Body(body),
            span: decl.span,
        }))
    }

    /// The name a reversed sequence gets: `Y` if `name` is declared `= reverse Y`; the file's
    /// own `X = reverse name` if there is one; else `b2a` for `a2b` when that is a name (not
    /// for `grid20p`, whose swap `0p2grid` is not); else `name_reversed`.
    pub fn reverse_name(&self, name: &str) -> String {
        if let Some(SequenceDef::Reverse(target)) = self.file.sequence(name).map(|d| &d.definition)
        {
            return target.name.clone();
        }
        if let Some(alias) = self.reverse_alias(name) {
            return alias;
        }
        match name.split_once('2') {
            Some((from, to))
                if !from.is_empty()
                    && !to.contains('2')
                    && crate::lexer::is_identifier(&format!("{to}2{from}")) =>
            {
                format!("{to}2{from}")
            }
            _ => format!("{name}_reversed"),
        }
    }

    fn reverse_alias(&self, name: &str) -> Option<String> {
        self.file.sequences().find_map(|d| match &d.definition {
            SequenceDef::Reverse(target) if target.name == name => Some(d.name.name.clone()),
            _ => None,
        })
    }

    /// Reverses a body; every statement in it must be invertible.
    pub fn reverse_body(&self, body: &Body) -> Body {
        let n = body.elements.len();
        let elements = (0..n)
            .map(|j| {
                let element = &body.elements[n - 1 - j];
                // The separator between a pair stays between that pair; the last one stays last.
                let separator = if j + 1 < n {
                    body.elements[n - 2 - j].separator
                } else {
                    body.elements[n - 1].separator
                };
                Element {
                    kind: self.reverse_kind(&element.kind),
                    separator,
                    span: element.span,
                }
            })
            .collect();
        // The reverse of a synchronous group is synchronous: the same turns undone together.
        Body {
            elements,
            span: body.span,
            synchronous: body.synchronous,
        }
    }

    fn reverse_kind(&self, kind: &ElementKind) -> ElementKind {
        match kind {
            ElementKind::Statement(s) => ElementKind::Statement(self.reverse_statement(s)),
            ElementKind::Block(body) => ElementKind::Block(self.reverse_body(body)),
            ElementKind::Call(call) => self.reverse_call(call),
        }
    }

    /// `X` becomes `reverse X` (or a name the file gives it); `reverse X` becomes `X`.
    fn reverse_call(&self, call: &Call) -> ElementKind {
        let span = call.name.span;
        if call.reverse.is_some() {
            return call_element(&call.name.name, false, span).kind;
        }
        let declared_reverse =
            self.file
                .sequence(&call.name.name)
                .and_then(|d| match &d.definition {
                    SequenceDef::Reverse(target) => Some(target.name.clone()),
                    SequenceDef::Body(_) => None,
                });
        if let Some(target) = declared_reverse {
            return call_element(&target, false, span).kind;
        }
        match self.reverse_alias(&call.name.name) {
            Some(alias) => call_element(&alias, false, span).kind,
            None => call_element(&call.name.name, true, span).kind,
        }
    }

    /// The name of value `n` where the argument it comes from was written by a value's name
    /// (`slide(-dir)` of `slide($PLUS_X)` is `slide($MINUS_X)`), when one name alone has it.
    fn value_name(&self, template: &Template, statement: &Statement, n: i64) -> Option<String> {
        let source = match template {
            Template::Negate(inner) => match inner.as_ref() {
                Template::Param(k) => *k,
                _ => return None,
            },
            _ => return None,
        };
        let ArgKind::Constant(written) = &statement.args.get(source)?.kind else {
            return None;
        };
        self.robot.constant(written).filter(|c| c.part.is_none())?;
        let mut named = (self.robot.constants.iter()).filter(|c| c.part.is_none() && c.value == n);
        match (named.next(), named.next()) {
            (Some(one), None) => Some(one.name.clone()),
            _ => None,
        }
    }

    fn reverse_statement(&self, statement: &Statement) -> Statement {
        let Ok(resolved) = resolve_statement(self.file, statement, &self.robot) else {
            return statement.clone();
        };
        let part = &self.robot.parts[resolved.part];
        let Some(inverse) = &part.operations[resolved.operation].inverse else {
            return statement.clone();
        };
        let inverse_name = part.operations[inverse.operation].name.clone();
        let args = inverse
            .args
            .iter()
            .map(|template| match template {
                // Keep the argument as written (a `$CONSTANT` stays a constant).
                Template::Param(k) => statement.args[*k].clone(),
                other => {
                    let value = other.apply(&resolved.args).unwrap_or(Value::Int(0));
                    let kind = match value {
                        Value::Int(n) => match self.value_name(other, statement, n) {
                            Some(name) => ArgKind::Constant(name),
                            None => ArgKind::Int(n),
                        },
                        Value::Bool(b) => ArgKind::Bool(b),
                    };
                    Arg {
                        kind,
                        span: statement.args_span,
                    }
                }
            })
            .collect();
        Statement {
            method: Ident {
                name: inverse_name,
                span: statement.method.span,
            },
            args,
            ..statement.clone()
        }
    }
}

fn call_element(name: &str, reverse: bool, span: crate::span::Span) -> Element {
    Element {
        kind: ElementKind::Call(Call {
            reverse: reverse.then_some(span),
            name: Ident {
                name: name.to_string(),
                span,
            },
        }),
        separator: Separator {
            kind: SeparatorKind::Sequential,
            span,
        },
        span,
    }
}
