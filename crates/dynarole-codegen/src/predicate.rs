//! Role predicates as C expressions over the HAL's queries.

use dynarole_core::ast::{Expr, ExprKind, UnaryOp};
use dynarole_core::RobotApi;

/// The C text of a checked predicate; `m` is the module context in scope.
pub fn to_c(expr: &Expr, robot: &RobotApi) -> String {
    match &expr.kind {
        ExprKind::Int(n) => n.to_string(),
        ExprKind::Bool(b) => u8::from(*b).to_string(),
        ExprKind::Constant(name) => robot.constant(name).map_or(0, |c| c.value).to_string(),
        ExprKind::Paren(inner) => format!("({})", to_c(inner, robot)),
        ExprKind::Unary {
            op: UnaryOp::Not,
            operand,
        } => format!("!{}", to_c(operand, robot)),
        ExprKind::Unary {
            op: UnaryOp::Negate,
            operand,
        } => format!("-{}", to_c(operand, robot)),
        ExprKind::Binary { op, lhs, rhs } => format!(
            "({} {} {})",
            to_c(lhs, robot),
            op.symbol(),
            to_c(rhs, robot)
        ),
        ExprKind::Name(name) => query(&name.name, None, robot),
        ExprKind::Call { function, args } => {
            query(&function.name, args.first().map(|a| to_c(a, robot)), robot)
        }
    }
}

fn query(name: &str, arg: Option<String>, robot: &RobotApi) -> String {
    let arg = arg.unwrap_or_else(|| "0".into());
    match name {
        "id" => "(int32_t)dr_hal_id(m)".into(),
        "joint" => format!("(int32_t)dr_hal_joint(m, (uint8_t)({arg}))"),
        "connected" => format!("dr_hal_connected(m, (uint8_t)({arg}))"),
        "neighbour_id" => format!("(int32_t)dr_hal_neighbour_id(m, (uint8_t)({arg}))"),
        "neighbours" => {
            let count = robot
                .connector_part
                .and_then(|p| robot.parts.get(p))
                .and_then(|p| p.count)
                .unwrap_or(0);
            format!("(int32_t)dr_program_neighbours(m, {count}u)")
        }
        // The checker admits no other query.
        _ => "0".into(),
    }
}
