//! The group-level check of `parallelise`: the pair graph's parallel groups, each checked as
//! a whole from the configuration it starts from, and split where the whole is not safe.
//!
//! A pair check cannot see statements that depend on each other only together (on eight2car,
//! two retracts of M3 and an extend of M1 are fine two by two, but both retracts before the
//! extend leave M3 alone), nor a pair that is independent on the input's states but not on the
//! state its group starts from. So the groups are built here the way the output runs them:
//! group after group from the input's start, each statement (in input order) joining the
//! first group after its parents' where the group with it still passes what the verification
//! asks of a group: it is accepted after the group's earlier statements with no warning the
//! input did not have, and it is independent of each of them on the group's start state
//! (`check_independence`'s pair check). Where it does not, the edge that keeps it out of that
//! group is added to the graph. The groups' reverse is left to the verification.

use super::{transitive_reduction, Request};
use crate::independence::{group_pair, group_turns, step, too_large, GroupTurnsVerdict};
use crate::motion::MovingSide;
use crate::orders::{every_order, Elements, Verdict};
use crate::robot_world::{RobotWorld, Warned};
use dynarole_core::check::ResolvedStatement;
use dynarole_core::Span;

/// An edge the group check added: the statement kept out, the one of the group it now
/// follows, and why.
pub(super) struct Split {
    pub edge: (usize, usize),
    pub reason: String,
}

/// What the group check needs to know of the input.
pub(super) struct GroupCheck<'a> {
    request: &'a Request<'a>,
    statements: &'a [ResolvedStatement],
    /// Statements the input's own replay already warns about (by input index).
    suspicious: Vec<bool>,
}

/// A group being filled: the state it starts from, its statements in input order and the
/// state after them (run in that order, as the replay of the written group does).
struct Group {
    start: RobotWorld,
    members: Vec<usize>,
    /// Each member's moving side on `start`, when it is a turn (for the pair check).
    sides: Vec<Option<MovingSide>>,
    after: RobotWorld,
}

impl<'a> GroupCheck<'a> {
    /// `suspicious`: the spans the input's own replay warns about.
    pub(super) fn new(
        request: &'a Request<'a>,
        statements: &'a [ResolvedStatement],
        suspicious: &[Span],
    ) -> GroupCheck<'a> {
        GroupCheck {
            request,
            statements,
            suspicious: statements
                .iter()
                .map(|s| suspicious.contains(&s.span))
                .collect(),
        }
    }

    /// `edges` with the splits added (transitively reduced), and the splits.
    pub(super) fn grouped(&self, edges: &[(usize, usize)]) -> (Vec<(usize, usize)>, Vec<Split>) {
        let splits = self.splits(edges);
        let mut all = edges.to_vec();
        all.extend(splits.iter().map(|s| s.edge));
        (transitive_reduction(self.statements.len(), &all), splits)
    }

    /// The edges that keep every parallel group of `edges` (levels: each statement one group
    /// after its latest parent) safe as a whole, each with its reason. With them added,
    /// `levels_layout` writes exactly the groups checked here.
    fn splits(&self, edges: &[(usize, usize)]) -> Vec<Split> {
        let n = self.statements.len();
        let mut parents = vec![Vec::new(); n];
        for &(i, j) in edges {
            if j < n {
                parents[j].push(i);
            }
        }
        let mut done = vec![false; n];
        let mut remaining: Vec<usize> = (0..n).collect();
        let mut world = self.request.world.clone();
        let mut splits = Vec::new();
        // Each round places at least the first ready statement, so at most `n` rounds.
        while !remaining.is_empty() {
            let mut group = Group {
                start: world.clone(),
                members: Vec::new(),
                sides: Vec::new(),
                after: world,
            };
            let mut left = Vec::new();
            for &j in &remaining {
                if !parents[j].iter().all(|&p| done[p]) {
                    left.push(j);
                    continue;
                }
                let side = self.side(&group.start, j);
                match self.conflict(&group, j, side.as_ref()) {
                    Some(split) => {
                        parents[j].push(split.edge.0);
                        splits.push(split);
                        left.push(j);
                    }
                    None => self.join(&mut group, j, side),
                }
            }
            for &m in &group.members {
                done[m] = true;
            }
            world = group.after;
            remaining = left;
        }
        splits
    }

    fn join(&self, group: &mut Group, j: usize, side: Option<MovingSide>) {
        self.apply(&mut group.after, j);
        group.members.push(j);
        group.sides.push(side);
    }

    /// Statement `j`'s moving side on `world`, when it is a turn.
    fn side(&self, world: &RobotWorld, j: usize) -> Option<MovingSide> {
        let robot = &self.request.program.robot;
        MovingSide::of(robot, &self.statements[j], self.module(j), world)
    }

    /// Runs statement `j` on `world`. A refusal is the verification's to report (a group of
    /// one statement is never split); the model leaves the world unchanged then, as the
    /// replay does.
    fn apply(&self, world: &mut RobotWorld, j: usize) {
        if let Some(module) = self.module(j) {
            let _ = world.apply(&self.request.program.robot, &self.statements[j], module);
        }
    }

    /// Why `j` cannot join `group` (which is safe as it is), as the edge that keeps it out:
    /// from the member named by a pair check, the latest first, or for a step refused (or
    /// newly suspicious) after the members, the latest member without which it is not.
    fn conflict(&self, group: &Group, j: usize, side: Option<&MovingSide>) -> Option<Split> {
        let (program, assignment) = (self.request.program, self.request.assignment);
        let pair = group
            .members
            .iter()
            .zip(&group.sides)
            .rev()
            .find_map(|(&i, side_i)| {
                let pair = (&self.statements[i], &self.statements[j]);
                let sides = (side_i.as_ref(), side);
                group_pair(program, assignment, pair, sides, &group.start).map(|r| (i, r))
            });
        if let Some((i, reason)) = pair {
            return Some(Split {
                edge: (i, j),
                reason,
            });
        }
        let settled = match self.turns_conflict(group, j, side) {
            Ok(settled) => settled,
            Err(split) => return Some(split),
        };
        let Some(reason) = self.step_problem(&group.after, j) else {
            if settled || group.members.len() < 2 {
                return None;
            }
            return self.orders_conflict(group, j);
        };
        let last = *group.members.last()?;
        let culprit = group
            .members
            .iter()
            .rev()
            .copied()
            .find(|&i| self.step_problem(&self.without(group, i), j).is_none())
            .unwrap_or(last);
        Some(Split {
            edge: (culprit, j),
            reason,
        })
    }

    /// Why `j`'s turn cannot join the group's turns done together, for some relative timing
    /// of them all (each pair alone may be fine): the edge from the latest member involved.
    /// Otherwise whether the group with it is all turns that settle it (`GroupTurnsVerdict`).
    fn turns_conflict(
        &self,
        group: &Group,
        j: usize,
        side: Option<&MovingSide>,
    ) -> Result<bool, Split> {
        // A statement that is not a turn adds nothing to the group's turns, and leaves the
        // group to its completion orders.
        if side.is_none() {
            return Ok(false);
        }
        let mut statements: Vec<&ResolvedStatement> =
            group.members.iter().map(|&i| &self.statements[i]).collect();
        statements.push(&self.statements[j]);
        let mut sides: Vec<Option<&MovingSide>> = group.sides.iter().map(Option::as_ref).collect();
        sides.push(side);
        let program = self.request.program;
        let (involved, reason) = match group_turns(program, &statements, &sides, &group.start) {
            GroupTurnsVerdict::Conflict(involved, reason) => (involved, reason),
            GroupTurnsVerdict::Settled => return Ok(true),
            GroupTurnsVerdict::Open => return Ok(false),
        };
        let newest = group.members.len();
        let culprit = involved
            .iter()
            .rev()
            .find(|&&e| e != newest)
            .or(involved.first())
            .and_then(|&e| group.members.get(e))
            .or(group.members.last());
        match culprit {
            Some(&culprit) => Err(Split {
                edge: (culprit, j),
                reason,
            }),
            None => Ok(false),
        }
    }

    /// Why `j` cannot join `group`, whose pairs are all fine with it, for some completion
    /// order of them all (`orders.rs`): the edge from the latest member without which every
    /// order is fine.
    fn orders_conflict(&self, group: &Group, j: usize) -> Option<Split> {
        let mut members = group.members.clone();
        members.push(j);
        let reason = self.orders_problem(&group.start, &members)?;
        let without = |skip: usize| -> Vec<usize> {
            members.iter().copied().filter(|&m| m != skip).collect()
        };
        let culprit = (group.members.iter().rev().copied())
            .find(|&i| self.orders_problem(&group.start, &without(i)).is_none())
            .or(group.members.last().copied())?;
        Some(Split {
            edge: (culprit, j),
            reason,
        })
    }

    /// Why `members` (input indices, in input order) started together from `start` go wrong
    /// in some completion order where the input order does not.
    fn orders_problem(&self, start: &RobotWorld, members: &[usize]) -> Option<String> {
        let robot = &self.request.program.robot;
        let apply = |&m: &usize, world: &mut RobotWorld, warned: &mut Vec<Warned>| {
            let module = self.module(m).ok_or("no module for its label")?;
            step(robot, &self.statements[m], module, world, warned)
        };
        let describe = |&m: &usize| self.statements[m].describe(robot);
        let elements = Elements {
            elements: members,
            apply: &apply,
            describe: &describe,
        };
        match every_order(&elements, start) {
            Verdict::Same => None,
            Verdict::Wrong(wrong) => Some(wrong.reason),
            Verdict::TooLarge => Some(too_large(members.len())),
        }
    }

    /// The state after `group`'s members but `skip`, run in order from its start.
    fn without(&self, group: &Group, skip: usize) -> RobotWorld {
        let mut world = group.start.clone();
        for &m in group.members.iter().filter(|&&m| m != skip) {
            self.apply(&mut world, m);
        }
        world
    }

    /// Why statement `j` run on `world` is refused, or warned about where the input's replay
    /// was not.
    fn step_problem(&self, world: &RobotWorld, j: usize) -> Option<String> {
        let module = self.module(j)?;
        let robot = &self.request.program.robot;
        let step = self.statements[j].describe(robot);
        match world.clone().apply(robot, &self.statements[j], module) {
            Err(reason) => Some(format!("`{step}` is refused: {reason}")),
            Ok(outcome) if !self.suspicious[j] => outcome
                .warnings
                .first()
                .map(|warning| format!("`{step}`: {warning}")),
            Ok(_) => None,
        }
    }

    fn module(&self, j: usize) -> Option<&str> {
        self.request
            .assignment
            .get(&self.statements[j].label)
            .map(String::as_str)
    }
}
