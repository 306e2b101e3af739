//! Which module runs each label: `M<k>` is the module whose ID is k, a role is the one module
//! of the configuration whose state satisfies the role's predicate.

use dynarole_core::ast::{BinaryOp, Expr, ExprKind, UnaryOp};
use dynarole_core::check::Label;
use dynarole_core::diagnostic::{Diagnostic, DiagnosticKind};
use dynarole_core::expand::Plan;
use dynarole_core::{Program, RobotApi};
use dynarole_world::{Configuration, Port, View};
use std::collections::BTreeMap;

/// Module name for every label a plan uses.
pub type Assignment = BTreeMap<Label, String>;

/// Resolves every label used by `plans` on `config`; errors point at the first use.
pub fn assign_modules(
    program: &Program,
    plans: &[Plan],
    config: &Configuration,
) -> Result<Assignment, Vec<Diagnostic>> {
    assign_modules_on(program, plans, View::of(config))
}

/// Resolves every label used by `plans` on any robot's configuration (`RobotWorld::view`).
pub fn assign_modules_on(
    program: &Program,
    plans: &[Plan],
    view: View<'_>,
) -> Result<Assignment, Vec<Diagnostic>> {
    let mut assignment = Assignment::new();
    let mut errors = Vec::new();
    for statement in plans.iter().flat_map(Plan::statements) {
        if assignment.contains_key(&statement.label) {
            continue;
        }
        match resolve(program, &statement.label, view) {
            Ok(name) => {
                assignment.insert(statement.label.clone(), name);
            }
            Err(kind) => {
                if !errors.iter().any(|d: &Diagnostic| d.kind == kind) {
                    errors.push(Diagnostic::new(kind, statement.span));
                }
            }
        }
    }
    if errors.is_empty() {
        Ok(assignment)
    } else {
        Err(errors)
    }
}

fn resolve(program: &Program, label: &Label, view: View<'_>) -> Result<String, DiagnosticKind> {
    match label {
        Label::Module(id) => view
            .index_by_id(*id)
            .map(|i| view.name(i))
            .ok_or(DiagnosticKind::NoModuleWithId { id: *id }),
        Label::Role(role) => {
            let predicate = program
                .file
                .roles()
                .find(|r| &r.name.name == role)
                .map(|r| &r.predicate);
            let matching: Vec<String> = (0..view.len())
                .filter(|&i| {
                    predicate.is_some_and(|p| {
                        eval(p, &view, i, &program.robot) == Some(Value::Bool(true))
                    })
                })
                .map(|i| view.name(i))
                .collect();
            match matching.as_slice() {
                [one] => Ok(one.clone()),
                _ => Err(DiagnosticKind::RoleNotUnique {
                    role: role.clone(),
                    modules: matching,
                }),
            }
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Value {
    Int(i64),
    Bool(bool),
}

/// Evaluates a checked predicate for module `i`; `None` only for an ill-typed tree, which the
/// checker has already refused.
fn eval(expr: &Expr, view: &View<'_>, i: usize, robot: &RobotApi) -> Option<Value> {
    Some(match &expr.kind {
        ExprKind::Int(n) => Value::Int(*n),
        ExprKind::Bool(b) => Value::Bool(*b),
        ExprKind::Constant(name) => Value::Int(robot.constant(name)?.value),
        ExprKind::Paren(inner) => eval(inner, view, i, robot)?,
        ExprKind::Name(name) => query(&name.name, None, view, i)?,
        ExprKind::Call { function, args } => {
            let arg = match args.first() {
                Some(a) => match eval(a, view, i, robot)? {
                    Value::Int(n) => Some(n),
                    Value::Bool(_) => return None,
                },
                None => None,
            };
            query(&function.name, arg, view, i)?
        }
        ExprKind::Unary { op, operand } => match (op, eval(operand, view, i, robot)?) {
            (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
            (UnaryOp::Negate, Value::Int(n)) => Value::Int(n.checked_neg()?),
            _ => return None,
        },
        ExprKind::Binary { op, lhs, rhs } => {
            binary(*op, eval(lhs, view, i, robot)?, eval(rhs, view, i, robot)?)?
        }
    })
}

fn binary(op: BinaryOp, lhs: Value, rhs: Value) -> Option<Value> {
    let b = match (op, lhs, rhs) {
        (BinaryOp::And, Value::Bool(a), Value::Bool(b)) => a && b,
        (BinaryOp::Or, Value::Bool(a), Value::Bool(b)) => a || b,
        (BinaryOp::Eq, a, b) => a == b,
        (BinaryOp::NotEq, a, b) => a != b,
        (BinaryOp::Lt, Value::Int(a), Value::Int(b)) => a < b,
        (BinaryOp::Le, Value::Int(a), Value::Int(b)) => a <= b,
        (BinaryOp::Gt, Value::Int(a), Value::Int(b)) => a > b,
        (BinaryOp::Ge, Value::Int(a), Value::Int(b)) => a >= b,
        _ => return None,
    };
    Some(Value::Bool(b))
}

fn query(name: &str, arg: Option<i64>, view: &View<'_>, i: usize) -> Option<Value> {
    let port = |c: i64| {
        u8::try_from(c).ok().map(|connector| Port {
            module: i,
            connector,
        })
    };
    Some(match name {
        "id" => Value::Int(view.id(i).map_or(-1, i64::from)),
        "joint" => Value::Int(view.joint(i, u8::try_from(arg.unwrap_or(0)).ok()?)?),
        "neighbours" => {
            let latched = (0..view.connectors()).filter(|&c| {
                view.latched_to(Port {
                    module: i,
                    connector: c,
                })
                .is_some()
            });
            Value::Int(latched.count() as i64)
        }
        "connected" => Value::Bool(view.latched_to(port(arg?)?).is_some()),
        "neighbour_id" => {
            let other = view.latched_to(port(arg?)?);
            Value::Int(other.and_then(|p| view.id(p.module)).map_or(-1, i64::from))
        }
        _ => return None,
    })
}
