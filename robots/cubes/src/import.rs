//! An MRWT scenario as a dynarole program (`dynarole import`): its modules are the first
//! configuration (each `M<id>`), each move set an `&` group of its modules' moves (checked
//! line by line by the move rules and set by set by the parallel-move rules, `decode.rs`),
//! the sets in order joined by `;`; the last configuration is where the moves end. Also the
//! one configuration `--from` takes from a scenario without moves.

use crate::decode::{decode_sets, LineMove, PlannedMove};
use crate::lattice::{Dir, Lattice, Move};
use crate::robot::{Cube, CubesRobot};
use crate::scen::{looks_like_scen, read_scen, ScenError, Scenario};
use dynarole_world::{ConfigError, Configuration, ImportedPlan, Metadata, PlanError};
use std::collections::BTreeMap;

/// The format's name in messages.
const FORMAT: &str = "MRWT scenario";

/// The configuration of a scenario (`None` when the text is none): one without move sets.
pub(crate) fn read_native(text: &str) -> Option<Result<Configuration, ConfigError>> {
    if !looks_like_scen(text) {
        return None;
    }
    Some(one_configuration(text).map(Configuration::new))
}

fn one_configuration(text: &str) -> Result<CubesRobot, ConfigError> {
    let scenario = read_scen(text).map_err(|e| {
        let at = format!("line {}, column {}", e.line, e.column);
        ConfigError::new(at, e.message)
    })?;
    if !scenario.sets.is_empty() {
        let message = format!(
            "the scenario holds {} move sets (a plan); give a configuration, or read the plan \
             with `dynarole import`",
            scenario.sets.len()
        );
        return Err(ConfigError::new("document", message));
    }
    let (robot, _) = start(&scenario, "configuration", &[]).map_err(|e| {
        let at = format!("line {}, column {}", e.line, e.column);
        ConfigError::new(at, e.message)
    })?;
    Ok(robot)
}

/// The plan of a scenario as a program with one sequence, `sequence`.
pub(crate) fn import_plan(
    text: &str,
    sequence: &str,
    ground: &[i64],
) -> Option<Result<ImportedPlan, PlanError>> {
    if !looks_like_scen(text) {
        return None;
    }
    Some(import(text, sequence, ground))
}

fn import(text: &str, sequence: &str, ground: &[i64]) -> Result<ImportedPlan, PlanError> {
    let scenario = read_scen(text).map_err(plan_error)?;
    check_ground(&scenario, ground)?;
    let (from, by_id) = start(&scenario, "first configuration", ground)?;
    let sets = line_moves(&scenario, &by_id);
    let name = |m: usize| from.cubes().get(m).map_or("?".into(), |c| c.name.clone());
    let (planned, end) =
        decode_sets(from.lattice().clone(), &sets, &name).map_err(|e| PlanError {
            line: e.line,
            column: 1,
            message: e.message,
        })?;
    let expect = ended(&from, end, &scenario);
    let steps = (planned.iter().enumerate())
        .map(|(k, set)| step_line(k, set))
        .collect();
    Ok(ImportedPlan {
        format: FORMAT,
        program: program(sequence, &scenario, &planned, &from),
        from: Configuration::new(from),
        expect: Configuration::new(expect),
        steps,
    })
}

fn plan_error(e: ScenError) -> PlanError {
    PlanError {
        line: e.line,
        column: e.column,
        message: e.message,
    }
}

/// The scenario's modules as a configuration (`what` names it in messages), with each
/// module's index by ID.
fn start(
    scenario: &Scenario,
    what: &str,
    ground: &[i64],
) -> Result<(CubesRobot, BTreeMap<u32, usize>), PlanError> {
    let mut by_id = BTreeMap::new();
    let mut at_cell = BTreeMap::new();
    for (m, module) in scenario.modules.iter().enumerate() {
        by_id.insert(module.id, m);
        if let Some(other) = at_cell.insert(module.position, module.id) {
            let [x, y, z] = module.position;
            return Err(PlanError {
                line: module.line,
                column: 1,
                message: format!(
                    "modules {other} and {} are both at ({x}, {y}, {z})",
                    module.id
                ),
            });
        }
    }
    let cubes = (scenario.modules.iter())
        .map(|m| Cube {
            name: format!("M{}", m.id),
            id: m.id,
            position: m.position,
            fixed: ground.contains(&m.group),
        })
        .collect();
    let metadata = Metadata {
        name: format!("{} ({what})", one_line(&scenario.name)),
        source: Some(format!("{FORMAT}: {}", one_line(&scenario.description))),
        ..Metadata::default()
    };
    let first_line = scenario.modules.first().map_or(1, |m| m.line);
    let robot = CubesRobot::new(cubes, metadata).map_err(|e| PlanError {
        line: first_line,
        column: 1,
        message: format!("the scenario's modules: {}", e.message),
    })?;
    Ok((robot, by_id))
}

/// Every ground group is one of the scenario's groups.
fn check_ground(scenario: &Scenario, ground: &[i64]) -> Result<(), PlanError> {
    let declared = |g: &i64| scenario.groups.iter().any(|group| group.id == *g);
    match ground.iter().find(|g| !declared(g)) {
        None => Ok(()),
        Some(g) => {
            let ids: Vec<String> = scenario.groups.iter().map(|g| g.id.to_string()).collect();
            Err(PlanError {
                line: scenario.groups.first().map_or(1, |g| g.line),
                column: 1,
                message: format!(
                    "no group {g} to hold as the ground; the scenario's groups are {}",
                    ids.join(", ")
                ),
            })
        }
    }
}

/// The move sets' lines with modules by index (the reader refused unknown IDs).
fn line_moves(scenario: &Scenario, by_id: &BTreeMap<u32, usize>) -> Vec<Vec<LineMove>> {
    (scenario.sets.iter())
        .map(|set| {
            (set.moves.iter())
                .filter_map(|line| {
                    Some(LineMove {
                        line: line.line,
                        module: *by_id.get(&line.id)?,
                        code: line.code,
                        d: line.d,
                    })
                })
                .collect()
        })
        .collect()
}

/// The configuration the moves end in.
fn ended(from: &CubesRobot, end: Lattice, scenario: &Scenario) -> CubesRobot {
    let mut robot = from.with_lattice(end);
    robot.rename(format!("{} (last configuration)", one_line(&scenario.name)));
    robot
}

/// The program's text: a header saying what it was imported from, then the sequence, one
/// move set per line.
fn program(
    sequence: &str,
    scenario: &Scenario,
    sets: &[Vec<PlannedMove>],
    from: &CubesRobot,
) -> String {
    let mut out = format!(
        "// Imported from an {FORMAT} ({}): {} modules, {} move sets. Each set's moves are\n\
         // made at the same time (`&`), the sets one after another.\n\
         robot cubes;\n\nsequence {sequence} {{\n",
        one_line(&scenario.name),
        scenario.modules.len(),
        sets.len()
    );
    for (k, set) in sets.iter().enumerate() {
        let line = set.first().map_or(0, |m| m.line);
        out.push_str(&format!("    // set {} (line {line})\n", k + 1));
        let each: Vec<String> = set.iter().map(|m| statement(m, from)).collect();
        out.push_str(&format!("    {};\n", each.join(" & ")));
    }
    out.push_str("}\n");
    out
}

/// `M3.Cube.pivot($MINUS_Z, $PLUS_X)`.
fn statement(planned: &PlannedMove, from: &CubesRobot) -> String {
    let name = from
        .cubes()
        .get(planned.module)
        .map_or("?", |c| c.name.as_str());
    let (operation, args) = planned.mv.operation();
    let op = Move::NAMES
        .get(usize::from(operation))
        .copied()
        .unwrap_or("?");
    let arity = arity(&planned.mv);
    let words: Vec<String> = args[..arity].iter().map(|a| direction(*a)).collect();
    format!("{name}.Cube.{op}({})", words.join(", "))
}

/// How many arguments a move takes.
fn arity(mv: &Move) -> usize {
    match mv {
        Move::Slide { .. } => 1,
        _ => 2,
    }
}

/// A direction's value name (`$PLUS_X`), as the plugin's `[values]` call them.
fn direction(code: i64) -> String {
    let Some(dir) = Dir::from_code(code) else {
        return code.to_string();
    };
    let sign = if dir.code() > 0 { "PLUS" } else { "MINUS" };
    let axis = ["X", "Y", "Z"][(dir.code().unsigned_abs() as usize).saturating_sub(1) % 3];
    format!("${sign}_{axis}")
}

/// One line of the printed steps: what set k does.
fn step_line(k: usize, set: &[PlannedMove]) -> String {
    let line = set.first().map_or(0, |m| m.line);
    let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
    for m in set {
        *kinds.entry(m.mv.name()).or_default() += 1;
    }
    let counts: Vec<String> = kinds.iter().map(|(k, n)| format!("{n} {k}")).collect();
    format!("set {} (line {line}): {}", k + 1, counts.join(", "))
}

/// A header's text kept on one comment line.
fn one_line(text: &str) -> String {
    text.replace(['\n', '\r'], " ")
}
