//! The independence check of parallel groups: two elements joined by `&` must give the same
//! configuration in either order, and two joint turns done at the same time must not sweep
//! through each other.

use crate::robot_world::RobotWorld;
use crate::roles::Assignment;
use dynarole_core::diagnostic::{Diagnostic, DiagnosticKind};
use dynarole_core::expand::{Plan, PlanElement, PlanKind};
use dynarole_core::Program;
use dynarole_world::{compare, TurnMotion, MIN_SWEEP_DISTANCE_LATTICE};

/// Steps per turn when two turns are sampled against each other (1.5 degrees for a quarter
/// turn). A warning, not a proof: the single-turn check of the world model is exact.
const SWEEP_SAMPLES: u32 = 60;

/// Warnings for every pair of elements of a parallel group that are not independent, walking
/// the plans from the world's configuration.
pub fn check_independence(
    program: &Program,
    plans: &[Plan],
    mut world: RobotWorld,
    assignment: &Assignment,
) -> Vec<Diagnostic> {
    let checker = Checker {
        program,
        assignment,
    };
    let mut out = Vec::new();
    for plan in plans {
        checker.plan(plan, &mut world, &mut out);
    }
    out
}

struct Checker<'a> {
    program: &'a Program<'a>,
    assignment: &'a Assignment,
}

impl Checker<'_> {
    fn plan(&self, plan: &Plan, world: &mut RobotWorld, out: &mut Vec<Diagnostic>) {
        for group in groups(plan) {
            for (i, a) in group.iter().enumerate() {
                for b in &group[i + 1..] {
                    if let Some(reason) = self.pair(a, b, world) {
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
        if let Err(difference) = compare(&ab.configuration(), &ba.configuration()) {
            let first_line = difference
                .to_string()
                .lines()
                .next()
                .unwrap_or_default()
                .to_string();
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
        let (ma, mb) = (self.motion(a, world)?, self.motion(b, world)?);
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
        let closest = closest_approach(&ma, &mb);
        (closest < MIN_SWEEP_DISTANCE_LATTICE).then(|| {
            format!("done at the same time, the turns bring modules within {closest:.3} lattice units of each other (limit {MIN_SWEEP_DISTANCE_LATTICE})")
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
        .split_inclusive(|e| e.separator == dynarole_core::ast::SeparatorKind::Sequential)
        .collect()
}

/// Smallest distance between a module moved by `a` and one moved by `b`, over every pair of
/// moments of the two turns. Each module's sampled path is computed once, and a pair of
/// modules whose paths' bounding boxes are already farther apart than the closest pair found
/// is skipped (the box distance is a lower bound): the same minimum, without comparing every
/// moment of every pair of modules of two large moving sides.
fn closest_approach(a: &TurnMotion, b: &TurnMotion) -> f64 {
    let paths_a: Vec<Path> = a.moving.iter().map(|(_, p)| Path::of(a, *p)).collect();
    let paths_b: Vec<Path> = b.moving.iter().map(|(_, p)| Path::of(b, *p)).collect();
    let mut best = f64::INFINITY;
    for pa in &paths_a {
        for pb in &paths_b {
            if pa.box_distance(pb) >= best {
                continue;
            }
            for x in &pa.points {
                for y in &pb.points {
                    best = best.min(distance(*x, *y));
                }
            }
        }
    }
    best
}

/// A moving module's sampled positions during a turn, and their bounding box.
struct Path {
    points: Vec<[f64; 3]>,
    low: [f64; 3],
    high: [f64; 3],
}

impl Path {
    fn of(turn: &TurnMotion, start: [f64; 3]) -> Path {
        let points: Vec<[f64; 3]> = (0..=SWEEP_SAMPLES)
            .map(|i| turn.position_at(start, f64::from(i) / f64::from(SWEEP_SAMPLES)))
            .collect();
        let (mut low, mut high) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in &points {
            for k in 0..3 {
                low[k] = low[k].min(p[k]);
                high[k] = high[k].max(p[k]);
            }
        }
        Path { points, low, high }
    }

    /// The distance between the two bounding boxes (0 when they overlap).
    fn box_distance(&self, other: &Path) -> f64 {
        let gap = |k: usize| {
            (other.low[k] - self.high[k])
                .max(self.low[k] - other.high[k])
                .max(0.0)
        };
        (gap(0).powi(2) + gap(1).powi(2) + gap(2).powi(2)).sqrt()
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}
