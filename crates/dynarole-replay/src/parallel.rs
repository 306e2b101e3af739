//! `parallelise`: the most parallelism that is provably safe on the model, found from a
//! sequence written in order. The dependency graph of the statements (what must stay ordered,
//! decided by the independence check on the state before the earlier statement), its
//! transitive reduction, the edges that keep each parallel group safe as a whole
//! (`parallel/groups.rs`), and its expression in the language as parallel groups (levels) or
//! as series-parallel blocks. Every form returned has been written out, parsed, replayed to the
//! input's final configuration and checked for independence forward and in reverse.

use crate::independence::{
    check_independence, compare_orders, simultaneous_turns, step, OrderRun, Orders, Warned,
};
use crate::robot_world::RobotWorld;
use crate::roles::Assignment;
use crate::run::replay;
use dynarole_core::ast::{ElementKind, Item};
use dynarole_core::check::{resolve_statement, ResolvedStatement};
use dynarole_core::diagnostic::{has_errors, Diagnostic, DiagnosticKind};
use dynarole_core::expand::Plan;
use dynarole_core::format::{format_items, statement as statement_text};
use dynarole_core::robot::OperationKind;
use dynarole_core::{driver, parse, Program, Span};
use dynarole_world::{Port, View};
use std::collections::BTreeMap;
use std::fmt::Write;

pub(crate) mod footprint;
mod groups;
mod layout;

use crate::bitset::BitSet;
use crate::motion::MovingSide;
use footprint::Later;
use groups::{GroupCheck, Split};
use layout::{ancestors, has_blocks, levels_layout, series_parallel, written_layout};
pub use layout::{transitive_reduction, Layout};

/// Rounds of "verify the output, add the edge it shows to be missing" before giving up on
/// parallelism (each round adds an edge; the sequential form is always valid).
const MAX_REPAIRS: usize = 64;

/// Which way the graph was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FormKind {
    /// Parallel groups separated by `;` (what the paper's protocol can run).
    Levels,
    /// Nested blocks `{ A; B } & { C; D };` where the graph is series-parallel.
    Blocks,
    /// The input order, one statement per group (when nothing parallel could be verified).
    Sequential,
    /// The input's own groups and blocks, when they verify (a candidate, not a result).
    AsWritten,
}

/// One verified way of writing the parallelised sequence.
#[derive(Clone, Debug)]
pub struct Form {
    pub kind: FormKind,
    pub layout: Layout,
    /// `sequence NAME { ... }`, in the canonical layout.
    pub text: String,
    /// Top-level parallel groups.
    pub groups: usize,
}

/// What `parallelise` found.
#[derive(Clone, Debug)]
pub struct Parallelised {
    /// The statements in input order, as source text.
    pub statements: Vec<String>,
    /// The model's dependency graph after transitive reduction, with the edges the group
    /// check and the verification's repairs added (earlier, later), input indices; one
    /// module's statements are pairs like any other unless the request keeps them in order.
    pub edges: Vec<(usize, usize)>,
    /// Verified forms, levels (or the sequential fallback) first.
    pub forms: Vec<Form>,
    /// The robot and role declarations the new sequence needs, as source.
    pub header: String,
    /// What the verification changed or gave up, in words.
    pub notes: Vec<String>,
}

/// What to parallelise and how.
pub struct Request<'a> {
    pub program: &'a Program<'a>,
    /// The sequence's name in the program (its reverse is checked too when it has one).
    pub sequence: &'a str,
    pub world: RobotWorld,
    pub assignment: &'a Assignment,
    /// Name of the new sequence.
    pub name: &'a str,
    /// Also try series-parallel blocks (not for the paper's protocol).
    pub blocks: bool,
    /// Join one module's statements with `&` when the model finds them independent, as it
    /// does any other pair (the lattice runtime starts them as one batch). `false` keeps each
    /// module's statements in input order, for the paper's protocol, which runs them one
    /// after the other in a group with other modules' statements (`docs/parallelise.md`).
    pub one_module_overlap: bool,
    /// Check only pairs at most this many statements apart; farther pairs stay ordered
    /// (faster on long sequences, less parallel). `None`: every pair.
    pub window: Option<usize>,
}

/// Builds the dependency graph of `request.sequence` from `request.world` and writes it as
/// the verified forms. Fails with the replay's diagnostics when the input itself does not
/// replay (a refused step), or with a message when no form can be verified.
pub fn parallelise(request: &Request) -> Result<Parallelised, ParalleliseError> {
    let program = request.program;
    let (plan, input, statements) = input_statements(request)?;
    let graph = Graph::build(request, &statements, false);
    let suspicious = suspicious_spans(&input.diagnostics);
    let check = GroupCheck::new(request, &statements, &suspicious);
    let verifier = Verifier {
        request,
        header: header(program),
        texts: statement_texts(program, &statements),
        expected: input.final_world,
        suspicious,
        spans: statements.iter().map(|s| s.span).collect(),
        reversible: program
            .reverse_sequence(request.sequence, "r")
            .is_some_and(|r| r.is_ok()),
    };
    let n = statements.len();
    let mut notes = Vec::new();
    if !request.one_module_overlap {
        notes = same_module_notes(&verifier.texts, &graph.same_module);
    }
    let (grouped, splits) = check.grouped(&graph.edges);
    notes.extend(split_notes(&verifier.texts, &splits));
    let (edges, levels) = verifier.levels(grouped, n, &mut notes)?;
    let mut forms = vec![levels];
    other_forms(&verifier, &plan, &edges, &mut forms, &mut notes);
    Ok(Parallelised {
        statements: verifier.texts.clone(),
        edges,
        forms,
        header: verifier.header.clone(),
        notes,
    })
}

/// The dependency graph of `request.sequence` (transitively reduced edges between input
/// indices), before any form is written. `exhaustive` runs every pair of statements both
/// ways on copies of the world, as the reference; otherwise pairs that can be decided from
/// the statements' footprints are (the same edges, faster).
pub fn dependency_graph(
    request: &Request,
    exhaustive: bool,
) -> Result<Vec<(usize, usize)>, ParalleliseError> {
    let (_, _, statements) = input_statements(request)?;
    Ok(Graph::build(request, &statements, exhaustive).edges)
}

/// The dependency graph with the edges the group check adds (`groups.rs`): what the
/// builder's own parallel groups are, before any verification.
pub fn group_checked_graph(request: &Request) -> Result<Vec<(usize, usize)>, ParalleliseError> {
    let (_, input, statements) = input_statements(request)?;
    let suspicious = suspicious_spans(&input.diagnostics);
    let check = GroupCheck::new(request, &statements, &suspicious);
    let graph = Graph::build(request, &statements, false);
    Ok(check.grouped(&graph.edges).0)
}

/// The input expanded, replayed (it must replay without a refused step) and its statements.
fn input_statements(
    request: &Request,
) -> Result<(Plan, crate::run::Replay, Vec<ResolvedStatement>), ParalleliseError> {
    let program = request.program;
    let plan = program.expand(request.sequence).ok_or_else(|| {
        ParalleliseError::Message(format!("no sequence named `{}`", request.sequence))
    })?;
    if plan.first_synchronous().is_some() {
        return Err(ParalleliseError::Message(format!(
            "`{}` has a synchronous group (`sync {{ ... }}`): its turns must start together, \
             which rearranging the statements would not keep; parallelise the sequences \
             around it",
            request.sequence
        )));
    }
    let input = replay(
        program,
        std::slice::from_ref(&plan),
        request.world.clone(),
        request.assignment,
    );
    if input.n_rejected > 0 || has_errors(&input.diagnostics) {
        return Err(ParalleliseError::Input(input.diagnostics));
    }
    let statements: Vec<ResolvedStatement> = plan.statements().into_iter().cloned().collect();
    if statements.is_empty() {
        return Err(ParalleliseError::Message(format!(
            "`{}` has no statements: nothing to parallelise",
            request.sequence
        )));
    }
    Ok((plan, input, statements))
}

/// Notes for the pairs kept in order only because one module does both (without
/// `one_module_overlap`): the first few, then how many more.
fn same_module_notes(texts: &[String], pairs: &[(usize, usize)]) -> Vec<String> {
    const SHOWN: usize = 4;
    let mut notes: Vec<String> = pairs
        .iter()
        .take(SHOWN)
        .map(|&(i, j)| {
            format!(
                "kept `{}` before `{}`: independent on the model, but one module does both and \
                 the paper's protocol runs them one after the other among other modules' \
                 statements (`&` would gain nothing)",
                texts[i], texts[j]
            )
        })
        .collect();
    if pairs.len() > SHOWN {
        notes.push(format!(
            "{} more pairs of one module's statements kept in order for the same reason",
            pairs.len() - SHOWN
        ));
    }
    notes
}

/// Notes for the edges the group check added: the first few, then how many more.
fn split_notes(texts: &[String], splits: &[Split]) -> Vec<String> {
    const SHOWN: usize = 4;
    let mut notes: Vec<String> = splits
        .iter()
        .take(SHOWN)
        .map(|split| {
            let (i, j) = split.edge;
            format!(
                "kept `{}` out of the group of `{}`: together with the group, {}",
                texts[j], texts[i], split.reason
            )
        })
        .collect();
    if splits.len() > SHOWN {
        notes.push(format!(
            "{} more statements kept out of a group that was not safe with them",
            splits.len() - SHOWN
        ));
    }
    notes
}

/// The candidates besides parallel groups: series-parallel blocks (unless the protocol is the
/// paper's) and the input's own groups when it has any; those that verify are added.
fn other_forms(
    verifier: &Verifier,
    plan: &Plan,
    edges: &[(usize, usize)],
    forms: &mut Vec<Form>,
    notes: &mut Vec<String>,
) {
    let blocks = verifier.request.blocks;
    let n = verifier.texts.len();
    let mut candidates = Vec::new();
    if blocks {
        candidates.push((FormKind::Blocks, series_parallel(n, edges)));
    }
    let written = written_layout(plan, &mut 0);
    let sequential =
        matches!(&written, Layout::Seq(v) if v.iter().all(|g| matches!(g, Layout::Op(_))));
    if !sequential && (blocks || !has_blocks(&written)) {
        candidates.push((FormKind::AsWritten, written));
    }
    for (kind, layout) in candidates {
        if forms.iter().any(|f| f.layout == layout) {
            continue;
        }
        match verifier.form(kind, layout) {
            Ok(form) => forms.push(form),
            Err(failure) => notes.push(match kind {
                FormKind::AsWritten => {
                    format!("the input's own groups do not verify ({})", failure.reason)
                }
                _ => format!("the block form did not verify ({})", failure.reason),
            }),
        }
    }
}

/// Why nothing could be written.
#[derive(Clone, Debug)]
pub enum ParalleliseError {
    /// The input does not replay: its refused steps, at their source locations.
    Input(Vec<Diagnostic>),
    Message(String),
}

/// The dependency graph of the input's statements: (earlier, later) pairs that must stay
/// ordered, transitively reduced.
struct Graph {
    edges: Vec<(usize, usize)>,
    /// Pairs independent on the model but done by one module (input indices): edges too
    /// without `one_module_overlap`.
    same_module: Vec<(usize, usize)>,
}

impl Graph {
    /// For each statement, from the nearest earlier one back: an edge when the pair must stay
    /// ordered and is not already ordered through the edges found. Parents found this way
    /// never reach one another, so the result is already transitively reduced. `exhaustive`
    /// decides every pair by running it both ways (the reference the fast path is tested
    /// against); otherwise pairs of turns are decided from their motions where
    /// `footprint.rs` can, without a copy of the world.
    fn build(request: &Request, statements: &[ResolvedStatement], exhaustive: bool) -> Graph {
        let n = statements.len();
        let (pre, warned) = pre_states(request, statements);
        let modules: Vec<Option<&str>> = statements
            .iter()
            .map(|s| request.assignment.get(&s.label).map(String::as_str))
            .collect();
        // Each turn's motion on the state it runs from in the input, computed once.
        let motions: Vec<Option<MovingSide>> = (0..n)
            .map(|i| MovingSide::of(&request.program.robot, &statements[i], modules[i], &pre[i]))
            .collect();
        let mut ancestors = vec![BitSet::new(n); n];
        let mut edges = Vec::new();
        let mut same_module = Vec::new();
        for j in 0..n {
            let later = Later::default();
            for i in (0..j).rev() {
                if ancestors[j].contains(i) {
                    continue;
                }
                let pair = Pair {
                    request,
                    a: &statements[i],
                    b: &statements[j],
                    modules: (modules[i], modules[j]),
                    motion_a: if exhaustive {
                        None
                    } else {
                        motions[i].as_ref()
                    },
                    warned_a: &warned[i],
                    index_a: i,
                    later: &later,
                };
                let beyond = request.window.is_some_and(|w| j - i > w);
                let order = if beyond {
                    Order::Model
                } else {
                    pair.order(&pre[i], &pre[i + 1])
                };
                if matches!(order, Order::SameModule) {
                    same_module.push((i, j));
                }
                let ordered = match order {
                    Order::Free => false,
                    Order::SameModule => !request.one_module_overlap,
                    Order::Model => true,
                };
                if ordered {
                    edges.push((i, j));
                    let above = ancestors[i].clone();
                    ancestors[j].union(&above);
                    ancestors[j].insert(i);
                }
            }
        }
        // Edges added without a check (beyond the window) may be implied by later ones.
        let edges = match request.window {
            Some(_) => transitive_reduction(n, &edges),
            None => {
                edges.sort_unstable();
                edges
            }
        };
        Graph { edges, same_module }
    }
}

/// The world before each statement, in input order, and at the end; and the model's warnings
/// on each statement there.
fn pre_states(
    request: &Request,
    statements: &[ResolvedStatement],
) -> (Vec<RobotWorld>, Vec<Vec<Warned>>) {
    let mut world = request.world.clone();
    let mut out = Vec::with_capacity(statements.len() + 1);
    let mut warned = Vec::with_capacity(statements.len());
    for statement in statements {
        out.push(world.clone());
        let mut warnings = Vec::new();
        if let Some(module) = request.assignment.get(&statement.label) {
            // The input replayed without a refusal, so this cannot fail.
            let robot = &request.program.robot;
            let _ = step(robot, statement, module, &mut world, &mut warnings);
        }
        warned.push(warnings);
    }
    out.push(world);
    (out, warned)
}

/// Why a pair of statements stays ordered, if it does.
enum Order {
    /// Independent on the model: they may run side by side.
    Free,
    /// Independent on the model, but done by one module: an edge only without
    /// `one_module_overlap` (the paper's protocol runs them one after the other, `&` would
    /// gain nothing; see `docs/parallelise.md`).
    SameModule,
    /// The model needs the order.
    Model,
}

/// Two statements, the earlier first, and their modules.
struct Pair<'a> {
    request: &'a Request<'a>,
    a: &'a ResolvedStatement,
    b: &'a ResolvedStatement,
    modules: (Option<&'a str>, Option<&'a str>),
    /// The moving side of `a` on the state before it, when `a` is a turn (the fast path).
    motion_a: Option<&'a MovingSide>,
    /// The model's warnings on `a` in the input (on the state before it).
    warned_a: &'a [Warned],
    /// `a`'s input index, and what is known of `b` from the pairs visited before.
    index_a: usize,
    later: &'a Later,
}

impl Pair<'_> {
    /// Whether the pair must stay ordered by the model, or is independent on it and done by
    /// one module (`Graph::build` decides what that means for the protocol). Conservative: the
    /// same latch, a step refused in either order, different results in the two orders, a
    /// warning in one order only (`compare_orders`, the decision `check --from` makes), or
    /// two turns that may sweep through each other (or move the same module). `before` and
    /// `after` are the states around `a` in the input.
    fn order(&self, before: &RobotWorld, after: &RobotWorld) -> Order {
        let (Some(ma), Some(mb)) = self.modules else {
            return Order::Model;
        };
        match (self.model_orders(before, after, ma, mb), ma == mb) {
            (true, _) => Order::Model,
            (false, true) => Order::SameModule,
            (false, false) => Order::Free,
        }
    }

    /// The model's checks, whoever does the two statements.
    fn model_orders(&self, before: &RobotWorld, after: &RobotWorld, ma: &str, mb: &str) -> bool {
        if self.same_latch(before, ma, mb) {
            return true;
        }
        if let Some(ordered) = self.turn_footprints(before) {
            return ordered;
        }
        let robot = &self.request.program.robot;
        // `a` then `b` is `b` on the state after `a`; `b` then `a` from the state before.
        let mut ab = OrderRun {
            world: after.clone(),
            warnings: self.warned_a.to_vec(),
        };
        let ab = step(robot, self.b, mb, &mut ab.world, &mut ab.warnings).map(|()| ab);
        let mut ba = OrderRun::from(before.clone());
        let ba = step(robot, self.b, mb, &mut ba.world, &mut ba.warnings)
            .and_then(|()| step(robot, self.a, ma, &mut ba.world, &mut ba.warnings))
            .map(|()| ba);
        let firsts = || (self.a.describe(robot), self.b.describe(robot));
        if !matches!(compare_orders(ab, ba, firsts), Orders::Agree) {
            // Refused in both orders too: conservative, the order of the input is kept.
            return true;
        }
        if !(kind(robot, self.a).is_turn() && kind(robot, self.b).is_turn()) {
            // Only two turns have a motion check; the rest is what was just done.
            return false;
        }
        // Both orders were just run and agree: what is left of the independence check of the
        // pair as a group is the motion of the two turns done at the same time.
        let (program, assignment) = (self.request.program, self.request.assignment);
        simultaneous_turns(program, assignment, (self.a, self.b), before).is_some()
    }

    /// Two turns decided from their motions alone, without running them (see
    /// `footprint.rs`): `Some(ordered)`, or `None` when the pair needs the full check.
    fn turn_footprints(&self, before: &RobotWorld) -> Option<bool> {
        let side_a = self.motion_a?;
        let robot = &self.request.program.robot;
        if !kind(robot, self.b).is_turn() {
            return None;
        }
        let b = (self.b, self.modules.1);
        self.later
            .decide(self.request, (side_a, self.index_a), b, before)
    }

    /// Connector operations on the two ends of one latch (made, or facing, before `a`).
    fn same_latch(&self, world: &RobotWorld, ma: &str, mb: &str) -> bool {
        let robot = &self.request.program.robot;
        if !(kind(robot, self.a).is_latch() && kind(robot, self.b).is_latch()) {
            return false;
        }
        let view = world.view();
        let (Some(pa), Some(pb)) = (port(robot, self.a, ma, view), port(robot, self.b, mb, view))
        else {
            return false;
        };
        partner(view, pa) == Some(pb) || partner(view, pb) == Some(pa)
    }
}

/// What `statement`'s operation does, as its plugin declares it.
fn kind(robot: &dynarole_core::RobotApi, statement: &ResolvedStatement) -> OperationKind {
    robot.kind(statement.part, statement.operation)
}

/// The port a connector statement works on.
fn port(
    robot: &dynarole_core::RobotApi,
    statement: &ResolvedStatement,
    module: &str,
    view: View,
) -> Option<Port> {
    if !kind(robot, statement).is_latch() {
        return None;
    }
    let connector = u8::try_from(statement.index?).ok()?;
    let index = view.index(module)?;
    Some(Port {
        module: index,
        connector,
    })
}

/// The port latched to `port`, or else the one it faces.
fn partner(view: View, port: Port) -> Option<Port> {
    view.latched_to(port).or_else(|| view.facing(port))
}

/// Writes forms out and checks them on the model, exactly as `check --from` would.
struct Verifier<'a> {
    request: &'a Request<'a>,
    header: String,
    texts: Vec<String>,
    expected: RobotWorld,
    /// Statements the input's replay already calls suspicious (by input index).
    suspicious: Vec<Span>,
    spans: Vec<Span>,
    reversible: bool,
}

/// Why a written form was not accepted, with the edge that would have prevented it.
struct Failure {
    reason: String,
    edge: Option<(usize, usize)>,
    /// A statement refused (or newly suspicious) in the written form, and which way it ran.
    refused: Option<(usize, Direction)>,
}

impl Failure {
    fn new(reason: String) -> Failure {
        Failure {
            reason,
            edge: None,
            refused: None,
        }
    }

    /// The edge to add: the pair named, or for a refused statement the nearest statement
    /// not yet ordered with it, on the side it ran after (before it in the input going
    /// forwards, after it in the reverse); when every one there is ordered with it, the
    /// nearest on the other side, as the input orders them: what the form ran before it may
    /// be a later statement of the input, which together with others (no pair alone) changed
    /// the state it runs on.
    fn repair(&self, n: usize, edges: &[(usize, usize)]) -> Option<(usize, usize)> {
        if self.edge.is_some() {
            return self.edge;
        }
        let (j, direction) = self.refused?;
        let anc = ancestors(n, edges);
        let earlier = || (0..j).rev().find(|i| !anc[j].contains(*i)).map(|i| (i, j));
        let later = || (j + 1..n).find(|k| !anc[*k].contains(j)).map(|k| (j, k));
        match direction {
            Direction::Forward => earlier().or_else(later),
            Direction::Backward => later().or_else(earlier),
        }
    }
}

impl Verifier<'_> {
    /// The levels form, repaired edge by edge until it verifies, else the input order.
    fn levels(
        &self,
        mut edges: Vec<(usize, usize)>,
        n: usize,
        notes: &mut Vec<String>,
    ) -> Result<(Vec<(usize, usize)>, Form), ParalleliseError> {
        for _ in 0..MAX_REPAIRS {
            let failure = match self.form(FormKind::Levels, levels_layout(n, &edges)) {
                Ok(form) => return Ok((edges, form)),
                Err(failure) => failure,
            };
            match failure.repair(n, &edges).filter(|e| !edges.contains(e)) {
                Some(edge) => {
                    notes.push(format!(
                        "kept `{}` before `{}`: {}",
                        self.texts[edge.0], self.texts[edge.1], failure.reason
                    ));
                    edges.push(edge);
                    edges = transitive_reduction(n, &edges);
                }
                None => {
                    notes.push(format!("written in the input order: {}", failure.reason));
                    break;
                }
            }
        }
        let chain: Vec<(usize, usize)> = (1..n).map(|j| (j - 1, j)).collect();
        let layout = Layout::Seq((0..n).map(Layout::Op).collect());
        let form = self.form(FormKind::Sequential, layout).map_err(|f| {
            ParalleliseError::Message(format!(
                "even the input order does not verify: {}",
                f.reason
            ))
        })?;
        Ok((chain, form))
    }

    /// Writes `layout`, parses it and checks it; the form when it passes.
    fn form(&self, kind: FormKind, layout: Layout) -> Result<Form, Failure> {
        let mut writer = Writer {
            texts: &self.texts,
            out: String::new(),
            starts: Vec::new(),
        };
        writer.sequence(self.request.name, &layout);
        let groups = match &layout {
            Layout::Seq(v) => v.len(),
            _ => 1,
        };
        let Writer {
            out: text, starts, ..
        } = writer;
        self.verify(&text, &starts)?;
        Ok(Form {
            kind,
            layout,
            text,
            groups,
        })
    }

    /// Replays the written sequence (and its reverse from the end) and checks independence.
    fn verify(&self, text: &str, starts: &[(usize, usize)]) -> Result<(), Failure> {
        let reverse_name = format!("{}_r", self.request.name);
        let mut source = format!("{}\n{text}", self.header);
        let offset = self.header.len() + 1;
        if self.reversible {
            let _ = write!(
                source,
                "\nsequence {reverse_name} = reverse {};\n",
                self.request.name
            );
        }
        let index: BTreeMap<u32, usize> = starts
            .iter()
            .filter_map(|(at, s)| Some((u32::try_from(at + offset).ok()?, *s)))
            .collect();
        let parsed = parse(&source);
        let program = driver::check_for(&parsed, &self.request.program.robot).map_err(|d| {
            Failure::new(format!(
                "the written sequence does not check: {:?}",
                d.first()
            ))
        })?;
        let lookup = Lookup { index: &index };
        let forward = program.expand(self.request.name).unwrap_or_default();
        let end = self.run(
            &program,
            &forward,
            self.request.world.clone(),
            &lookup,
            Direction::Forward,
        )?;
        if let Some(difference) = end.difference(&self.expected) {
            let first = difference.lines().next().unwrap_or_default().to_string();
            return Err(Failure::new(format!(
                "it ends elsewhere than the input ({first})"
            )));
        }
        if self.reversible {
            let backward = program.expand(&reverse_name).unwrap_or_default();
            self.run(&program, &backward, end, &lookup, Direction::Backward)?;
        }
        Ok(())
    }

    /// Replays `plan` and checks its groups; the end configuration when nothing is wrong.
    fn run(
        &self,
        program: &Program,
        plan: &Plan,
        world: RobotWorld,
        lookup: &Lookup,
        direction: Direction,
    ) -> Result<RobotWorld, Failure> {
        let assignment = self.request.assignment;
        let plans = std::slice::from_ref(plan);
        let result = replay(program, plans, world.clone(), assignment);
        for d in &result.diagnostics {
            let new_warning = match &d.kind {
                DiagnosticKind::StepSuspicious { .. } => lookup
                    .statement(d.span)
                    .is_none_or(|s| !self.suspicious.contains(&self.spans[s])),
                _ => true,
            };
            if new_warning {
                let reason = format!("{direction}, {}", describe(d));
                return Err(Failure {
                    refused: lookup.statement(d.span).map(|j| (j, direction)),
                    ..Failure::new(reason)
                });
            }
        }
        if let Some(d) = check_independence(program, plans, world, assignment).first() {
            let reason = format!("{direction}, {}", describe(d));
            let edge = match &d.kind {
                DiagnosticKind::NotIndependent { other, .. } => {
                    match (lookup.statement(d.span), lookup.statement(*other)) {
                        (Some(a), Some(b)) => Some((a.min(b), a.max(b))),
                        _ => None,
                    }
                }
                _ => None,
            };
            return Err(Failure {
                edge,
                ..Failure::new(reason)
            });
        }
        Ok(result.final_world)
    }
}

#[derive(Clone, Copy, Debug)]
enum Direction {
    Forward,
    Backward,
}

impl std::fmt::Display for Direction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Direction::Forward => "forwards",
            Direction::Backward => "in its reverse",
        })
    }
}

/// From a span of the written file to the input index of its statement.
struct Lookup<'a> {
    index: &'a BTreeMap<u32, usize>,
}

impl Lookup<'_> {
    fn statement(&self, span: Span) -> Option<usize> {
        self.index.get(&span.start).copied()
    }
}

fn describe(d: &Diagnostic) -> String {
    match &d.kind {
        DiagnosticKind::StepRejected { step, reason } => format!("`{step}` is refused: {reason}"),
        DiagnosticKind::StepSuspicious { step, reason } => format!("`{step}`: {reason}"),
        DiagnosticKind::NotIndependent {
            step,
            other_step,
            reason,
            ..
        } => {
            format!("`{step}` and `{other_step}` are not independent: {reason}")
        }
        other => format!("{other:?}"),
    }
}

/// Prints a layout in the canonical layout of `fmt`, noting where each statement starts.
struct Writer<'a> {
    texts: &'a [String],
    out: String,
    starts: Vec<(usize, usize)>,
}

impl Writer<'_> {
    fn sequence(&mut self, name: &str, layout: &Layout) {
        let _ = write!(self.out, "sequence {name} {{");
        self.body(layout, 1);
        self.out.push_str("\n}\n");
    }

    /// The groups of a `Seq` (or one group), one element per line.
    fn body(&mut self, layout: &Layout, depth: usize) {
        let groups: Vec<&Layout> = match layout {
            Layout::Seq(v) => v.iter().collect(),
            other => vec![other],
        };
        for g in groups {
            let members: Vec<&Layout> = match g {
                Layout::Par(v) => v.iter().collect(),
                other => vec![other],
            };
            for (k, m) in members.iter().enumerate() {
                self.out.push('\n');
                self.out.push_str(&"    ".repeat(depth));
                self.element(m, depth);
                self.out
                    .push_str(if k + 1 == members.len() { ";" } else { " &" });
            }
        }
    }

    fn element(&mut self, layout: &Layout, depth: usize) {
        match layout {
            Layout::Op(s) => {
                self.starts.push((self.out.len(), *s));
                self.out
                    .push_str(self.texts.get(*s).map_or("", String::as_str));
            }
            other => {
                self.out.push('{');
                self.body(other, depth + 1);
                self.out.push('\n');
                self.out.push_str(&"    ".repeat(depth));
                self.out.push('}');
            }
        }
    }
}

/// The robot and role declarations of the program, as source.
fn header(program: &Program) -> String {
    let items: Vec<Item> = program
        .file
        .items
        .iter()
        .filter(|item| matches!(item, Item::Robot(_) | Item::Role(_)))
        .cloned()
        .collect();
    format_items(items)
}

/// Each statement as written in the source when it is executed as written (its constants
/// kept), else as executed (a reversed statement, with its values).
fn statement_texts(program: &Program, statements: &[ResolvedStatement]) -> Vec<String> {
    let mut written: BTreeMap<Span, &dynarole_core::ast::Statement> = BTreeMap::new();
    for decl in program.file.sequences() {
        if let dynarole_core::ast::SequenceDef::Body(body) = &decl.definition {
            collect_statements(body, &mut written);
        }
    }
    statements
        .iter()
        .map(|s| {
            written
                .get(&s.span)
                .filter(|w| {
                    resolve_statement(program.file, w, &program.robot).is_ok_and(|r| r == *s)
                })
                .map_or_else(|| s.describe(&program.robot), |w| statement_text(w))
        })
        .collect()
}

fn collect_statements<'f>(
    body: &'f dynarole_core::ast::Body,
    out: &mut BTreeMap<Span, &'f dynarole_core::ast::Statement>,
) {
    // Bounded by the parser's nesting limit.
    for element in &body.elements {
        match &element.kind {
            ElementKind::Statement(s) => {
                out.insert(element.span, s);
            }
            ElementKind::Block(inner) => collect_statements(inner, out),
            ElementKind::Call(_) => {}
        }
    }
}

fn suspicious_spans(diagnostics: &[Diagnostic]) -> Vec<Span> {
    diagnostics
        .iter()
        .filter(|d| matches!(d.kind, DiagnosticKind::StepSuspicious { .. }))
        .map(|d| d.span)
        .collect()
}
