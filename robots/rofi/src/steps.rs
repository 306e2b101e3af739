//! A RoFI plan (a list of configurations) as steps: what changes between two consecutive
//! configurations, in the order RoFI's planners execute a step (disconnections, then
//! connections, then the joint turns, all at once), each checked the way the robot does it:
//! the robot stays connected, a connection is made only between mated connectors, and the
//! turns are proven safe over every relative timing (a parallel group), or only in lock-step
//! (a synchronous group), or refused with where they collide.

use crate::kinematics::{poses, KinematicsError};
use crate::module::{circular, Connection, Joint, RofiConfiguration};
use crate::sweep::{sweep, SweepError, SweepVerdict, Timing, Turn};
use crate::validity::{validate, Invalid};
use std::fmt;

/// How the turns of a step may run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Together {
    /// No turn, or one.
    Alone,
    /// Safe for every relative timing: joined by `&`.
    AnyTiming,
    /// Proven safe in lock-step, not over every timing (an overlap found there, or not
    /// proven within the budget): a synchronous group.
    LockStep,
}

/// One step of a plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    pub disconnects: Vec<Connection>,
    pub connects: Vec<Connection>,
    pub turns: Vec<Turn>,
    pub together: Together,
    /// Choices the step's file left open (a half turn of gamma has no direction), in words.
    pub notes: Vec<String>,
}

/// Why two consecutive configurations are not one step the robot can do.
#[derive(Clone, Debug, PartialEq)]
pub enum StepError {
    /// The two configurations do not hold the same modules.
    ModulesDiffer { missing: Vec<u32>, added: Vec<u32> },
    /// The configurations are the same: no action.
    Nothing,
    /// The robot falls apart once the step's connections are released.
    Splits(KinematicsError),
    /// A connection made where the two connectors do not mate.
    NotMated(Connection, KinematicsError),
    /// The turns collide, or open a loop, in lock-step too (the lock-step verdict).
    Turns(SweepVerdict),
    /// The turns could not be checked.
    Sweep(SweepError),
    /// A connection the configuration's rules refuse (a connector already in use).
    Refused(String),
    /// The configuration after the step is not valid.
    Invalid(Invalid),
}

impl fmt::Display for StepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StepError::ModulesDiffer { missing, added } => write!(
                f,
                "the modules change (missing: {missing:?}, added: {added:?}): a step only turns \
                 joints and makes or breaks connections"
            ),
            StepError::Nothing => write!(f, "nothing changes: a step is one action"),
            StepError::Splits(e) => write!(f, "after its disconnections, {e}"),
            StepError::NotMated(c, e) => write!(
                f,
                "module {} connector {} and module {} connector {} do not mate: {e}",
                c.from.0, c.from.1, c.to.0, c.to.1
            ),
            StepError::Turns(verdict @ SweepVerdict::Collides { fractions, .. })
                if fractions.len() == 1 =>
            {
                write!(f, "the turn {}", describe(verdict))
            }
            StepError::Turns(verdict) => write!(f, "the turns, {}", describe(verdict)),
            StepError::Sweep(e) => e.fmt(f),
            StepError::Refused(reason) => reason.fmt(f),
            StepError::Invalid(e) => write!(f, "after the step, {e}"),
        }
    }
}

/// A sweep verdict that is not clear, in words.
fn describe(verdict: &SweepVerdict) -> String {
    let at = |fractions: &[f64]| {
        let each: Vec<String> = fractions.iter().map(|f| format!("{f:.3}")).collect();
        each.join(", ")
    };
    match verdict {
        SweepVerdict::Clear => "are clear".to_string(),
        SweepVerdict::Collides {
            fractions,
            collision,
        } if fractions.len() == 1 => {
            let ((a, sa), (b, sb)) = collision.shoes;
            format!(
                "brings shoe {sa:?} of module {a} and shoe {sb:?} of module {b} within {:.3} \
                 (under 1) at {} of its motion",
                collision.distance,
                at(fractions)
            )
        }
        SweepVerdict::Collides {
            fractions,
            collision,
        } => {
            let ((a, sa), (b, sb)) = collision.shoes;
            format!(
                "even in lock-step, bring shoe {sa:?} of module {a} and shoe {sb:?} of module \
                 {b} within {:.3} (under 1) at fractions {} of their motions",
                collision.distance,
                at(fractions)
            )
        }
        SweepVerdict::OpensLoop {
            fractions,
            connection: c,
        } => format!(
            "even in lock-step, pull module {} connector {} away from module {} connector {} \
             (at fractions {}): a loop does not stay closed",
            c.from.0,
            c.from.1,
            c.to.0,
            c.to.1,
            at(fractions)
        ),
        SweepVerdict::Unproven { lower_bound, shoes } => format!(
            "could not be proven to keep shoe {:?} of module {} and shoe {:?} of module {} \
             one unit apart (proven {lower_bound:.4})",
            shoes.0 .1, shoes.0 .0, shoes.1 .1, shoes.1 .0
        ),
    }
}

/// Why a plan read from a file is refused: the configuration (its index from 0, and the line
/// where it starts in the file) that cannot be reached from the one before, or that is not
/// valid to start from.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanError {
    pub configuration: usize,
    pub line: usize,
    pub error: StepError,
}

impl fmt::Display for PlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (k, line) = (self.configuration, self.line);
        match (k, &self.error) {
            (0, StepError::Invalid(e)) => write!(f, "configuration 0 (line {line}): {e}"),
            _ => write!(
                f,
                "configuration {k} (line {line}), the step from configuration {}: {}",
                k.saturating_sub(1),
                self.error
            ),
        }
    }
}

impl std::error::Error for PlanError {}

/// The steps of a plan read from a file, each configuration with the line it starts at; the
/// error names the configuration and its line.
pub fn plan_steps_at(
    configurations: &[(usize, RofiConfiguration)],
) -> Result<Vec<Step>, PlanError> {
    let plain: Vec<RofiConfiguration> = configurations.iter().map(|(_, c)| c.clone()).collect();
    plan_steps(&plain).map_err(|(step, error)| {
        // A first configuration that is not valid is reported as step 0's, at configuration 0.
        let configuration = match (step, &error) {
            (0, StepError::Invalid(_)) if validate(&plain[0]).is_err() => 0,
            _ => step + 1,
        };
        let line = configurations
            .get(configuration)
            .map_or(0, |(line, _)| *line);
        PlanError {
            configuration,
            line,
            error,
        }
    })
}

/// The steps of a plan: one between each two consecutive configurations, the first of which
/// must be valid; the error names the step (0 is from configuration 0 to 1).
pub fn plan_steps(configurations: &[RofiConfiguration]) -> Result<Vec<Step>, (usize, StepError)> {
    if let Some(first) = configurations.first() {
        validate(first).map_err(|e| (0, StepError::Invalid(e)))?;
    }
    (configurations.windows(2).enumerate())
        .map(|(i, pair)| step_between(&pair[0], &pair[1]).map_err(|e| (i, e)))
        .collect()
}

/// The step from `before` (valid) to `after`.
pub fn step_between(
    before: &RofiConfiguration,
    after: &RofiConfiguration,
) -> Result<Step, StepError> {
    same_modules(before, after)?;
    let disconnects = only_in(before, after);
    let connects = only_in(after, before);
    let mut notes = Vec::new();
    let turns = turns_between(before, after, &mut notes);
    if disconnects.is_empty() && connects.is_empty() && turns.is_empty() {
        return Err(StepError::Nothing);
    }
    let released = without(before, &disconnects)?;
    poses(&released).map_err(StepError::Splits)?;
    let connected = with(&released, &connects)?;
    let (turns, together) = decide_turns(&connected, turns, &mut notes)?;
    validate(after).map_err(StepError::Invalid)?;
    Ok(Step {
        disconnects,
        connects,
        turns,
        together,
        notes,
    })
}

fn same_modules(before: &RofiConfiguration, after: &RofiConfiguration) -> Result<(), StepError> {
    let ids = |c: &RofiConfiguration| c.modules().map(|m| m.id).collect::<Vec<u32>>();
    let (a, b) = (ids(before), ids(after));
    if a == b {
        return Ok(());
    }
    let missing = a.iter().filter(|id| !b.contains(id)).copied().collect();
    let added = b.iter().filter(|id| !a.contains(id)).copied().collect();
    Err(StepError::ModulesDiffer { missing, added })
}

/// The connections of `one` that `other` does not have (the same ports and twist, seen
/// from either end, are the same connection).
fn only_in(one: &RofiConfiguration, other: &RofiConfiguration) -> Vec<Connection> {
    let has = |c: &Connection| (other.connections().iter()).any(|o| *o == *c || *o == c.reversed());
    one.connections()
        .iter()
        .filter(|c| !has(c))
        .copied()
        .collect()
}

/// `config` without `connections`.
fn without(
    config: &RofiConfiguration,
    connections: &[Connection],
) -> Result<RofiConfiguration, StepError> {
    let modules: Vec<_> = config.modules().copied().collect();
    let kept: Vec<Connection> = (config.connections().iter())
        .filter(|c| !connections.contains(c))
        .copied()
        .collect();
    RofiConfiguration::from_parts(&modules, &kept).map_err(|e| StepError::Refused(e.to_string()))
}

/// `config` with `connections` made one by one, each checked to mate.
fn with(
    config: &RofiConfiguration,
    connections: &[Connection],
) -> Result<RofiConfiguration, StepError> {
    let mut out = config.clone();
    for c in connections {
        out.connect(*c)
            .map_err(|e| StepError::Refused(e.to_string()))?;
        poses(&out).map_err(|e| StepError::NotMated(*c, e))?;
    }
    Ok(out)
}

/// The joint turns from `before` to `after`: alpha and beta by their difference, gamma the
/// short way round (a half turn, which has no direction in a file, is taken positive here and
/// reconsidered by `decide_turns`).
fn turns_between(
    before: &RofiConfiguration,
    after: &RofiConfiguration,
    notes: &mut Vec<String>,
) -> Vec<Turn> {
    let mut turns = Vec::new();
    for (a, b) in before.modules().zip(after.modules()) {
        for joint in Joint::ALL {
            let from = a.joint(joint);
            let by = match joint {
                Joint::Gamma => circular(b.joint(joint) - from),
                _ => b.joint(joint) - from,
            };
            if by.abs() < 1e-9 {
                continue;
            }
            if joint == Joint::Gamma && (by - 180.0).abs() < 1e-9 {
                notes.push(format!(
                    "module {}: gamma turns half round, a direction the file does not give",
                    a.id
                ));
            }
            turns.push(Turn {
                module: a.id,
                joint,
                from,
                by,
            });
        }
    }
    turns
}

/// How the turns may run: over every timing, else in lock-step; a half turn of gamma whose
/// positive direction collides is tried the other way round.
fn decide_turns(
    config: &RofiConfiguration,
    turns: Vec<Turn>,
    notes: &mut Vec<String>,
) -> Result<(Vec<Turn>, Together), StepError> {
    if turns.is_empty() {
        return Ok((turns, Together::Alone));
    }
    let first = timing_of(config, &turns);
    let half_turns: Vec<usize> = (0..turns.len())
        .filter(|&i| turns[i].joint == Joint::Gamma && (turns[i].by - 180.0).abs() < 1e-9)
        .collect();
    let Err(refusal) = first else {
        return first.map(|together| (turns, together));
    };
    if half_turns.is_empty() {
        return Err(refusal);
    }
    let mut other = turns.clone();
    for &i in &half_turns {
        other[i].by = -180.0;
    }
    let together = timing_of(config, &other).map_err(|_| refusal)?;
    notes.push("the half turns of gamma go the negative way: the positive way is refused".into());
    Ok((other, together))
}

/// `AnyTiming` when the turns are clear over every timing, `LockStep` when only in lock-step.
fn timing_of(config: &RofiConfiguration, turns: &[Turn]) -> Result<Together, StepError> {
    let check = |timing| sweep(config, turns, timing).map_err(StepError::Sweep);
    if check(Timing::Every)? == SweepVerdict::Clear {
        let alone = turns.len() < 2;
        return Ok(if alone {
            Together::Alone
        } else {
            Together::AnyTiming
        });
    }
    match check(Timing::LockStep)? {
        SweepVerdict::Clear => Ok(Together::LockStep),
        verdict => Err(StepError::Turns(verdict)),
    }
}
