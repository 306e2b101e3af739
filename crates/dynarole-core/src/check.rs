//! Name and type checking of a parsed file against its robot's API plugin.
//!
//! [`analyze`] walks every item and reports every problem it finds; when there are no errors it
//! also returns a [`Program`], the checked file that later passes (reverse, expand) work on.

use crate::ast::*;
use crate::diagnostic::{has_errors, Diagnostic, DiagnosticKind as K, SyncProblem};
use crate::limits::MAX_STATEMENTS;
use crate::robot::{OperationKind, ParamType, Part, RobotApi, RobotRegistry, Value};
use crate::span::Span;
use crate::suggest::{closest, module_label_lookalike};
use std::collections::BTreeMap;

/// A file that passed checking, with its robot's API.
#[derive(Clone, Debug)]
pub struct Program<'f> {
    pub file: &'f SourceFile,
    pub robot: RobotApi,
}

/// Who executes a statement.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Label {
    /// The module(s) whose state satisfies the role's predicate.
    Role(String),
    /// `M<k>`: the module whose ID is k.
    Module(u32),
}

/// A statement with its names resolved against the robot API.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResolvedStatement {
    pub label: Label,
    pub part: usize,
    pub index: Option<i64>,
    pub operation: usize,
    pub args: Vec<Value>,
    /// The statement in the source.
    pub span: Span,
}

impl ResolvedStatement {
    /// `M3.Joint.rotateFromToBy(0, 324, false, 150)`, as executed (after any reversal).
    pub fn describe(&self, robot: &RobotApi) -> String {
        let label = match &self.label {
            Label::Module(id) => format!("M{id}"),
            Label::Role(role) => role.clone(),
        };
        let Some(part) = robot.parts.get(self.part) else {
            return label;
        };
        let index = self.index.map_or(String::new(), |i| format!("[{i}]"));
        let op = part
            .operations
            .get(self.operation)
            .map_or("?", |o| o.name.as_str());
        let args: Vec<String> = self.args.iter().map(ToString::to_string).collect();
        format!("{label}.{}{index}.{op}({})", part.name, args.join(", "))
    }
}

/// Checks `file`; the program is returned only when no error was found.
pub fn analyze<'f>(
    file: &'f SourceFile,
    registry: &RobotRegistry,
) -> (Option<Program<'f>>, Vec<Diagnostic>) {
    let mut checker = Checker {
        file,
        diagnostics: Vec::new(),
        searches_left: crate::diagnostic::MAX_SHOWN,
    };
    let robot = checker.robot(registry);
    checker.duplicates();
    checker.roles(robot);
    for decl in file.sequences() {
        checker.sequence(decl, robot);
    }
    let acyclic = checker.cycles();
    if acyclic {
        if let Some(robot) = robot {
            checker.reversals(robot);
        }
    }
    let mut diagnostics = checker.diagnostics;
    diagnostics.sort_by_key(|d| d.span);
    let program = match robot {
        Some(robot) if !has_errors(&diagnostics) => Some(Program {
            file,
            robot: robot.clone(),
        }),
        _ => None,
    };
    (program, diagnostics)
}

struct Checker<'f> {
    file: &'f SourceFile,
    diagnostics: Vec<Diagnostic>,
    /// Searches of the file's own names for a "did you mean" still allowed: each costs a
    /// comparison with every role or sequence, and a report shows only the first errors.
    searches_left: usize,
}

impl Checker<'_> {
    /// The closest of `candidates` to `name`, while the search budget lasts.
    fn closest_declared<'a>(
        &mut self,
        name: &str,
        candidates: impl IntoIterator<Item = &'a str>,
    ) -> Option<String> {
        self.searches_left = self.searches_left.checked_sub(1)?;
        closest(name, candidates)
    }
}

/// The role queries a predicate may use, and their number of arguments.
const QUERIES: [(&str, &str); 5] = [
    ("id", "the module's own ID"),
    ("neighbours", "number of connected neighbours"),
    (
        "joint",
        "joint angle (`joint(j)` for robots with several joints)",
    ),
    (
        "connected",
        "`connected(c)`: whether connector c is connected",
    ),
    (
        "neighbour_id",
        "`neighbour_id(c)`: ID of the module on connector c, -1 if none",
    ),
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Type {
    Int,
    Bool,
    /// Already reported; suppresses follow-on errors.
    Unknown,
}

impl Type {
    fn describe(self) -> &'static str {
        match self {
            Type::Int => "a number",
            Type::Bool => "a boolean",
            Type::Unknown => "unknown",
        }
    }
}

impl<'f> Checker<'f> {
    fn report(&mut self, kind: K, span: Span) {
        self.diagnostics.push(Diagnostic::new(kind, span));
    }

    fn robot<'r>(&mut self, registry: &'r RobotRegistry) -> Option<&'r RobotApi> {
        let decls: Vec<&RobotDecl> = self
            .file
            .items
            .iter()
            .filter_map(|i| match i {
                Item::Robot(d) => Some(d),
                _ => None,
            })
            .collect();
        let Some(first) = decls.first() else {
            let known = registry.names();
            self.report(K::MissingRobot { known }, Span::new(0, 0));
            return None;
        };
        for extra in &decls[1..] {
            self.report(K::DuplicateRobot { first: first.span }, extra.span);
        }
        let found = registry.get(&first.name.name);
        if found.is_none() {
            let kind = K::UnknownRobot {
                name: first.name.name.clone(),
                known: registry.names(),
            };
            self.report(kind, first.name.span);
        }
        found
    }

    fn duplicates(&mut self) {
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        let mut reports = Vec::new();
        for item in &self.file.items {
            let (what, name) = match item {
                Item::Role(d) => ("role", &d.name),
                Item::Sequence(d) => ("sequence", &d.name),
                Item::Robot(_) => continue,
            };
            match seen.get(name.name.as_str()) {
                Some(first) => {
                    let kind = K::DuplicateDefinition {
                        name: name.name.clone(),
                        what,
                        first: *first,
                    };
                    reports.push((kind, name.span));
                }
                None => {
                    seen.insert(&name.name, name.span);
                }
            }
        }
        for (kind, span) in reports {
            self.report(kind, span);
        }
    }

    // ---------- roles ----------

    fn roles(&mut self, robot: Option<&RobotApi>) {
        for role in self.file.roles() {
            if parse_module_label(&role.name.name).is_some() {
                self.report(
                    K::RoleShadowsModuleLabel {
                        name: role.name.name.clone(),
                    },
                    role.name.span,
                );
            }
            let Some(robot) = robot else { continue };
            let ty = self.expr(&role.predicate, robot);
            if ty == Type::Int {
                let kind = K::PredicateNotBoolean {
                    role: role.name.name.clone(),
                    found: ty.describe().into(),
                };
                self.report(kind, role.predicate.span);
            }
        }
    }

    fn expr(&mut self, expr: &Expr, robot: &RobotApi) -> Type {
        match &expr.kind {
            ExprKind::Int(n) => {
                if i32::try_from(*n).is_err() {
                    let kind = K::NumberOutOfRange {
                        value: *n,
                        allowed: format!("{} to {}", i32::MIN, i32::MAX),
                        reason: "role predicates are computed in 32 bits on the modules".into(),
                    };
                    self.report(kind, expr.span);
                }
                Type::Int
            }
            ExprKind::Bool(_) => Type::Bool,
            ExprKind::Constant(name) => match robot.constant(name) {
                Some(_) => Type::Int,
                None => {
                    self.unknown_constant(name, expr.span, robot);
                    Type::Unknown
                }
            },
            ExprKind::Paren(inner) => self.expr(inner, robot),
            ExprKind::Name(name) => self.query(name, &[], expr.span, robot),
            ExprKind::Call { function, args } => self.query(function, args, expr.span, robot),
            ExprKind::Unary { op, operand } => {
                let (want, symbol) = match op {
                    UnaryOp::Not => (Type::Bool, "`!`"),
                    UnaryOp::Negate => (Type::Int, "`-`"),
                };
                self.expect_type(operand, robot, want, symbol);
                want
            }
            ExprKind::Binary { op, lhs, rhs } => self.binary(*op, lhs, rhs, robot),
        }
    }

    fn binary(&mut self, op: BinaryOp, lhs: &Expr, rhs: &Expr, robot: &RobotApi) -> Type {
        let context = format!("`{}`", op.symbol());
        match op {
            BinaryOp::And | BinaryOp::Or => {
                self.expect_type(lhs, robot, Type::Bool, &context);
                self.expect_type(rhs, robot, Type::Bool, &context);
            }
            BinaryOp::Eq | BinaryOp::NotEq => {
                let left = self.expr(lhs, robot);
                if left != Type::Unknown {
                    self.expect_type(rhs, robot, left, &context);
                } else {
                    self.expr(rhs, robot);
                }
            }
            _ => {
                self.expect_type(lhs, robot, Type::Int, &context);
                self.expect_type(rhs, robot, Type::Int, &context);
            }
        }
        if op == BinaryOp::Eq {
            self.id_comparison(lhs, rhs);
            self.id_comparison(rhs, lhs);
        }
        Type::Bool
    }

    /// A module ID equal to a number no module can have is a mistake: IDs are 16 bits on the
    /// modules (65,535 means "none", and `neighbour_id` answers -1 for no neighbour).
    fn id_comparison(&mut self, query: &Expr, number: &Expr) {
        let lowest = match &query.kind {
            ExprKind::Name(name) if name.name == "id" => 0,
            ExprKind::Call { function, .. } if function.name == "neighbour_id" => -1,
            _ => return,
        };
        let Some(value) = literal(number) else { return };
        let max = i64::from(u16::MAX) - 1;
        // A number beyond 32 bits is reported on its own.
        if (lowest..=max).contains(&value) || i32::try_from(value).is_err() {
            return;
        }
        let kind = K::NumberOutOfRange {
            value,
            allowed: format!("{lowest} to {max}"),
            reason: "module IDs are 16 bits on the modules (65535 means none)".into(),
        };
        self.report(kind, number.span);
    }

    fn expect_type(&mut self, expr: &Expr, robot: &RobotApi, want: Type, context: &str) {
        let found = self.expr(expr, robot);
        if found != want && found != Type::Unknown {
            let kind = K::TypeMismatch {
                context: context.to_string(),
                expected: want.describe().into(),
                found: found.describe().into(),
            };
            self.report(kind, expr.span);
        }
    }

    fn query(&mut self, name: &Ident, args: &[Expr], span: Span, robot: &RobotApi) -> Type {
        let (index_part, result) = match name.name.as_str() {
            "id" | "neighbours" => (None, Type::Int),
            "connected" => (robot.connector_part, Type::Bool),
            "neighbour_id" => (robot.connector_part, Type::Int),
            "joint" => return self.joint_query(args, span, robot),
            _ => {
                let known: Vec<String> = QUERIES.iter().map(|(q, _)| q.to_string()).collect();
                let suggestion = closest(&name.name, QUERIES.iter().map(|(q, _)| *q));
                self.report(
                    K::UnknownQuery {
                        name: name.name.clone(),
                        known,
                        suggestion,
                    },
                    name.span,
                );
                return Type::Unknown;
            }
        };
        let expected = usize::from(matches!(name.name.as_str(), "connected" | "neighbour_id"));
        if args.len() != expected {
            self.report(
                K::QueryArity {
                    name: name.name.clone(),
                    expected,
                    found: args.len(),
                },
                span,
            );
            return result;
        }
        if let (Some(arg), Some(part)) = (args.first(), index_part) {
            self.query_index(arg, &robot.parts[part], part, robot);
        }
        result
    }

    fn joint_query(&mut self, args: &[Expr], span: Span, robot: &RobotApi) -> Type {
        let Some(part) = robot.joint_part else {
            let kind = K::UnknownQuery {
                name: "joint".into(),
                known: vec![],
                suggestion: None,
            };
            self.report(kind, span);
            return Type::Unknown;
        };
        let expected = usize::from(robot.parts[part].count.is_some());
        if args.len() != expected {
            self.report(
                K::QueryArity {
                    name: "joint".into(),
                    expected,
                    found: args.len(),
                },
                span,
            );
        } else if let Some(arg) = args.first() {
            self.query_index(arg, &robot.parts[part], part, robot);
        }
        Type::Int
    }

    /// A query argument that names an instance of `part`: a number in range or its constant.
    fn query_index(&mut self, arg: &Expr, part: &Part, part_idx: usize, robot: &RobotApi) {
        let arg_value = match &arg.kind {
            ExprKind::Int(n) => Some(ArgKind::Int(*n)),
            ExprKind::Constant(c) => Some(ArgKind::Constant(c.clone())),
            _ => None,
        };
        match arg_value {
            Some(kind) => {
                let as_arg = Arg {
                    kind,
                    span: arg.span,
                };
                self.index(&as_arg, part, part_idx, robot);
            }
            None => self.expect_type(arg, robot, Type::Int, &format!("the {} index", part.name)),
        }
    }

    // ---------- sequences ----------

    fn sequence(&mut self, decl: &SequenceDecl, robot: Option<&RobotApi>) {
        match &decl.definition {
            SequenceDef::Reverse(target) => self.sequence_name(target),
            SequenceDef::Body(body) => self.body(body, robot),
        }
    }

    fn sequence_name(&mut self, name: &Ident) {
        if self.file.sequence(&name.name).is_none() {
            let file = self.file;
            let suggestion =
                self.closest_declared(&name.name, file.sequences().map(|s| s.name.name.as_str()));
            self.report(
                K::UnknownSequence {
                    name: name.name.clone(),
                    suggestion,
                },
                name.span,
            );
        }
    }

    fn body(&mut self, body: &Body, robot: Option<&RobotApi>) {
        if let Some(keyword) = body.synchronous {
            self.synchronous(body, keyword, robot);
        }
        for element in &body.elements {
            match &element.kind {
                ElementKind::Statement(statement) => {
                    self.label(&statement.label);
                    if let Some(robot) = robot {
                        self.statement(statement, robot);
                    }
                }
                ElementKind::Block(inner) => self.body(inner, robot),
                ElementKind::Call(call) => self.sequence_name(&call.name),
            }
        }
    }

    /// A synchronous group is one parallel group of turns: what the runtime can start at one
    /// instant and move in lock-step (a connector has no speed to share, and a block or a
    /// sequence inside would have an order of its own).
    fn synchronous(&mut self, body: &Body, keyword: Span, robot: Option<&RobotApi>) {
        let Some((last, before)) = body.elements.split_last() else {
            self.report(
                K::SynchronousGroupShape {
                    problem: SyncProblem::Empty,
                },
                keyword.to(body.span),
            );
            return;
        };
        for element in before {
            if element.separator.kind == SeparatorKind::Sequential {
                let problem = SyncProblem::SequentialInside;
                self.report(K::SynchronousGroupShape { problem }, element.separator.span);
            }
        }
        for element in before.iter().chain([last]) {
            let ElementKind::Statement(statement) = &element.kind else {
                let problem = SyncProblem::NotAStatement;
                self.report(K::SynchronousGroupShape { problem }, element.span);
                continue;
            };
            let Some(robot) = robot else { continue };
            let Ok(resolved) = resolve_statement(self.file, statement, robot) else {
                continue;
            };
            // A turn from a stated angle: the plugin loader makes its first parameters
            // `from`, `to` and the direction, so every module can know the group's pace.
            if robot.kind(resolved.part, resolved.operation) != OperationKind::Turn {
                let step = resolved.describe(robot);
                self.report(K::SynchronousNotATurn { step }, element.span);
            }
        }
    }

    fn label(&mut self, label: &Ident) {
        if self.file.has_role(&label.name) || parse_module_label(&label.name).is_some() {
            return;
        }
        let file = self.file;
        let suggestion = module_label_lookalike(&label.name).or_else(|| {
            self.closest_declared(&label.name, file.roles().map(|r| r.name.name.as_str()))
        });
        self.report(
            K::UnknownLabel {
                name: label.name.clone(),
                suggestion,
            },
            label.span,
        );
    }

    fn statement(&mut self, statement: &Statement, robot: &RobotApi) {
        let diagnostics = resolve_statement(self.file, statement, robot)
            .err()
            .unwrap_or_default();
        self.diagnostics.extend(diagnostics);
    }

    fn index(&mut self, arg: &Arg, part: &Part, part_idx: usize, robot: &RobotApi) {
        if let Err(d) = resolve_index(arg, part, part_idx, robot) {
            self.diagnostics.push(d);
        }
    }

    fn unknown_constant(&mut self, name: &str, span: Span, robot: &RobotApi) {
        self.diagnostics.push(unknown_constant(name, span, robot));
    }

    // ---------- composition ----------

    /// Reports each cycle of sequences using each other; true when there is none.
    fn cycles(&mut self) -> bool {
        let graph = uses_graph(self.file);
        let mut state: BTreeMap<&str, Visit> = BTreeMap::new();
        let mut found = Vec::new();
        for decl in self.file.sequences() {
            find_cycles(&graph, &decl.name.name, &mut state, &mut found);
        }
        let acyclic = found.is_empty();
        if acyclic {
            self.expansion_limits(&graph);
        }
        for (path, uses) in found {
            let Some((&last, rest)) = uses.split_last() else {
                continue;
            };
            self.report(
                K::CompositionCycle {
                    path,
                    uses: rest.to_vec(),
                },
                last,
            );
        }
        acyclic
    }

    /// Reports each sequence whose expansion would pass a limit while the sequences it uses
    /// do not (where the limit is crossed), before anything is expanded.
    fn expansion_limits(&mut self, graph: &UsesGraph<'_>) {
        let sizes = expanded_sizes(self.file, graph);
        let within = |name: &str| {
            sizes.get(name).is_none_or(|&(count, depth)| {
                count <= MAX_STATEMENTS && depth <= MAX_COMPOSITION_DEPTH
            })
        };
        let mut total = 0usize;
        let mut total_reported = false;
        for decl in self.file.sequences() {
            let name = decl.name.name.as_str();
            let Some(&(count, depth)) = sizes.get(name) else {
                continue;
            };
            total = total.saturating_add(count);
            if total > MAX_EXPANDED_PER_FILE && !total_reported {
                total_reported = true;
                let kind = K::FileTooLong {
                    statements: total,
                    limit: MAX_EXPANDED_PER_FILE,
                };
                self.report(kind, decl.name.span);
            }
            let uses = graph.get(name).map(Vec::as_slice).unwrap_or(&[]);
            if within(name) || !uses.iter().all(|(callee, _)| within(callee)) {
                continue;
            }
            let kind = if depth > MAX_COMPOSITION_DEPTH {
                K::CompositionTooDeep {
                    name: name.to_string(),
                    limit: MAX_COMPOSITION_DEPTH,
                }
            } else {
                K::SequenceTooLong {
                    name: name.to_string(),
                    statements: count,
                    limit: MAX_STATEMENTS,
                }
            };
            self.report(kind, decl.name.span);
        }
    }

    // ---------- reversal ----------

    /// Every `reverse X` needs every operation reachable from X to have an inverse.
    fn reversals(&mut self, robot: &RobotApi) {
        let mut reports = Vec::new();
        for decl in self.file.sequences() {
            match &decl.definition {
                SequenceDef::Reverse(target) => reports.push((target.name.as_str(), decl.span)),
                SequenceDef::Body(body) => collect_reverse_calls(body, &mut reports),
            }
        }
        for (target, site) in reports {
            for (statement, method) in non_invertible(self.file, robot, target) {
                let kind = K::NotInvertible {
                    method,
                    sequence: target.to_string(),
                    reversed_at: site,
                };
                self.report(kind, statement);
            }
        }
    }
}

fn collect_reverse_calls<'a>(body: &'a Body, out: &mut Vec<(&'a str, Span)>) {
    for element in &body.elements {
        match &element.kind {
            ElementKind::Call(Call {
                reverse: Some(keyword),
                name,
            }) => {
                out.push((name.name.as_str(), keyword.to(name.span)));
            }
            ElementKind::Block(inner) => collect_reverse_calls(inner, out),
            _ => {}
        }
    }
}

/// The statements (method spans and names) reachable from sequence `name` that have no inverse.
/// Call only on a file without composition cycles.
pub fn non_invertible(file: &SourceFile, robot: &RobotApi, name: &str) -> Vec<(Span, String)> {
    let mut out = Vec::new();
    let mut visited = Vec::new();
    non_invertible_in(file, robot, name, &mut visited, &mut out);
    out
}

fn non_invertible_in<'f>(
    file: &'f SourceFile,
    robot: &RobotApi,
    name: &'f str,
    visited: &mut Vec<&'f str>,
    out: &mut Vec<(Span, String)>,
) {
    if visited.contains(&name) {
        return;
    }
    visited.push(name);
    let Some(decl) = file.sequence(name) else {
        return;
    };
    match &decl.definition {
        SequenceDef::Reverse(target) => non_invertible_in(file, robot, &target.name, visited, out),
        SequenceDef::Body(body) => {
            let mut stack = vec![body];
            while let Some(body) = stack.pop() {
                for element in &body.elements {
                    match &element.kind {
                        ElementKind::Statement(s) => {
                            if let Ok(r) = resolve_statement(file, s, robot) {
                                if robot.parts[r.part].operations[r.operation]
                                    .inverse
                                    .is_none()
                                {
                                    out.push((s.method.span, s.method.name.clone()));
                                }
                            }
                        }
                        ElementKind::Block(inner) => stack.push(inner),
                        ElementKind::Call(call) => {
                            non_invertible_in(file, robot, &call.name.name, visited, out)
                        }
                    }
                }
            }
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Visit {
    Active,
    Done,
}

type UsesGraph<'f> = BTreeMap<&'f str, Vec<(&'f str, Span)>>;

/// For each sequence, the sequences it uses (calls and reverse targets), with where.
fn uses_graph(file: &SourceFile) -> UsesGraph<'_> {
    let mut graph = BTreeMap::new();
    for decl in file.sequences() {
        let mut uses = Vec::new();
        match &decl.definition {
            SequenceDef::Reverse(target) => uses.push((target.name.as_str(), target.span)),
            SequenceDef::Body(body) => collect_calls(body, &mut uses),
        }
        graph.entry(decl.name.name.as_str()).or_insert(uses);
    }
    graph
}

fn collect_calls<'a>(body: &'a Body, out: &mut Vec<(&'a str, Span)>) {
    for element in &body.elements {
        match &element.kind {
            ElementKind::Call(call) => out.push((call.name.name.as_str(), call.name.span)),
            ElementKind::Block(inner) => collect_calls(inner, out),
            ElementKind::Statement(_) => {}
        }
    }
}

/// Depth-first search; each back edge is one cycle, reported as names and use spans. The
/// search keeps its own stack, so a chain of any length of sequences using each other cannot
/// exhaust the thread's.
fn find_cycles<'f>(
    graph: &UsesGraph<'f>,
    root: &'f str,
    state: &mut BTreeMap<&'f str, Visit>,
    found: &mut Vec<(Vec<String>, Vec<Span>)>,
) {
    if state.contains_key(root) {
        return;
    }
    state.insert(root, Visit::Active);
    // The sequences being visited, each with its next use to follow.
    let mut frames: Vec<(&'f str, usize)> = vec![(root, 0)];
    // For each visited sequence but the deepest: it and the use that led further down.
    let mut stack: Vec<(&'f str, Span)> = Vec::new();
    while let Some((node, next_use)) = frames.last_mut() {
        let node = *node;
        let uses = graph.get(node).map(Vec::as_slice).unwrap_or(&[]);
        let Some(&(next, span)) = uses.get(*next_use) else {
            state.insert(node, Visit::Done);
            frames.pop();
            stack.pop();
            continue;
        };
        *next_use += 1;
        match state.get(next) {
            Some(Visit::Active) => found.push(cycle(&stack, node, next, span)),
            Some(Visit::Done) => {}
            None => {
                stack.push((node, span));
                state.insert(next, Visit::Active);
                frames.push((next, 0));
            }
        }
    }
}

/// The cycle closed by `node` using `next` (at `span`), which is on `stack` or is `node`.
fn cycle(stack: &[(&str, Span)], node: &str, next: &str, span: Span) -> (Vec<String>, Vec<Span>) {
    let start = stack
        .iter()
        .position(|(n, _)| *n == next)
        .unwrap_or(stack.len());
    let on_cycle = stack.get(start..).unwrap_or(&[]);
    let mut path: Vec<String> = on_cycle.iter().map(|(n, _)| n.to_string()).collect();
    path.push(node.to_string());
    path.push(next.to_string());
    let mut uses: Vec<Span> = on_cycle.iter().skip(1).map(|(_, s)| *s).collect();
    uses.push(span);
    (path, uses)
}

/// The value of a number written in a predicate (`7`, `-7`, `(7)`), if `expr` is one.
fn literal(expr: &Expr) -> Option<i64> {
    match &expr.kind {
        ExprKind::Int(n) => Some(*n),
        ExprKind::Paren(inner) => literal(inner),
        ExprKind::Unary {
            op: UnaryOp::Negate,
            operand,
        } => literal(operand).and_then(i64::checked_neg),
        _ => None,
    }
}

/// Most statements all the sequences of a file expand to together: `check` expands and lowers
/// each sequence, so this bounds its work on a file of many sequences using a long one.
pub const MAX_EXPANDED_PER_FILE: usize = 1_000_000;

/// Deepest chain of sequences using sequences that expansion (a recursive pass) accepts.
pub const MAX_COMPOSITION_DEPTH: usize = 64;

/// For an acyclic file, each sequence's size once expanded (statements, saturating) and depth
/// of composition, computed without expanding; sequences are visited callees first with an
/// explicit stack.
fn expanded_sizes<'f>(
    file: &'f SourceFile,
    graph: &UsesGraph<'f>,
) -> BTreeMap<&'f str, (usize, usize)> {
    let mut sizes: BTreeMap<&'f str, (usize, usize)> = BTreeMap::new();
    let mut decls: BTreeMap<&str, &SequenceDecl> = BTreeMap::new();
    for decl in file.sequences() {
        decls.entry(decl.name.name.as_str()).or_insert(decl);
    }
    for decl in file.sequences() {
        let mut todo = vec![decl.name.name.as_str()];
        while let Some(&name) = todo.last() {
            if sizes.contains_key(name) {
                todo.pop();
                continue;
            }
            let uses = graph.get(name).map(Vec::as_slice).unwrap_or(&[]);
            let pending: Vec<&str> = uses
                .iter()
                .map(|(callee, _)| *callee)
                .filter(|callee| !sizes.contains_key(callee) && graph.contains_key(callee))
                .collect();
            if !pending.is_empty() {
                todo.extend(pending);
                continue;
            }
            let own = match decls.get(name).map(|d| &d.definition) {
                Some(SequenceDef::Body(body)) => statements_in(body),
                _ => 0,
            };
            let (mut count, mut depth) = (own, 0usize);
            for (callee, _) in uses {
                let (n, d) = sizes.get(callee).copied().unwrap_or((0, 0));
                count = count.saturating_add(n);
                depth = depth.max(d);
            }
            sizes.insert(name, (count, depth + 1));
            todo.pop();
        }
    }
    sizes
}

/// Statements written in `body` and its blocks (calls not followed).
fn statements_in(body: &Body) -> usize {
    let mut count = 0usize;
    let mut stack = vec![body];
    while let Some(body) = stack.pop() {
        for element in &body.elements {
            match &element.kind {
                ElementKind::Statement(_) => count += 1,
                ElementKind::Block(inner) => stack.push(inner),
                ElementKind::Call(_) => {}
            }
        }
    }
    count
}

// ---------- resolution, shared with later passes ----------

/// `M12` is the module with ID 12.
pub fn parse_module_label(name: &str) -> Option<u32> {
    let digits = name.strip_prefix('M')?;
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// Who runs a statement labelled `label` in `file` (roles take precedence over `M<k>`).
pub fn resolve_label(file: &SourceFile, label: &str) -> Option<Label> {
    if file.has_role(label) {
        return Some(Label::Role(label.to_string()));
    }
    parse_module_label(label).map(Label::Module)
}

/// Resolves part, index, operation and arguments of a statement. An unknown label is reported
/// by the checker, not here (it resolves to a role of that name).
pub fn resolve_statement(
    file: &SourceFile,
    statement: &Statement,
    robot: &RobotApi,
) -> Result<ResolvedStatement, Vec<Diagnostic>> {
    let mut errors = Vec::new();
    let Some((part_idx, part)) = robot.part(&statement.part.name) else {
        let known: Vec<String> = robot.parts.iter().map(|p| p.name.clone()).collect();
        let suggestion = closest(
            &statement.part.name,
            robot.parts.iter().map(|p| p.name.as_str()),
        );
        let kind = K::UnknownPart {
            part: statement.part.name.clone(),
            robot: robot.name.clone(),
            known,
            suggestion,
        };
        return Err(vec![Diagnostic::new(kind, statement.part.span)]);
    };
    let index = statement_index(statement, part, part_idx, robot, &mut errors);
    let Some((op_idx, op)) = part.operation(&statement.method.name) else {
        let known: Vec<String> = part.operations.iter().map(|o| o.name.clone()).collect();
        let suggestion = closest(
            &statement.method.name,
            part.operations.iter().map(|o| o.name.as_str()),
        );
        let kind = K::UnknownMethod {
            part: part.name.clone(),
            method: statement.method.name.clone(),
            known,
            suggestion,
        };
        errors.push(Diagnostic::new(kind, statement.method.span));
        return Err(errors);
    };
    if let (true, Some(i)) = (op.requires_male, index) {
        if !part.is_male(i) {
            let males: Vec<String> = part.male.iter().map(u32::to_string).collect();
            let kind = K::FemaleConnector {
                part: part.name.clone(),
                method: op.name.clone(),
                index: i,
                males: males.join(", "),
            };
            let span = statement
                .index
                .as_ref()
                .map_or(statement.method.span, |a| a.span);
            errors.push(Diagnostic::new(kind, span));
        }
    }
    let args = statement_args(statement, &op.params, robot, &mut errors, &op.signature());
    if !errors.is_empty() {
        return Err(errors);
    }
    let label = resolve_label(file, &statement.label.name)
        .unwrap_or(Label::Role(statement.label.name.clone()));
    Ok(ResolvedStatement {
        label,
        part: part_idx,
        index,
        operation: op_idx,
        args,
        span: statement.label.span.to(statement.args_span),
    })
}

fn statement_index(
    statement: &Statement,
    part: &Part,
    part_idx: usize,
    robot: &RobotApi,
    errors: &mut Vec<Diagnostic>,
) -> Option<i64> {
    match (&statement.index, part.count) {
        (Some(arg), Some(_)) => match resolve_index(arg, part, part_idx, robot) {
            Ok(i) => Some(i),
            Err(d) => {
                errors.push(d);
                None
            }
        },
        (None, Some(_)) => {
            let first = robot.constants.iter().find(|c| c.part == Some(part_idx));
            let example = first.map_or(format!("{}[0]", part.name), |c| {
                format!("{}[${}]", part.name, c.name)
            });
            let kind = K::MissingIndex {
                part: part.name.clone(),
                example,
            };
            errors.push(Diagnostic::new(kind, statement.part.span));
            None
        }
        (Some(arg), None) => {
            errors.push(Diagnostic::new(
                K::UnexpectedIndex {
                    part: part.name.clone(),
                },
                arg.span,
            ));
            None
        }
        (None, None) => None,
    }
}

fn resolve_index(
    arg: &Arg,
    part: &Part,
    part_idx: usize,
    robot: &RobotApi,
) -> Result<i64, Diagnostic> {
    let count = part.count.unwrap_or(0);
    let index = match &arg.kind {
        ArgKind::Int(n) => *n,
        ArgKind::Bool(b) => {
            let kind = K::WrongArgumentType {
                param: format!("{} index", part.name),
                expected: format!("a {} index", part.name),
                found: format!("`{b}`"),
            };
            return Err(Diagnostic::new(kind, arg.span));
        }
        ArgKind::Constant(name) => match robot.constant(name) {
            None => return Err(unknown_constant(name, arg.span, robot)),
            Some(c) if c.part.is_some() && c.part != Some(part_idx) => {
                let other = c
                    .part
                    .and_then(|p| robot.parts.get(p))
                    .map_or("other", |p| p.name.as_str());
                let kind = K::WrongArgumentType {
                    param: format!("{} index", part.name),
                    expected: format!("a {} index", part.name),
                    found: format!("`${name}`, a {other} index"),
                };
                return Err(Diagnostic::new(kind, arg.span));
            }
            Some(c) => c.value,
        },
    };
    if index < 0 || index >= i64::from(count) {
        return Err(Diagnostic::new(
            K::IndexOutOfRange {
                part: part.name.clone(),
                index,
                count,
            },
            arg.span,
        ));
    }
    Ok(index)
}

fn statement_args(
    statement: &Statement,
    params: &[crate::robot::Param],
    robot: &RobotApi,
    errors: &mut Vec<Diagnostic>,
    signature: &str,
) -> Vec<Value> {
    if statement.args.len() != params.len() {
        let kind = K::WrongArity {
            method: statement.method.name.clone(),
            signature: signature.to_string(),
            expected: params.len(),
            found: statement.args.len(),
        };
        errors.push(Diagnostic::new(kind, statement.args_span));
        return Vec::new();
    }
    let mut values = Vec::new();
    for (arg, param) in statement.args.iter().zip(params) {
        match resolve_arg(arg, param, robot) {
            Ok(v) => values.push(v),
            Err(d) => errors.push(d),
        }
    }
    values
}

fn resolve_arg(
    arg: &Arg,
    param: &crate::robot::Param,
    robot: &RobotApi,
) -> Result<Value, Diagnostic> {
    let value = match &arg.kind {
        ArgKind::Int(n) => Value::Int(*n),
        ArgKind::Bool(b) => Value::Bool(*b),
        ArgKind::Constant(name) => match robot.constant(name) {
            None => return Err(unknown_constant(name, arg.span, robot)),
            Some(c) if c.part.is_some() => {
                let kind = K::WrongArgumentType {
                    param: param.name.clone(),
                    expected: param.ty.describe(),
                    found: format!("`${name}`, an index name"),
                };
                return Err(Diagnostic::new(kind, arg.span));
            }
            Some(c) => Value::Int(c.value),
        },
    };
    let ok_type = matches!(
        (&param.ty, value),
        (ParamType::Bool, Value::Bool(_)) | (ParamType::Int { .. }, Value::Int(_))
    );
    if !ok_type {
        let kind = K::WrongArgumentType {
            param: param.name.clone(),
            expected: param.ty.describe(),
            found: format!("`{value}`"),
        };
        return Err(Diagnostic::new(kind, arg.span));
    }
    if let Value::Int(n) = value {
        if !param.ty.allows(n) {
            let kind = K::ArgumentOutOfRange {
                param: param.name.clone(),
                value: n,
                allowed: param.ty.allowed(),
            };
            return Err(Diagnostic::new(kind, arg.span));
        }
    }
    Ok(value)
}

fn unknown_constant(name: &str, span: Span, robot: &RobotApi) -> Diagnostic {
    let suggestion = closest(name, robot.constants.iter().map(|c| c.name.as_str()));
    Diagnostic::new(
        K::UnknownConstant {
            name: name.to_string(),
            suggestion,
        },
        span,
    )
}
