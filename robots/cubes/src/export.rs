//! A sequence of cube moves as an MRWT scenario (`dynarole export scen`): its first
//! configuration as the module block (movable cubes in group 0, fixed ones in group 1, as the
//! pathfinder's writer groups them), one move set per parallel group. Each move is one line
//! as the importer reads it back (`decode.rs`); a monkey move's second line goes in a set of
//! its own after its group, which the importer folds back into the monkey.

use crate::decode::digit_of_anchor;
use crate::lattice::{Cell, Dir, Move};
use crate::robot::CubesRobot;
use crate::scen::{write_scen, Group, MoveLine, MoveSet, ScenModule, Scenario};
use dynarole_world::{Action, PlanToExport, RobotShape};

/// The display group of movable cubes and of fixed ones.
const MOVABLE_GROUP: i64 = 0;
const FIXED_GROUP: i64 = 1;

/// The plan as a scenario's text, or why it has none.
pub(crate) fn export_scen(plan: &PlanToExport<'_>) -> Result<String, String> {
    let robot =
        (plan.from.downcast_ref::<CubesRobot>()).ok_or("the configuration is not one of cubes")?;
    let mut sets = Vec::new();
    for group in plan.sets {
        let mut now = Vec::new();
        let mut second = Vec::new();
        for (module, action) in group {
            let id = id_of(robot, module)?;
            let mv = move_of(action)?;
            let mut lines = scen_lines(&mv).into_iter();
            if let Some((code, d)) = lines.next() {
                now.push(line(id, code, d));
            }
            second.extend(lines.map(|(code, d)| line(id, code, d)));
        }
        sets.push(set(now));
        if !second.is_empty() {
            sets.push(set(second));
        }
    }
    let scenario = Scenario {
        name: one_line(plan.title),
        description: one_line(plan.description),
        groups: groups(),
        modules: modules(robot),
        sets,
    };
    Ok(write_scen(&scenario))
}

/// A move's lines in a scenario: (anchor code, displacement), one, or two for a monkey (its
/// second step in the next set).
pub fn scen_lines(mv: &Move) -> Vec<(i64, Cell)> {
    let add = |a: Dir, b: Dir| -> Cell { std::array::from_fn(|k| a.vector()[k] + b.vector()[k]) };
    match *mv {
        Move::Slide { dir } => vec![(0, dir.vector())],
        Move::CornerSlide { first, second } => {
            // The first leg's axis, as a negative code (1 = x, 2 = y, 3 = z).
            vec![(-first.code().abs(), add(first, second))]
        }
        Move::Pivot { anchor, dir } => vec![(digit_of_anchor(anchor), dir.vector())],
        Move::Pivot180 { anchor, dir } => vec![(digit_of_anchor(anchor), add(dir, anchor))],
        Move::Monkey { anchor, dir } => {
            let step = (digit_of_anchor(anchor), dir.vector());
            vec![step, step]
        }
        Move::DiagonalMonkey { anchor, dir } => vec![
            (digit_of_anchor(anchor), dir.vector()),
            (digit_of_anchor(dir), anchor.reversed().vector()),
        ],
    }
}

fn id_of(robot: &CubesRobot, module: &str) -> Result<u32, String> {
    let m = robot
        .index(module)
        .ok_or_else(|| format!("no module is called \"{module}\""))?;
    robot.id(m).ok_or_else(|| format!("{module} has no ID"))
}

fn move_of(action: &Action) -> Result<Move, String> {
    match *action {
        Action::Move { operation, args } => Move::from_operation(operation, args),
        _ => Err("a cube's operations are its moves".to_string()),
    }
}

/// A line of a set (its `*` is the writer's: every set a checkpoint, as one statement group).
fn line(id: u32, code: i64, d: Cell) -> MoveLine {
    MoveLine {
        line: 0,
        starred: false,
        id,
        code,
        d,
    }
}

fn set(moves: Vec<MoveLine>) -> MoveSet {
    MoveSet {
        line: 0,
        checkpoint: true,
        moves,
    }
}

fn groups() -> Vec<Group> {
    let group = |id, colour| Group {
        line: 0,
        id,
        colour,
        size_percent: 90,
    };
    vec![
        group(MOVABLE_GROUP, [90, 140, 200]),
        group(FIXED_GROUP, [120, 120, 120]),
    ]
}

fn modules(robot: &CubesRobot) -> Vec<ScenModule> {
    (robot.cubes().iter())
        .map(|c| ScenModule {
            line: 0,
            id: c.id,
            group: if c.fixed { FIXED_GROUP } else { MOVABLE_GROUP },
            position: c.position,
        })
        .collect()
}

/// A header's text on one line.
fn one_line(text: &str) -> String {
    text.replace(['\n', '\r'], " ")
}
