//! The independence check of parallel groups: two elements joined by `&` must give the same
//! configuration in either order, and two joint turns done at the same time must not sweep
//! through each other.

use crate::lockstep;
use crate::motion::{closest_approach, MovingSide};
use crate::orders::{every_order, Elements, Verdict, EVERY_ORDER_UP_TO};
use crate::robot_world::RobotWorld;
use crate::roles::Assignment;
use crate::simultaneous::{turns_together, Approach, Together};
use crate::warnings::unmatched;
use dynarole_core::ast::SeparatorKind;
use dynarole_core::check::ResolvedStatement;
use dynarole_core::diagnostic::{Diagnostic, DiagnosticKind};
use dynarole_core::expand::{Plan, PlanElement, PlanKind};
use dynarole_core::{Program, RobotApi};
use dynarole_world::Motion;
use std::cell::OnceCell;

/// Warnings for every pair of elements of a parallel group that are not independent, walking
/// the plans from the world's configuration. Pairs of whole-module turns that their motions prove
/// independent (`motion.rs`) are not run both ways; every other pair is.
pub fn check_independence(
    program: &Program,
    plans: &[Plan],
    world: RobotWorld,
    assignment: &Assignment,
) -> Vec<Diagnostic> {
    independence(program, plans, world, assignment, false)
}

/// The same check running every pair both ways on copies of the world: the reference the
/// motions' shortcut is tested against (the same warnings).
pub fn check_independence_exhaustive(
    program: &Program,
    plans: &[Plan],
    world: RobotWorld,
    assignment: &Assignment,
) -> Vec<Diagnostic> {
    independence(program, plans, world, assignment, true)
}

fn independence(
    program: &Program,
    plans: &[Plan],
    mut world: RobotWorld,
    assignment: &Assignment,
    exhaustive: bool,
) -> Vec<Diagnostic> {
    let checker = Checker {
        program,
        assignment,
        exhaustive,
    };
    let mut out = Vec::new();
    for plan in plans {
        checker.plan(plan, &mut world, &mut out);
    }
    out
}

/// Why two statements, both accepted in either order from `world` with the same result, may
/// not be done at the same time: the motions of two turns (`None` for anything else).
pub(crate) fn simultaneous_turns(
    program: &Program,
    assignment: &Assignment,
    (a, b): (&ResolvedStatement, &ResolvedStatement),
    world: &RobotWorld,
) -> Option<String> {
    let checker = Checker {
        program,
        assignment,
        exhaustive: true,
    };
    let (ma, mb) = (
        checker.statement_motion(a, world)?,
        checker.statement_motion(b, world)?,
    );
    checker.motions_apart(ma, mb, world, true)
}

/// Why statements `a` and `b`, joined by `&` in a group that starts from `world`, are not
/// independent as a group of two: the check `check_independence` makes of that pair of a
/// group (the group's turns together are `group_turns_conflict`'s). `sides`: their moving
/// sides on `world` (`MovingSide::of`, computed once per statement by the caller).
pub(crate) fn group_pair(
    program: &Program,
    assignment: &Assignment,
    (a, b): (&ResolvedStatement, &ResolvedStatement),
    sides: (Option<&MovingSide>, Option<&MovingSide>),
    world: &RobotWorld,
) -> Option<String> {
    let checker = Checker {
        program,
        assignment,
        exhaustive: false,
    };
    let element = |s: &ResolvedStatement| PlanElement {
        kind: PlanKind::Op(s.clone()),
        separator: SeparatorKind::Parallel,
        span: s.span,
    };
    let alone = Simultaneity::Pairwise { alone: true };
    checker.decided_pair(&element(a), &element(b), sides, world, alone)
}

/// What the turns of a group starting from `world`, done together, say about it.
pub(crate) enum GroupTurnsVerdict {
    /// Not safe for every relative timing: the statements involved (indices into the
    /// group, in order: the turns that bring the two modules together) and the reason.
    Conflict(Vec<usize>, String),
    /// Every statement is a turn, proven clear with the others and alone: any order and
    /// timing of them ends alike and keeps the structure, so nothing else is asked.
    Settled,
    /// Proven clear, or not turns on a tree: the pairs and the completion orders decide.
    Open,
}

/// The verdict on the turns of a group starting from `world`: `sides` are its statements'
/// moving sides on `world` in its order (`MovingSide::of`, computed once per statement by the
/// caller; `None` for what is not a turn).
pub(crate) fn group_turns(
    program: &Program,
    statements: &[&ResolvedStatement],
    sides: &[Option<&MovingSide>],
    world: &RobotWorld,
) -> GroupTurnsVerdict {
    let motions: Vec<Option<(&Motion, usize)>> = sides
        .iter()
        .map(|side| side.map(|s| (s.motion(), s.pivot)))
        .collect();
    let Some(together) = GroupTurns::of(&motions, world) else {
        return GroupTurnsVerdict::Open;
    };
    let describe = |i: usize| statements[i].describe(&program.robot);
    if let Some((involved, reason)) = together.conflict(world, &describe) {
        return GroupTurnsVerdict::Conflict(involved, reason);
    }
    let settled = (0..sides.len()).all(|i| {
        settled_by_turns(Some(&together), i)
            && sides[i].and_then(|s| s.sweep_clear(world)) == Some(true)
    });
    if settled {
        GroupTurnsVerdict::Settled
    } else {
        GroupTurnsVerdict::Open
    }
}

/// How the pair check treats two statements done at the same time.
#[derive(Clone, Copy)]
enum Simultaneity {
    /// Their group's turns were decided together (`GroupTurns`): nothing left for the pair;
    /// `clear` when they were found safe (then, on a tree, two turns whose own sweeps are
    /// clear are accepted in either order too).
    Decided { clear: bool },
    /// Decided for the pair, `alone` when they are their group's only two.
    Pairwise { alone: bool },
}

impl Simultaneity {
    /// How elements `i` and `k` of a group of `len` are treated, given its turns' verdict.
    fn of(together: Option<&GroupTurns>, (i, k): (usize, usize), len: usize) -> Simultaneity {
        match together {
            Some(t) if t.covers(i) && t.covers(k) => Simultaneity::Decided {
                clear: t.verdict == Together::Clear,
            },
            _ => Simultaneity::Pairwise { alone: len == 2 },
        }
    }
}

/// Is element `i` a turn that the group's turns, decided together, found clear? Such turns
/// end alike in every order among themselves and keep the structure: only what is not one
/// asks for the group's completion orders.
fn settled_by_turns(together: Option<&GroupTurns>, i: usize) -> bool {
    together.is_some_and(|t| t.covers(i) && t.verdict == Together::Clear)
}

/// Why a group is refused whose completion orders are too many to be checked.
pub(crate) fn too_large(len: usize) -> String {
    format!(
        "a group of {len} statements that are not all turns proven clear together is checked \
         in every completion order only up to {EVERY_ORDER_UP_TO} statements: split it"
    )
}

/// The turns of one group decided together over every relative timing (`simultaneous.rs`):
/// the group's elements that are turns, and what they do together.
struct GroupTurns {
    members: Vec<usize>,
    limit: f64,
    verdict: Together,
}

impl GroupTurns {
    /// The verdict on the elements whose motions (with their modules) move modules, when
    /// there are at least two and the robot's own check or the search over turns on a tree
    /// decides them (a motion that is not a turn only the robot's own check decides).
    fn of(motions: &[Option<(&Motion, usize)>], world: &RobotWorld) -> Option<GroupTurns> {
        let members: Vec<usize> = (0..motions.len())
            .filter(|&i| motions[i].as_ref().is_some_and(|(m, _)| m.moves()))
            .collect();
        if members.len() < 2 {
            return None;
        }
        let turns: Vec<(&Motion, usize)> = members.iter().filter_map(|&i| motions[i]).collect();
        let limit = turns.iter().map(|(m, _)| m.limit).fold(0.0, f64::max);
        let verdict = turns_together(&turns, world)?;
        Some(GroupTurns {
            members,
            limit,
            verdict,
        })
    }

    fn covers(&self, element: usize) -> bool {
        self.members.contains(&element)
    }

    /// The elements a conflict involves (the turns that bring the modules together, in the
    /// group's order: it is reported on the first two) and why; `describe` names an element.
    fn conflict(
        &self,
        world: &RobotWorld,
        describe: &dyn Fn(usize) -> String,
    ) -> Option<(Vec<usize>, String)> {
        let (approach, proven) = match &self.verdict {
            Together::Clear => return None,
            Together::Closest(approach) => (approach, true),
            Together::Unproven(approach) => (approach, false),
        };
        let elements: Vec<usize> = approach.turns.iter().map(|&t| self.members[t]).collect();
        if elements.len() < 2 {
            return None;
        }
        let reason = self.reason(approach, proven, world, &|| {
            let others: Vec<String> = elements[2..]
                .iter()
                .map(|&e| format!("`{}`", describe(e)))
                .collect();
            others.join(", ")
        });
        Some((elements, reason))
    }

    fn reason(
        &self,
        approach: &Approach,
        proven: bool,
        world: &RobotWorld,
        others: &dyn Fn() -> String,
    ) -> String {
        let limit = self.limit;
        let unit = world.model().length_unit();
        let d = approach.distance;
        let view = world.view();
        let (a, b) = (view.name(approach.modules.0), view.name(approach.modules.1));
        let with = if approach.turns.len() > 2 {
            format!(" with {}", others())
        } else {
            String::new()
        };
        if let Some(rule) = &approach.rule {
            return format!("done at the same time{with}, {rule}");
        }
        if proven {
            format!(
                "done at the same time{with}, the turns bring {a} and {b} within {d:.3} {unit} \
                 of each other (limit {limit})"
            )
        } else {
            format!(
                "done at the same time{with}, the turns could not be proven to keep {a} and {b} \
                 {limit} {unit} apart for every relative timing (lower bound {d:.3})"
            )
        }
    }
}

pub(crate) use crate::robot_world::Warned;

/// One order of a pair, run on a copy of the world: where it ends and what the model warned
/// about on the way.
pub(crate) struct OrderRun {
    pub world: RobotWorld,
    pub warnings: Vec<Warned>,
}

impl From<RobotWorld> for OrderRun {
    fn from(world: RobotWorld) -> OrderRun {
        OrderRun {
            world,
            warnings: Vec::new(),
        }
    }
}

/// What the two orders of a pair say about it.
pub(crate) enum Orders {
    /// Both accepted, ending alike, with the same warnings.
    Agree,
    /// Not independent, and why.
    Differ(String),
    /// A step is refused in either order.
    RefusedBoth,
}

/// The world's account of a difference is a header and one line per difference: the note
/// names the orders ("first" is the order in which `a` ends first) and the first difference,
/// so that it is a whole sentence however long the account.
fn differing_ends(difference: &str, (a, b): (String, String)) -> String {
    let lines: Vec<&str> = difference.lines().map(str::trim).collect();
    // An account of one line (another robot, say) is its own first difference.
    let mut details = lines.iter().skip(usize::from(lines.len() > 1));
    let first = details.next().copied().unwrap_or("they differ");
    let more = match details.count() {
        0 => String::new(),
        1 => ", and 1 more difference".to_string(),
        n => format!(", and {n} more differences"),
    };
    format!(
        "the two orders end in different configurations (first: `{a}` ends first, second: \
         `{b}` ends first; {first}{more})"
    )
}

/// The one decision on a pair run both ways (`ab`: `a` then `b`; `ba`: `b` then `a`; the
/// error is why a step was refused): a refusal in one order only, different end
/// configurations, or a warning one order gives and the other does not (the robot in two
/// parts for a moment if the retract ends first, say) make it not independent. `firsts`
/// describes `a` and `b`, asked only for a reason.
pub(crate) fn compare_orders(
    ab: Result<OrderRun, String>,
    ba: Result<OrderRun, String>,
    firsts: impl Fn() -> (String, String),
) -> Orders {
    let (ab, ba) = match (ab, ba) {
        (Ok(ab), Ok(ba)) => (ab, ba),
        (Ok(_), Err(reason)) | (Err(reason), Ok(_)) => {
            return Orders::Differ(format!(
                "in one of the two orders a step is refused ({reason})"
            ));
        }
        (Err(_), Err(_)) => return Orders::RefusedBoth,
    };
    if let Some(difference) = ab.world.difference(&ba.world) {
        return Orders::Differ(differing_ends(&difference, firsts()));
    }
    let (a, b) = (ab.warnings.as_slice(), ba.warnings.as_slice());
    let warned = match (unmatched(a, b), unmatched(b, a)) {
        (Some(warned), _) => Some((firsts().0, warned)),
        (None, Some(warned)) => Some((firsts().1, warned)),
        (None, None) => None,
    };
    match warned {
        Some((first, (step, warning))) if *step == first => {
            Orders::Differ(format!("if `{first}` ends first: {warning}"))
        }
        Some((first, (step, warning))) => {
            Orders::Differ(format!("if `{first}` ends first: `{step}`: {warning}"))
        }
        None => Orders::Agree,
    }
}

/// Does `statement` on `module`, adding the model's warnings to `warnings`; the error names
/// the step and says why the model refused it.
pub(crate) fn step(
    robot: &RobotApi,
    statement: &ResolvedStatement,
    module: &str,
    world: &mut RobotWorld,
    warnings: &mut Vec<Warned>,
) -> Result<(), String> {
    match world.apply(robot, statement, module) {
        Ok(outcome) => {
            if !outcome.warnings.is_empty() {
                let text = statement.describe(robot);
                let each = outcome.warnings.into_iter().map(|w| (text.clone(), w));
                warnings.extend(each);
            }
            Ok(())
        }
        Err(reason) => Err(format!("`{}`: {reason}", statement.describe(robot))),
    }
}

struct Checker<'a> {
    program: &'a Program<'a>,
    assignment: &'a Assignment,
    /// Run every pair both ways, even turns their motions prove independent.
    exhaustive: bool,
}

impl Checker<'_> {
    fn plan(&self, plan: &Plan, world: &mut RobotWorld, out: &mut Vec<Diagnostic>) {
        for group in groups(plan) {
            self.group(group, world, out);
            for element in group {
                if let PlanKind::Block(inner) = &element.kind {
                    // Groups inside a block are checked from the state the block starts in;
                    // a synchronous group's turns never run in any other timing than
                    // together, which the replay checks (`lockstep.rs`).
                    if !inner.synchronous {
                        self.plan(inner, &mut world.clone(), out);
                    }
                }
                // A refused step or a warning is the replay's to report; here a refused
                // step just changes nothing.
                let _ = self.apply(element, world, &mut Vec::new());
            }
        }
    }

    /// The warnings of one group, from the state `world` it starts in: its turns together,
    /// then every pair that the turns' verdict does not settle.
    fn group(&self, group: &[PlanElement], world: &RobotWorld, out: &mut Vec<Diagnostic>) {
        let warned = out.len();
        let sides = self.sides(group, world);
        let together = self.group_turns(group, world);
        if let Some(together) = &together {
            self.warn_group(group, together, world, out);
        }
        // Each turn's own sweep on the group's start, asked once per turn for the pairs whose
        // motions together the group found clear.
        let own: Vec<OnceCell<Option<bool>>> = vec![OnceCell::new(); group.len()];
        let clear_alone = |i: usize| {
            *own[i].get_or_init(|| sides[i].as_ref().and_then(|s| s.sweep_clear(world)))
                == Some(true)
        };
        for (i, a) in group.iter().enumerate() {
            for (k, b) in group.iter().enumerate().skip(i + 1) {
                let simultaneity = Simultaneity::of(together.as_ref(), (i, k), group.len());
                if let Simultaneity::Decided { clear: true } = simultaneity {
                    // On a tree, turns clear together whose own sweeps are clear are accepted
                    // in either order and end alike.
                    if clear_alone(i) && clear_alone(k) {
                        continue;
                    }
                }
                let sides = (sides[i].as_ref(), sides[k].as_ref());
                if let Some(reason) = self.decided_pair(a, b, sides, world, simultaneity) {
                    out.push(self.not_independent(a, b, reason));
                }
            }
        }
        // Pairs fine, three or more may still depend on each other only together.
        let settled = |i: usize| settled_by_turns(together.as_ref(), i) && clear_alone(i);
        if out.len() == warned && group.len() > 2 && !(0..group.len()).all(settled) {
            out.extend(self.orders(group, world));
        }
    }

    /// The warning of a group some completion order of which goes wrong where the written
    /// order does not (`orders.rs`), or that is too large to be checked so.
    fn orders(&self, group: &[PlanElement], world: &RobotWorld) -> Option<Diagnostic> {
        let apply = |e: &PlanElement, w: &mut RobotWorld, warned: &mut Vec<Warned>| {
            self.apply(e, w, warned)
        };
        let describe = |e: &PlanElement| self.describe(e);
        let elements = Elements {
            elements: group,
            apply: &apply,
            describe: &describe,
        };
        match every_order(&elements, world) {
            Verdict::Same => None,
            Verdict::Wrong(wrong) => {
                let (a, b) = (&group[wrong.at], &group[wrong.other]);
                Some(self.not_independent(a, b, wrong.reason))
            }
            Verdict::TooLarge => {
                let (a, b) = (&group[0], &group[group.len() - 1]);
                Some(self.not_independent(a, b, too_large(group.len())))
            }
        }
    }

    /// The warning that `a` and `b`, joined by `&`, are not independent, at `a`.
    fn not_independent(&self, a: &PlanElement, b: &PlanElement, reason: String) -> Diagnostic {
        let kind = DiagnosticKind::NotIndependent {
            step: self.describe(a),
            other_step: self.describe(b),
            reason,
            other: b.span,
        };
        Diagnostic::new(kind, a.span)
    }

    /// The group's turns decided together, when there are two or more on a tree.
    fn group_turns(&self, group: &[PlanElement], world: &RobotWorld) -> Option<GroupTurns> {
        let motions: Vec<Option<(Motion, usize)>> =
            group.iter().map(|e| self.motion(e, world)).collect();
        let refs: Vec<Option<(&Motion, usize)>> = (motions.iter())
            .map(|m| m.as_ref().map(|(m, t)| (m, *t)))
            .collect();
        GroupTurns::of(&refs, world)
    }

    /// The warning of a group whose turns are not safe together, on the first two turns
    /// involved.
    fn warn_group(
        &self,
        group: &[PlanElement],
        together: &GroupTurns,
        world: &RobotWorld,
        out: &mut Vec<Diagnostic>,
    ) {
        let describe = |i: usize| self.describe(&group[i]);
        if let Some((involved, reason)) = together.conflict(world, &describe) {
            let (a, b) = (&group[involved[0]], &group[involved[1]]);
            let reason = match self.lockstep_suggestion(group, together, world) {
                Some(suggestion) => format!("{reason}; {suggestion}"),
                None => reason,
            };
            out.push(self.not_independent(a, b, reason));
        }
    }

    /// When the group's turns, unsafe over every relative timing, are safe moved in
    /// lock-step: the synchronous group to write instead (`lockstep.rs` decides it as the
    /// replay would).
    fn lockstep_suggestion(
        &self,
        group: &[PlanElement],
        together: &GroupTurns,
        world: &RobotWorld,
    ) -> Option<String> {
        let statements: Vec<&PlanElement> = together.members.iter().map(|&i| &group[i]).collect();
        let plan = Plan {
            elements: (statements.iter().enumerate())
                .map(|(j, e)| PlanElement {
                    separator: if j + 1 == statements.len() {
                        SeparatorKind::Sequential
                    } else {
                        SeparatorKind::Parallel
                    },
                    ..(*e).clone()
                })
                .collect(),
            synchronous: true,
        };
        let mut after = world.clone();
        let fine = lockstep::apply_synchronous(
            self.program,
            &plan,
            &mut after,
            self.assignment,
            &mut Vec::new(),
        );
        fine.ok()?;
        Some(format!(
            "moved in lock-step they stay clear: write `{};`",
            lockstep::describe(self.program, &plan)
        ))
    }

    /// Each element's turn motion on `world` (the state its group starts from), for the
    /// pairs decided from motions; `None` for anything else, or all when exhaustive.
    fn sides(&self, group: &[PlanElement], world: &RobotWorld) -> Vec<Option<MovingSide>> {
        group
            .iter()
            .map(|element| match &element.kind {
                PlanKind::Op(statement) if !self.exhaustive => {
                    let module = self.assignment.get(&statement.label).map(String::as_str);
                    MovingSide::of(&self.program.robot, statement, module, world)
                }
                _ => None,
            })
            .collect()
    }

    /// Why `a` and `b` of one group are not independent, if they are not: turns that their
    /// moving sides (on the group's start state) prove independent are not run.
    fn decided_pair(
        &self,
        a: &PlanElement,
        b: &PlanElement,
        sides: (Option<&MovingSide>, Option<&MovingSide>),
        world: &RobotWorld,
        simultaneity: Simultaneity,
    ) -> Option<String> {
        if let (Some(sa), Some(sb)) = sides {
            // Such turns also warn alike in either order: the only warning a turn gets (its
            // joint already at the angle) does not depend on another module's turn. Linked
            // turns are proven so for the two of them alone: with more turns in a group that
            // were not decided together, the pair check says why.
            // A group's pair found clear together got here because a turn's own sweep is not
            // clear (`group`): the orders decide.
            let shortcut = match simultaneity {
                Simultaneity::Decided { clear } => !clear,
                Simultaneity::Pairwise { alone } => alone || !sa.linked(sb),
            };
            if shortcut && sa.proven_independent(sb, world) {
                return None;
            }
        }
        self.pair(a, b, world, simultaneity)
    }

    /// Why `a` and `b` are not independent, if they are not.
    fn pair(
        &self,
        a: &PlanElement,
        b: &PlanElement,
        world: &RobotWorld,
        simultaneity: Simultaneity,
    ) -> Option<String> {
        let run = |first: &PlanElement, second: &PlanElement| {
            let mut run = OrderRun::from(world.clone());
            self.apply(first, &mut run.world, &mut run.warnings)?;
            self.apply(second, &mut run.world, &mut run.warnings)?;
            Ok(run)
        };
        let firsts = || (self.describe(a), self.describe(b));
        match compare_orders(run(a, b), run(b, a), firsts) {
            Orders::Agree => match simultaneity {
                Simultaneity::Decided { .. } => None,
                Simultaneity::Pairwise { alone } => self.simultaneous_turns(a, b, world, alone),
            },
            Orders::Differ(reason) => Some(reason),
            // Refused in both orders: the replay reports the step itself.
            Orders::RefusedBoth => None,
        }
    }

    /// Two whole-module turns at once: they must move disjoint sets of modules, which must stay apart
    /// whatever their relative timing.
    fn simultaneous_turns(
        &self,
        a: &PlanElement,
        b: &PlanElement,
        world: &RobotWorld,
        alone: bool,
    ) -> Option<String> {
        self.motions_apart(self.motion(a, world)?, self.motion(b, world)?, world, alone)
    }

    /// Two motions done at the same time: a closest approach below the limit for some
    /// relative timing. Two turns that share moving modules, or one of which moves the other's
    /// module, are decided over every relative timing on a tree (`simultaneous.rs`) when they
    /// are their group's only two (`alone`); otherwise, or where the robot cannot be cut so,
    /// sharing a module is a conflict. Motions in place (latches) are the orders' to decide.
    fn motions_apart(
        &self,
        (ma, ta): (Motion, usize),
        (mb, tb): (Motion, usize),
        world: &RobotWorld,
        alone: bool,
    ) -> Option<String> {
        if !ma.moves() || !mb.moves() {
            return None;
        }
        let what = if ma.is_turn() && mb.is_turn() {
            "turns"
        } else {
            "motions"
        };
        let limit = ma.limit.max(mb.limit);
        let unit = world.model().length_unit();
        let within = |closest: f64| {
            format!("done at the same time, the {what} bring modules within {closest:.3} {unit} of each other (limit {limit})")
        };
        let shared: Vec<&str> = ma
            .moving
            .iter()
            .filter(|(name, _)| mb.moving.iter().any(|(other, _)| other == name))
            .map(|(name, _)| name.as_str())
            .collect();
        let carries = |m: &Motion, turner: usize| {
            let name = world.view().name(turner);
            m.moving.iter().any(|(n, _)| *n == name)
        };
        if shared.is_empty() && !carries(&ma, tb) && !carries(&mb, ta) {
            return closest_approach(&ma, &mb).map(within);
        }
        // One turn moving the other's modules is decided for the two of them alone: with a
        // third turn in the group, a module may be moved by all three at once, which the
        // pair's box does not cover.
        let together = if alone {
            turns_together(&[(&ma, ta), (&mb, tb)], world)
        } else {
            None
        };
        match together {
            Some(Together::Clear) => None,
            Some(Together::Closest(closest)) => Some(within(closest.distance)),
            Some(Together::Unproven(bound)) => Some(format!(
                "done at the same time, the {what} could not be proven to keep modules {limit} \
                 {unit} apart for every relative timing (lower bound {:.3})",
                bound.distance
            )),
            None if !shared.is_empty() && !alone => Some(format!(
                "both {what} move {} and the motions of their group are not all turns of a \
                 tree of modules, which only are checked together for every relative timing",
                shared.join(", ")
            )),
            None if !shared.is_empty() => Some(format!(
                "both {what} move {}; where they end depends on their timing",
                shared.join(", ")
            )),
            None => closest_approach(&ma, &mb).map(within),
        }
    }

    /// The motion of an operation and its module's index (`None` for a block).
    fn motion(&self, element: &PlanElement, world: &RobotWorld) -> Option<(Motion, usize)> {
        let PlanKind::Op(statement) = &element.kind else {
            return None;
        };
        self.statement_motion(statement, world)
    }

    /// The motion of a statement on the module of its label, and that module's index.
    fn statement_motion(
        &self,
        statement: &ResolvedStatement,
        world: &RobotWorld,
    ) -> Option<(Motion, usize)> {
        let module = self.assignment.get(&statement.label)?;
        let turner = world.view().index(module)?;
        Some((
            world.motion(&self.program.robot, statement, module)?,
            turner,
        ))
    }

    /// Applies an element (a block: all of it, in order), adding the model's warnings to
    /// `warnings`, and says why it was refused.
    fn apply(
        &self,
        element: &PlanElement,
        world: &mut RobotWorld,
        warnings: &mut Vec<Warned>,
    ) -> Result<(), String> {
        match &element.kind {
            PlanKind::Op(statement) => {
                let module = self
                    .assignment
                    .get(&statement.label)
                    .ok_or("no module for its label")?;
                step(&self.program.robot, statement, module, world, warnings)
            }
            PlanKind::Block(inner) if inner.synchronous => {
                let assignment = self.assignment;
                lockstep::apply_synchronous(self.program, inner, world, assignment, warnings)
            }
            PlanKind::Block(inner) => inner
                .elements
                .iter()
                .try_for_each(|e| self.apply(e, world, warnings)),
        }
    }

    fn describe(&self, element: &PlanElement) -> String {
        match &element.kind {
            PlanKind::Op(statement) => statement.describe(&self.program.robot),
            PlanKind::Block(inner) if inner.synchronous => lockstep::describe(self.program, inner),
            PlanKind::Block(inner) => match inner.statements().first() {
                Some(first) => format!("{{ {}; ... }}", first.describe(&self.program.robot)),
                None => "{ }".to_string(),
            },
        }
    }
}

/// The parallel groups of a plan (each ends with its `;` element).
fn groups(plan: &Plan) -> Vec<&[PlanElement]> {
    plan.elements
        .split_inclusive(|e| e.separator == SeparatorKind::Sequential)
        .collect()
}
