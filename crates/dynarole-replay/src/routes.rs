//! The token baseline's routes: the sequence replayed statement by statement on the start
//! configuration, and after each statement the shortest chain of latched neighbours from its
//! module to the next statement's module (the path the original hand-written token programs
//! took, e.g. M3 -> M5 -> M6 -> M4).

use crate::{assign_modules, RobotWorld};
use dynarole_core::diagnostic::{Diagnostic, DiagnosticKind};
use dynarole_core::expand::Plan;
use dynarole_core::lower::TokenRoutes;
use dynarole_core::span::Span;
use dynarole_core::Program;
use dynarole_world::{Configuration, Port, View};
use std::collections::VecDeque;

/// Where each statement of `plans` (run in turn) runs on `start`, and the route its token
/// takes. Fails (`token-route`) at the statement concerned when a module has no usable ID, the model refuses
/// a statement, or no chain of latched modules joins two consecutive statements' modules.
pub fn token_routes(
    program: &Program,
    plans: &[Plan],
    start: &Configuration,
) -> Result<TokenRoutes, Vec<Diagnostic>> {
    let assignment = assign_modules(program, plans, start)?;
    let limit = |message: String, span: Span| {
        vec![Diagnostic::new(
            DiagnosticKind::TokenRoute { message },
            span,
        )]
    };
    let mut world =
        RobotWorld::new(start.clone(), &program.robot).map_err(|e| limit(e, Span::default()))?;
    let mut routes = TokenRoutes {
        holders: Vec::new(),
        routes: Vec::new(),
    };
    let mut previous: Option<usize> = None;
    for statement in plans.iter().flat_map(Plan::statements) {
        let name = assignment
            .get(&statement.label)
            .cloned()
            .unwrap_or_default();
        let view = world.view();
        let Some(module) = view.index(&name) else {
            return Err(limit(
                format!("module {name} is not in the configuration"),
                statement.span,
            ));
        };
        let id = token_id(view, module).ok_or_else(|| {
            limit(
                format!("the token protocol addresses modules by ID, and module {name} has none below 65535"),
                statement.span,
            )
        })?;
        let route = match previous {
            Some(from) if from != module => route(view, from, module).ok_or_else(|| {
                limit(
                    format!(
                        "no chain of latched modules joins {} to {name} after the previous statement: the token cannot be handed over",
                        view.name(from)
                    ),
                    statement.span,
                )
            })?,
            _ => Vec::new(),
        };
        routes.holders.push(id);
        routes.routes.push(route);
        world
            .apply(&program.robot, statement, &name)
            .map_err(|reason| {
                limit(
                    format!("the token routes are computed by replaying the sequence, and the model refuses this statement: {reason}"),
                    statement.span,
                )
            })?;
        previous = Some(module);
    }
    Ok(routes)
}

fn token_id(view: View, module: usize) -> Option<u16> {
    view.id(module)
        .and_then(|id| u16::try_from(id).ok())
        .filter(|id| *id != u16::MAX)
}

/// Breadth-first search over latched connectors (lowest module index and connector first, so
/// the route is deterministic): the hops (module ID, connector) from `from` up to the module
/// before `to`.
fn route(view: View, from: usize, to: usize) -> Option<Vec<(u16, u8)>> {
    let n = view.len();
    let mut came_from: Vec<Option<(usize, u8)>> = vec![None; n];
    let mut seen = vec![false; n];
    let mut queue = VecDeque::from([from]);
    *seen.get_mut(from)? = true;
    while let Some(m) = queue.pop_front() {
        if m == to {
            break;
        }
        for connector in 0..view.connectors() {
            let port = Port {
                module: m,
                connector,
            };
            let Some(other) = view.latched_to(port) else {
                continue;
            };
            if !seen[other.module] {
                seen[other.module] = true;
                came_from[other.module] = Some((m, connector));
                queue.push_back(other.module);
            }
        }
    }
    let mut hops = Vec::new();
    let mut at = to;
    while at != from {
        let (previous, connector) = came_from.get(at).copied().flatten()?;
        hops.push((token_id(view, previous)?, connector));
        at = previous;
    }
    hops.reverse();
    Some(hops)
}
