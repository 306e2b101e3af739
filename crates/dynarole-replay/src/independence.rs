//! The independence check of parallel groups: two elements joined by `&` must give the same
//! configuration in either order, and two joint turns done at the same time must not sweep
//! through each other.

use crate::motion::{closest_approach, MovingSide};
use crate::robot_world::RobotWorld;
use crate::roles::Assignment;
use dynarole_core::ast::SeparatorKind;
use dynarole_core::check::ResolvedStatement;
use dynarole_core::diagnostic::{Diagnostic, DiagnosticKind};
use dynarole_core::expand::{Plan, PlanElement, PlanKind};
use dynarole_core::Program;
use dynarole_world::TurnMotion;

/// Warnings for every pair of elements of a parallel group that are not independent, walking
/// the plans from the world's configuration. Pairs of ATRON turns that their motions prove
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
    let motion = |s: &ResolvedStatement| {
        let module = assignment.get(&s.label)?;
        world.turn_motion(&program.robot, s, module)
    };
    checker.turns_apart(motion(a)?, motion(b)?, world)
}

/// Why statements `a` and `b`, joined by `&` in a group that starts from `world`, are not
/// independent: the check `check_independence` makes of that pair of the group. `sides`:
/// their moving sides on `world` (`MovingSide::of`, computed once per statement by the
/// caller).
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
    checker.decided_pair(&element(a), &element(b), sides, world)
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
            let sides = self.sides(group, world);
            for (i, a) in group.iter().enumerate() {
                for (k, b) in group.iter().enumerate().skip(i + 1) {
                    let sides = (sides[i].as_ref(), sides[k].as_ref());
                    if let Some(reason) = self.decided_pair(a, b, sides, world) {
                        let kind = DiagnosticKind::NotIndependent {
                            step: self.describe(a),
                            other_step: self.describe(b),
                            reason,
                            other: b.span,
                        };
                        out.push(Diagnostic::new(kind, a.span));
                    }
                }
            }
            for element in group {
                if let PlanKind::Block(inner) = &element.kind {
                    // Groups inside a block are checked from the state the block starts in.
                    self.plan(inner, &mut world.clone(), out);
                }
                // A refused step is the replay's to report; here it just changes nothing.
                let _ = self.apply(element, world);
            }
        }
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
    ) -> Option<String> {
        if let (Some(sa), Some(sb)) = sides {
            if sa.proven_independent(sb, world) {
                return None;
            }
        }
        self.pair(a, b, world)
    }

    /// Why `a` and `b` are not independent, if they are not.
    fn pair(&self, a: &PlanElement, b: &PlanElement, world: &RobotWorld) -> Option<String> {
        let mut ab = world.clone();
        let mut ba = world.clone();
        let first = self.apply(a, &mut ab).and_then(|()| self.apply(b, &mut ab));
        let second = self.apply(b, &mut ba).and_then(|()| self.apply(a, &mut ba));
        match (first, second) {
            (Ok(()), Ok(())) => {}
            (Ok(()), Err(reason)) | (Err(reason), Ok(())) => {
                return Some(format!(
                    "in one of the two orders a step is refused ({reason})"
                ));
            }
            // Refused in both orders: the replay reports the step itself.
            (Err(_), Err(_)) => return None,
        }
        if let Some(difference) = ab.difference(&ba) {
            let first_line = difference.lines().next().unwrap_or_default().to_string();
            return Some(format!(
                "the two orders end in different configurations ({first_line})"
            ));
        }
        self.simultaneous_turns(a, b, world)
    }

    /// Two ATRON turns at once: they must move disjoint sets of modules, which must stay apart
    /// whatever their relative timing.
    fn simultaneous_turns(
        &self,
        a: &PlanElement,
        b: &PlanElement,
        world: &RobotWorld,
    ) -> Option<String> {
        self.turns_apart(self.motion(a, world)?, self.motion(b, world)?, world)
    }

    /// Two turns done at the same time: a shared moving module, or a closest approach below
    /// the limit for some relative timing.
    fn turns_apart(&self, ma: TurnMotion, mb: TurnMotion, world: &RobotWorld) -> Option<String> {
        let shared: Vec<&str> = ma
            .moving
            .iter()
            .filter(|(name, _)| mb.moving.iter().any(|(other, _)| other == name))
            .map(|(name, _)| name.as_str())
            .collect();
        if !shared.is_empty() {
            return Some(format!(
                "both turns move {}; where they end depends on their timing",
                shared.join(", ")
            ));
        }
        let limit = ma.limit.max(mb.limit);
        let unit = world.model().length_unit();
        closest_approach(&ma, &mb).map(|closest| {
            format!("done at the same time, the turns bring modules within {closest:.3} {unit} of each other (limit {limit})")
        })
    }

    fn motion(&self, element: &PlanElement, world: &RobotWorld) -> Option<TurnMotion> {
        let PlanKind::Op(statement) = &element.kind else {
            return None;
        };
        let module = self.assignment.get(&statement.label)?;
        world.turn_motion(&self.program.robot, statement, module)
    }

    /// Applies an element (a block: all of it, in order) and says why it was refused.
    fn apply(&self, element: &PlanElement, world: &mut RobotWorld) -> Result<(), String> {
        match &element.kind {
            PlanKind::Op(statement) => {
                let module = self
                    .assignment
                    .get(&statement.label)
                    .ok_or("no module for its label")?;
                let step = statement.describe(&self.program.robot);
                world
                    .apply(&self.program.robot, statement, module)
                    .map(|_| ())
                    .map_err(|reason| format!("`{step}`: {reason}"))
            }
            PlanKind::Block(inner) => inner.elements.iter().try_for_each(|e| self.apply(e, world)),
        }
    }

    fn describe(&self, element: &PlanElement) -> String {
        match &element.kind {
            PlanKind::Op(statement) => statement.describe(&self.program.robot),
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
