//! A RoFI planner's plan as a dynarole program (`dynarole import`): each step between two
//! consecutive configurations becomes, in the order RoFI's planners execute a step, its
//! disconnections, then its connections, then its joint turns, each kind joined by `&` and
//! the kinds by `;`; turns proven safe only in lock-step become a synchronous group. Also the
//! one configuration `--from` and `--expect` take from a file of RoFI's formats.

use crate::formats::{read_plan, recognise, Format, FormatError};
use crate::module::{Connection, Joint, RofiConfiguration};
use crate::robot::{whole, RofiRobot};
use crate::steps::{plan_steps_at, Step, Together};
use crate::sweep::Turn;
use dynarole_world::{ConfigError, Configuration, ImportedPlan, Metadata, PlanError};
use std::collections::BTreeMap;

/// The speed, in percent of a joint's top speed, every imported turn is written with.
const IMPORTED_SPEED: u8 = 100;

/// The configuration of a file in one of RoFI's formats (`None` when it is in none): it must
/// hold exactly one.
pub(crate) fn read_native(text: &str) -> Option<Result<Configuration, ConfigError>> {
    let format = recognise(text)?;
    Some(one_configuration(text, format).map(Configuration::new))
}

fn one_configuration(text: &str, format: Format) -> Result<RofiRobot, ConfigError> {
    let plan = read_plan(text, format).map_err(|e| located(&e))?;
    let count = plan.indices.last().map_or(0, |k| k + 1);
    match (plan.configurations.first(), count) {
        (Some((_, config)), 1) => robot(config.clone(), format, "configuration"),
        (None, _) => Err(ConfigError::new(
            "document",
            "the file holds no configuration",
        )),
        _ => Err(ConfigError::new(
            "document",
            format!(
                "the file holds {count} configurations (a plan); give one, or read the plan \
                 with `dynarole import`"
            ),
        )),
    }
}

/// A reading error as a configuration error: the JSON path, else the line and column.
fn located(e: &FormatError) -> ConfigError {
    let path = e
        .path
        .clone()
        .unwrap_or_else(|| format!("line {}, column {}", e.line, e.column));
    ConfigError::new(path, e.message.clone())
}

fn robot(config: RofiConfiguration, format: Format, what: &str) -> Result<RofiRobot, ConfigError> {
    let metadata = Metadata {
        name: format!("RoFI {what}"),
        source: Some(format.name().to_string()),
        ..Metadata::default()
    };
    let robot = RofiRobot::new(config, &BTreeMap::new(), metadata)?;
    Ok(match format.names_modules() {
        true => robot,
        false => robot.anonymous(),
    })
}

/// The plan of a file in one of RoFI's formats as a program with one sequence, `sequence`.
pub(crate) fn import_plan(text: &str, sequence: &str) -> Option<Result<ImportedPlan, PlanError>> {
    let format = recognise(text)?;
    Some(import(text, format, sequence))
}

fn import(text: &str, format: Format, sequence: &str) -> Result<ImportedPlan, PlanError> {
    let read = read_plan(text, format).map_err(|e| PlanError {
        line: e.line,
        column: e.column,
        message: e.to_string(),
    })?;
    let (plan, indices) = (read.configurations, read.indices);
    let count = indices.last().map_or(0, |k| k + 1);
    let at = |k: usize, message: String| PlanError {
        line: plan.get(k).map_or(1, |(line, _)| *line),
        column: 1,
        message,
    };
    if count < 2 {
        let n = count;
        return Err(at(
            0,
            format!("a plan needs two configurations or more; this holds {n}"),
        ));
    }
    let steps = plan_steps_at(&plan).map_err(|e| {
        // Named as the file numbers its configurations.
        let configuration = indices
            .get(e.configuration)
            .copied()
            .unwrap_or(e.configuration);
        PlanError {
            line: e.line.max(1),
            column: 1,
            message: crate::steps::PlanError { configuration, ..e }.to_string(),
        }
    })?;
    let ends = [
        (0, "first configuration"),
        (plan.len() - 1, "last configuration"),
    ];
    let [from, expect] = ends.map(|(k, what)| {
        let index = indices[k];
        robot(plan[k].1.clone(), format, what)
            .map_err(|e| at(k, format!("configuration {index}: {}", e.message)))
    });
    let (from, expect) = (from?, expect?);
    let lines: Vec<String> = (steps.iter().enumerate())
        .map(|(k, step)| step_line(k, step, plan[k + 1].0))
        .collect();
    Ok(ImportedPlan {
        format: format.name(),
        program: program(sequence, format, &steps, &plan, &indices),
        from: Configuration::new(from),
        expect: Configuration::new(expect),
        steps: lines,
    })
}

/// The program's text: a header saying what it was imported from, then the sequence with
/// each step's statements after a comment naming the step.
fn program(
    sequence: &str,
    format: Format,
    steps: &[Step],
    plan: &[(usize, RofiConfiguration)],
    indices: &[usize],
) -> String {
    let mut out = format!(
        "// Imported from a RoFI plan ({}): {} configurations, {} steps. Each step runs its\n\
         // disconnections, then its connections, then its turns, as RoFI's planners do.\n\
         robot rofi;\n\nsequence {sequence} {{\n",
        format.name(),
        indices.last().map_or(0, |k| k + 1),
        steps.len()
    );
    for (k, step) in steps.iter().enumerate() {
        let line = plan[k + 1].0;
        let (a, b) = (indices[k], indices[k + 1]);
        let what = match a == b {
            true => format!("the connections the turn to configuration {b} makes"),
            false => format!("configuration {a} to {b}"),
        };
        out.push_str(&format!("    // step {}: {what} (line {line})\n", k + 1));
        for note in &step.notes {
            out.push_str(&format!("    // {}\n", one_line(note)));
        }
        for group in statements(step) {
            out.push_str(&format!("    {group}\n"));
        }
    }
    out.push_str("}\n");
    out
}

/// A note kept on one comment line.
fn one_line(text: &str) -> String {
    text.replace(['\n', '\r'], " ")
}

/// A step's statement groups, each ending in `;`.
fn statements(step: &Step) -> Vec<String> {
    let mut groups = Vec::new();
    let connections = |list: &[Connection], op: &str| {
        let each: Vec<String> = list.iter().map(|c| connector_statement(c, op)).collect();
        each
    };
    for each in [
        connections(&step.disconnects, "disconnect"),
        connections(&step.connects, "connect"),
    ] {
        if !each.is_empty() {
            groups.push(format!("{};", each.join(" & ")));
        }
    }
    let turns: Vec<String> = step.turns.iter().map(turn_statement).collect();
    match (turns.len(), step.together) {
        (0, _) => {}
        (_, Together::LockStep) if turns.len() > 1 => {
            groups.push(format!("sync {{ {}; }};", turns.join(" & ")));
        }
        _ => groups.push(format!("{};", turns.join(" & "))),
    }
    groups
}

/// `M3.Connector[$CONNECTOR_4].connect();` from the connection's lower end (ID, connector).
fn connector_statement(c: &Connection, op: &str) -> String {
    let (id, connector) = if c.to < c.from { c.to } else { c.from };
    format!("M{id}.Connector[$CONNECTOR_{}].{op}()", connector.index())
}

/// `M2.Joint[$GAMMA].rotateFromToBy(0, 90, true, 100)`.
fn turn_statement(turn: &Turn) -> String {
    let from = whole(turn.from);
    let to = match turn.joint {
        Joint::Gamma => whole(crate::module::circular(turn.from + turn.by)),
        _ => whole(turn.from + turn.by),
    };
    let joint = match turn.joint {
        Joint::Alpha => "ALPHA",
        Joint::Beta => "BETA",
        Joint::Gamma => "GAMMA",
    };
    format!(
        "M{}.Joint[${joint}].rotateFromToBy({from}, {to}, {}, {IMPORTED_SPEED})",
        turn.module,
        turn.by > 0.0
    )
}

/// One line of the printed steps: what step k does.
fn step_line(k: usize, step: &Step, line: usize) -> String {
    let kind = match step.together {
        Together::Alone => "",
        Together::AnyTiming => ", turns safe at any timing (&)",
        Together::LockStep => ", turns safe only in lock-step (sync)",
    };
    format!(
        "step {} (line {line}): {} disconnect(s), {} connect(s), {} turn(s){kind}",
        k + 1,
        step.disconnects.len(),
        step.connects.len(),
        step.turns.len()
    )
}
