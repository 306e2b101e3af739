//! Lowering of expanded plans to the state-machine IR that every back-end (C, nesC, the model
//! checker) is generated from: statements with module addresses, operation codes and their
//! dependencies, and, for the paper's protocol, the original compiler's state numbers.

use crate::ast::{Expr, SeparatorKind};
use crate::check::{Label, Program, ResolvedStatement};
use crate::expand::{Plan, PlanKind};
use crate::robot::Value;
use crate::span::Span;
use std::collections::BTreeSet;

/// Highest address a module can have: 254 and 255 are reserved (end, "all" and "none").
pub const MAX_ADDRESS: u32 = 253;
/// Largest window of the lattice protocol the compiler will generate.
pub const MAX_WINDOW: usize = 128;
/// States of the paper protocol are one byte, and 254, 255 are reserved.
pub const MAX_PAPER_STATE: u32 = 253;
/// The paper protocol's reserved state "the sequence has ended" (`DR_STATE_END` in C).
pub const PAPER_STATE_END: u8 = 254;
/// The paper protocol's reserved state "nothing to do" (`DR_STATE_IDLE` in C).
pub const PAPER_STATE_IDLE: u8 = 255;
/// The paper protocol's recipient of the end: every module (`DR_ADDRESS_ALL` in C).
pub const PAPER_ADDRESS_ALL: u8 = 255;

/// Where each statement runs and how the token reaches it, on one configuration.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TokenRoutes {
    /// ID of the module that runs each statement.
    pub holders: Vec<u16>,
    /// For each statement, the hops of the hand-over into it: (module ID, connector it sends
    /// on), from the previous statement's module up to the one before this statement's.
    /// Empty for the first statement and when the previous one ran on the same module.
    pub routes: Vec<Vec<(u16, u8)>>,
}

/// The compiled form of one or more sequences run in turn.
#[derive(Clone, Debug, PartialEq)]
pub struct Ir {
    pub robot: String,
    /// Who can run statements: index = address number is in `Address::number`.
    pub addresses: Vec<Address>,
    /// The operations used, in code order: `(part, operation)` names.
    pub operations: Vec<(String, String)>,
    pub statements: Vec<IrStatement>,
    /// Statements the lattice protocol must track above its low-water mark (a multiple of 8).
    pub window: usize,
    /// The longest argument list.
    pub max_args: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Address {
    pub number: u8,
    pub label: Label,
    /// For a role: its predicate (evaluated on the module at start-up).
    pub predicate: Option<Expr>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct IrStatement {
    pub address: u8,
    /// Index into `Ir::operations`.
    pub op: u8,
    pub index: u8,
    pub args: Vec<i16>,
    /// Statements that must be complete before this one starts: the previous parallel group
    /// (within its block). This is the ordering the sequence means, which checkers verify.
    pub deps: Vec<u16>,
    /// The same module's previous statement (source order): the order of a module that runs
    /// one operation at a time, a bound the simulator's critical path reports. No protocol
    /// waits for it: the lattice runs a module's overlapping statements together, the paper
    /// protocol's blocks too.
    pub previous_on_module: Option<u16>,
    /// `;` or `&` after it in the flattened source (the paper protocol's view).
    pub separator: SeparatorKind,
    /// The statement as executed, e.g. `M3.Joint.rotateFromToBy(0, 324, false, 150)`.
    pub text: String,
    pub span: Span,
    /// The synchronous group it belongs to, if any (`sync { ... }`): its members start at one
    /// agreed instant and move in lock-step (`crate::synchronous`).
    pub synchronous: Option<SyncGroup>,
}

/// A synchronous group of the IR: its members are the `size` statements from `first` on
/// (a group is one parallel group of statements, numbered one after another).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SyncGroup {
    pub first: u16,
    pub size: u16,
}

/// A limit of the target that the sequence exceeds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LimitError {
    pub message: String,
    pub span: Span,
}

impl Program<'_> {
    /// Lowers `plans` (run in turn) to the IR; fails, naming the limit, where a sequence does
    /// not fit what the runtime encodes.
    pub fn lower(&self, plans: &[Plan]) -> Result<Ir, LimitError> {
        let mut flat = Vec::new();
        let mut entry: Vec<u16> = Vec::new();
        for plan in plans {
            entry = flatten(plan, &entry, &mut flat)?;
        }
        let addresses = self.addresses(&flat)?;
        let mut operations: Vec<(String, String)> = Vec::new();
        let mut statements: Vec<IrStatement> = Vec::new();
        // Each address's latest statement so far.
        let mut latest = [None; 256];
        for (statement, deps, separator) in &flat {
            let lowered = self.lower_statement(
                statement,
                deps,
                *separator,
                &addresses,
                &mut operations,
                &latest,
            )?;
            latest[usize::from(lowered.address)] = Some(statements.len() as u16);
            statements.push(lowered);
        }
        for group in synchronous_groups(plans) {
            let members =
                usize::from(group.first)..usize::from(group.first) + usize::from(group.size);
            for member in &mut statements[members] {
                member.synchronous = Some(group);
            }
        }
        check_dep_entries(&statements)?;
        let window = window_needed(&statements, MAX_WINDOW).map_err(|s| {
            let message = format!("the lattice protocol would need a window of more than {MAX_WINDOW} statements: this statement can be complete while a statement more than {MAX_WINDOW} places before it is not");
            LimitError {
                message,
                span: statements.get(s).map_or(Span::default(), |s| s.span),
            }
        })?;
        let max_args = statements.iter().map(|s| s.args.len()).max().unwrap_or(0);
        Ok(Ir {
            robot: self.robot.name.clone(),
            addresses,
            operations,
            statements,
            window,
            max_args,
        })
    }

    fn lower_statement(
        &self,
        statement: &ResolvedStatement,
        deps: &[u16],
        separator: SeparatorKind,
        addresses: &[Address],
        operations: &mut Vec<(String, String)>,
        latest: &[Option<u16>; 256],
    ) -> Result<IrStatement, LimitError> {
        let limit = |message: String| LimitError {
            message,
            span: statement.span,
        };
        let address = addresses
            .iter()
            .find(|a| a.label == statement.label)
            .map_or(0, |a| a.number);
        let part = &self.robot.parts[statement.part];
        let key = (
            part.name.clone(),
            part.operations[statement.operation].name.clone(),
        );
        let op = match operations.iter().position(|o| *o == key) {
            Some(i) => i,
            None => {
                operations.push(key);
                operations.len() - 1
            }
        };
        let index = u8::try_from(statement.index.unwrap_or(0))
            .map_err(|_| limit("part index above 255".into()))?;
        let args = statement
            .args
            .iter()
            .map(|v| match v {
                Value::Int(n) => i16::try_from(*n)
                    .map_err(|_| limit(format!("argument {n} does not fit in 16 bits"))),
                Value::Bool(b) => Ok(i16::from(*b)),
            })
            .collect::<Result<Vec<i16>, LimitError>>()?;
        let previous_on_module = latest[usize::from(address)];
        Ok(IrStatement {
            address,
            op: u8::try_from(op).map_err(|_| limit("more than 256 kinds of operation".into()))?,
            index,
            args,
            deps: deps.to_vec(),
            previous_on_module,
            separator,
            text: statement.describe(&self.robot),
            span: statement.span,
            synchronous: None,
        })
    }

    /// `M<k>` is address k; roles get the next free numbers, in declaration order.
    fn addresses(&self, flat: &Flat) -> Result<Vec<Address>, LimitError> {
        let mut addresses: Vec<Address> = Vec::new();
        for (statement, _, _) in flat {
            let Label::Module(id) = statement.label else {
                continue;
            };
            if id > MAX_ADDRESS {
                let message = format!("module ID {id} is above {MAX_ADDRESS}, the largest address a one-byte packet field can carry");
                return Err(LimitError {
                    message,
                    span: statement.span,
                });
            }
            if !addresses.iter().any(|a| a.label == statement.label) {
                addresses.push(Address {
                    number: id as u8,
                    label: statement.label.clone(),
                    predicate: None,
                });
            }
        }
        let first_free = addresses
            .iter()
            .map(|a| u32::from(a.number) + 1)
            .max()
            .unwrap_or(0);
        // The roles the statements use, in declaration order (found through the file's
        // index: a scan of every item per sequence made many-sequence files quadratic).
        let mut roles: Vec<(usize, &crate::ast::RoleDecl)> = flat
            .iter()
            .filter_map(|(s, _, _)| match &s.label {
                Label::Role(name) => self.file.role(name),
                Label::Module(_) => None,
            })
            .collect();
        roles.sort_by_key(|(item, _)| *item);
        roles.dedup_by_key(|(item, _)| *item);
        for (next, (_, role)) in (first_free..).zip(roles) {
            let label = Label::Role(role.name.name.clone());
            if next > MAX_ADDRESS {
                return Err(LimitError {
                    message: format!("more roles and modules than the {MAX_ADDRESS} addresses"),
                    span: role.span,
                });
            }
            addresses.push(Address {
                number: next as u8,
                label,
                predicate: Some(role.predicate.clone()),
            });
        }
        addresses.sort_by_key(|a| a.number);
        Ok(addresses)
    }
}

pub use crate::limits::MAX_STATEMENTS;
/// Most statements one statement can wait for (`n_deps` is one byte in the lattice tables).
pub const MAX_WAITS: usize = u8::MAX as usize;
/// Most entries of the lattice dependency table (`first_dep` is 16 bits).
pub const MAX_DEP_ENTRIES: usize = u16::MAX as usize;

type Flat = Vec<(ResolvedStatement, Vec<u16>, SeparatorKind)>;

/// Appends the statements of `plan` to `out` with their dependencies; `entry` is what must be
/// complete before the plan starts. Returns the statements whose completion ends the plan.
/// Fails before appending a statement that would pass [`MAX_STATEMENTS`] or wait for more
/// than [`MAX_WAITS`], so the flattened form is never larger than the limits allow.
fn flatten(plan: &Plan, entry: &[u16], out: &mut Flat) -> Result<Vec<u16>, LimitError> {
    let mut group_entry: Vec<u16> = entry.to_vec();
    let mut group_exit: Vec<u16> = Vec::new();
    for element in &plan.elements {
        let exit = match &element.kind {
            PlanKind::Op(statement) => {
                let index = push_statement(out, statement, &group_entry, element.separator)?;
                vec![index]
            }
            PlanKind::Block(inner) => {
                let exit = flatten(inner, &group_entry, out)?;
                // The block's last statement carries the block's own separator.
                if let Some(last) = out.last_mut() {
                    last.2 = element.separator;
                }
                exit
            }
        };
        group_exit.extend(exit);
        if element.separator == SeparatorKind::Sequential {
            group_entry = std::mem::take(&mut group_exit);
        }
    }
    // A body ends with `;`, so group_exit is empty here; an unclosed group would end the
    // plan together with the last closed one.
    group_entry.extend(group_exit);
    Ok(group_entry)
}

/// The synchronous groups of `plans` (run in turn), numbered as `flatten` numbers their
/// statements: in source order, one after another. The flattening already fits the limits,
/// so every number fits in 16 bits.
fn synchronous_groups(plans: &[Plan]) -> Vec<SyncGroup> {
    fn walk(plan: &Plan, next: &mut usize, out: &mut Vec<SyncGroup>) {
        for element in &plan.elements {
            match &element.kind {
                PlanKind::Op(_) => *next += 1,
                PlanKind::Block(inner) if inner.synchronous => {
                    let size = inner.statements().len();
                    if let (Ok(first), Ok(size)) = (u16::try_from(*next), u16::try_from(size)) {
                        out.push(SyncGroup { first, size });
                    }
                    *next += size;
                }
                PlanKind::Block(inner) => walk(inner, next, out),
            }
        }
    }
    let mut out = Vec::new();
    let mut next = 0;
    for plan in plans {
        walk(plan, &mut next, &mut out);
    }
    out
}

fn push_statement(
    out: &mut Flat,
    statement: &ResolvedStatement,
    deps: &[u16],
    separator: SeparatorKind,
) -> Result<u16, LimitError> {
    let limit = |message: String| LimitError {
        message,
        span: statement.span,
    };
    if out.len() >= MAX_STATEMENTS {
        return Err(limit(format!(
            "more than {MAX_STATEMENTS} statements (statement numbers are 16 bits)"
        )));
    }
    // n_deps is one byte; the limit stays MAX_WAITS - 1 (what the message names).
    if deps.len() >= MAX_WAITS {
        return Err(limit(format!("this statement waits for the {} statements of the parallel group before it; the lattice tables hold at most {} per statement", deps.len(), MAX_WAITS - 1)));
    }
    out.push((statement.clone(), deps.to_vec(), separator));
    Ok((out.len() - 1) as u16)
}

/// The lattice dependency table holds every statement's `waits_for`, indexed by 16 bits.
fn check_dep_entries(statements: &[IrStatement]) -> Result<(), LimitError> {
    let mut total = 0usize;
    for statement in statements {
        total += statement.waits_for().len();
        if total > MAX_DEP_ENTRIES {
            let message = format!("the lattice dependency table would have more than {MAX_DEP_ENTRIES} entries (16-bit positions): too many statements wait for large parallel groups");
            return Err(LimitError {
                message,
                span: statement.span,
            });
        }
    }
    Ok(())
}

/// The smallest window (multiple of 8, at least 8) covering, for every statement s, every
/// earlier statement that is not a (transitive) dependency of s: those can still be incomplete
/// when s is complete, so both must fit above the low-water mark. `Err(s)` names the first
/// statement that would need more than `limit` (at most 128).
///
/// Linear in the statements and their dependencies: the ancestors of s are kept as a prefix
/// `0..low` that is entirely ancestors plus a 128-bit mask of the ancestors in `low..s`, which
/// is exact as long as no statement needs more than 128 (`s - low` stays below 128).
fn window_needed(statements: &[IrStatement], limit: usize) -> Result<usize, usize> {
    debug_assert!(limit <= 128);
    // For each statement: (low, mask), bit i of mask = statement low + i is an ancestor.
    let mut ancestors: Vec<(usize, u128)> = Vec::with_capacity(statements.len());
    let mut needed = 1usize;
    for (s, statement) in statements.iter().enumerate() {
        let waits = statement.waits_for();
        let base = waits
            .iter()
            .filter_map(|&d| ancestors.get(usize::from(d)))
            .map(|&(low, _)| low)
            .max()
            .unwrap_or(0);
        let mut mask = 0u128;
        for &d in &waits {
            let d = usize::from(d);
            let Some(&(low, theirs)) = ancestors.get(d) else {
                continue;
            };
            // low <= base, and d - base <= d - low < 128 when d is above the prefix.
            mask |= shifted_down(theirs, base - low);
            if d >= base {
                mask |= 1u128 << (d - base);
            }
        }
        let low = base + mask.trailing_ones() as usize;
        if low < s {
            let window = s - low + 1;
            if window > limit {
                return Err(s);
            }
            needed = needed.max(window);
        }
        ancestors.push((low, shifted_down(mask, low - base)));
    }
    Ok(needed.div_ceil(8).max(1) * 8)
}

/// `mask >> by`, zero when every bit is shifted out.
fn shifted_down(mask: u128, by: usize) -> u128 {
    u32::try_from(by)
        .ok()
        .and_then(|by| mask.checked_shr(by))
        .unwrap_or(0)
}

/// How the paper's compiler turned a statement (or a block) into states (e.9 of the protocol
/// notes): a parallel statement takes 3 states, a sequential one or a block of one module's
/// operations 2.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PaperUnitKind {
    /// `S`: add pending and start; `S+1`: transfer; `S+2`: wait, remove pending.
    Parallel,
    /// `S`: start; `S+1`: wait for the operation and an empty pending set, then go on.
    Sequential,
    /// A group `A & B & ... & Z;` all on one module: `S` starts all, `S+1` waits for all
    /// (without looking at the pending set, as the original did).
    Block,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PaperUnit {
    pub kind: PaperUnitKind,
    pub first_state: u8,
    /// Indices into `Ir::statements`.
    pub statements: Vec<usize>,
    pub address: u8,
}

impl IrStatement {
    /// Everything the lattice protocol waits for, sorted and without repeats: the dependencies
    /// only (what the sequence means). A module's statements that these let overlap run at
    /// once (a batch); those they order, the module runs in that order.
    pub fn waits_for(&self) -> Vec<u16> {
        let all: BTreeSet<u16> = self.deps.iter().copied().collect();
        all.into_iter().collect()
    }
}

impl Ir {
    /// Whether any statement belongs to a synchronous group.
    pub fn has_synchronous(&self) -> bool {
        self.statements.iter().any(|s| s.synchronous.is_some())
    }

    /// For each statement, every statement that depends on it through `deps`, transitively
    /// (what the sequence means; the checkers' S2). Dependencies always point backwards, so
    /// one pass from the end suffices.
    pub fn dependents(&self) -> Vec<Vec<usize>> {
        let n = self.statements.len();
        let mut out: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
        for s in (0..n).rev() {
            let mine: Vec<usize> = std::iter::once(s).chain(out[s].iter().copied()).collect();
            for d in &self.statements[s].deps {
                if let Some(set) = out.get_mut(usize::from(*d)) {
                    set.extend(mine.iter().copied());
                }
            }
        }
        out.into_iter().map(|s| s.into_iter().collect()).collect()
    }

    /// The state layout of the paper's compiler. The plan must already be flat (see
    /// `Plan::flatten_for_paper`).
    pub fn paper_layout(&self) -> Result<Vec<PaperUnit>, LimitError> {
        let mut units = Vec::new();
        let mut state = 1u32;
        let mut start = 0usize;
        while start < self.statements.len() {
            let end = (start..self.statements.len())
                .find(|&i| self.statements[i].separator == SeparatorKind::Sequential)
                .map_or(self.statements.len(), |i| i + 1);
            let group: Vec<usize> = (start..end).collect();
            let address = self.statements[start].address;
            if group.len() > 1 && group.iter().all(|&i| self.statements[i].address == address) {
                units.push(self.paper_unit(PaperUnitKind::Block, &mut state, group, address)?);
            } else {
                for i in group {
                    let kind = match self.statements[i].separator {
                        SeparatorKind::Parallel => PaperUnitKind::Parallel,
                        SeparatorKind::Sequential => PaperUnitKind::Sequential,
                    };
                    let address = self.statements[i].address;
                    units.push(self.paper_unit(kind, &mut state, vec![i], address)?);
                }
            }
            start = end;
        }
        Ok(units)
    }

    fn paper_unit(
        &self,
        kind: PaperUnitKind,
        state: &mut u32,
        statements: Vec<usize>,
        address: u8,
    ) -> Result<PaperUnit, LimitError> {
        let size = if kind == PaperUnitKind::Parallel {
            3
        } else {
            2
        };
        if *state + size - 1 > MAX_PAPER_STATE {
            let span = statements
                .first()
                .and_then(|&i| self.statements.get(i))
                .map_or(Span::default(), |s| s.span);
            let message = format!("the paper protocol numbers states in one byte (1 to {MAX_PAPER_STATE}); this statement would need state {}", *state + size - 1);
            return Err(LimitError { message, span });
        }
        let unit = PaperUnit {
            kind,
            first_state: *state as u8,
            statements,
            address,
        };
        *state += size;
        Ok(unit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The original definition, one set of ancestors per statement (quadratic): the reference
    /// the linear `window_needed` must agree with.
    fn window_reference(statements: &[IrStatement], limit: usize) -> Result<usize, usize> {
        let mut ancestors: Vec<BTreeSet<usize>> = Vec::new();
        let mut needed = 1usize;
        for (s, statement) in statements.iter().enumerate() {
            let mut mine = BTreeSet::new();
            for d in statement.waits_for() {
                let d = usize::from(d);
                mine.insert(d);
                mine.extend(ancestors[d].iter().copied());
            }
            if let Some(lowest) = (0..s).find(|t| !mine.contains(t)) {
                if s - lowest + 1 > limit {
                    return Err(s);
                }
                needed = needed.max(s - lowest + 1);
            }
            ancestors.push(mine);
        }
        Ok(needed.div_ceil(8).max(1) * 8)
    }

    /// Statements on `modules` modules, each depending on a few earlier ones.
    fn program(modules: u8) -> impl Strategy<Value = Vec<IrStatement>> {
        let one = (
            0..modules,
            proptest::collection::vec(any::<prop::sample::Index>(), 0..3),
        );
        proptest::collection::vec(one, 0..220).prop_map(|raw| {
            let mut latest = [None; 256];
            let mut out = Vec::new();
            for (i, (address, picks)) in raw.into_iter().enumerate() {
                let mut deps: Vec<u16> = if i == 0 {
                    Vec::new()
                } else {
                    picks.iter().map(|p| p.index(i) as u16).collect()
                };
                deps.sort_unstable();
                deps.dedup();
                out.push(IrStatement {
                    address,
                    op: 0,
                    index: 0,
                    args: Vec::new(),
                    deps,
                    previous_on_module: latest[usize::from(address)],
                    separator: SeparatorKind::Sequential,
                    text: String::new(),
                    span: Span::default(),
                    synchronous: None,
                });
                latest[usize::from(address)] = Some(i as u16);
            }
            out
        })
    }

    proptest! {
        #[test]
        fn window_matches_the_reference(
            statements in (1u8..6).prop_flat_map(program),
            limit in prop::sample::select(vec![4usize, 16, 40, 128]),
        ) {
            prop_assert_eq!(
                window_needed(&statements, limit),
                window_reference(&statements, limit)
            );
        }
    }

    #[test]
    fn a_long_chain_needs_the_smallest_window() {
        let statements: Vec<IrStatement> = (0..60_000u16)
            .map(|i| IrStatement {
                address: 1,
                op: 0,
                index: 0,
                args: Vec::new(),
                deps: i.checked_sub(1).into_iter().collect(),
                previous_on_module: i.checked_sub(1),
                separator: SeparatorKind::Sequential,
                text: String::new(),
                span: Span::default(),
                synchronous: None,
            })
            .collect();
        assert_eq!(window_needed(&statements, MAX_WINDOW), Ok(8));
    }
}
