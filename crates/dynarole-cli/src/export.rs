//! `dynarole export FORMAT`: a sequence written in a format of its robot's own tools (the
//! cube planners' `.scen`), one set per parallel group, after it replays on the model from
//! the configuration given (a plan the model refuses is not written).

use crate::load::{self, Failure};
use crate::world::read_configuration;
use dynarole_core::ast::SeparatorKind;
use dynarole_core::expand::{Plan, PlanKind};
use dynarole_core::Program;
use dynarole_replay::Prepared;
use dynarole_world::{Action, PlanToExport};
use std::path::PathBuf;
use std::process::ExitCode;

/// What `export` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct ExportArgs {
    /// The format to write, one of those the program's robot writes (its folder lists them).
    pub format: String,
    /// The `.dr` file holding the sequence.
    pub file: PathBuf,
    #[command(flatten)]
    pub run: crate::world::RunArgs,
    /// Where to write the plan.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub out: PathBuf,
    #[command(flatten)]
    pub plugins: crate::load::PluginArgs,
}

pub fn run(args: &ExportArgs) -> Result<ExitCode, Failure> {
    load::with_program(&args.file, &args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let kind = (crate::robots::robots().get(&program.robot.name))
            .ok_or_else(|| Failure::Internal(format!("no robot kind {}", program.robot.name)))?;
        if !kind.export_formats().contains(&args.format.as_str()) {
            return Err(unknown_format(
                &args.format,
                &program.robot.name,
                kind.export_formats(),
            ));
        }
        let start = read_configuration(&args.run.from)?;
        let run = (program, source, display.as_str());
        let what = ("the sequence", "; nothing written");
        let (prepared, _) =
            match crate::replay::replayed_whole(run, &args.run.sequences, start, what)? {
                Ok(done) => done,
                Err(code) => return Ok(code),
            };
        let sets = sets(program, &prepared).map_err(Failure::Input)?;
        let title = prepared.names.join(", ");
        let description = format!("exported by dynarole from {display}");
        let plan = PlanToExport {
            title: &title,
            description: &description,
            from: &prepared.start,
            sets: &sets,
        };
        let text = match kind.export_plan(&args.format, &plan) {
            Some(Ok(text)) => text,
            Some(Err(why)) => return Err(Failure::Input(format!("{display}: {why}"))),
            None => return Err(unknown_format(&args.format, &program.robot.name, &[])),
        };
        if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| Failure::Input(format!("cannot make {}: {e}", dir.display())))?;
        }
        std::fs::write(&args.out, text)
            .map_err(|e| Failure::Input(format!("cannot write {}: {e}", args.out.display())))?;
        println!("{} sets written to {}", sets.len(), args.out.display());
        Ok(ExitCode::SUCCESS)
    })
}

fn unknown_format(format: &str, robot: &str, formats: &[&str]) -> Failure {
    let known = if formats.is_empty() {
        "it writes none".to_string()
    } else {
        format!("it writes {}", formats.join(", "))
    };
    Failure::Usage(format!(
        "robot {robot} has no export format `{format}`; {known}"
    ))
}

/// The sequences' parallel groups in order, each its modules' actions: a block is spliced
/// where it keeps its meaning (alone in its group, or itself one group).
fn sets(program: &Program, prepared: &Prepared) -> Result<Vec<Vec<(String, Action)>>, String> {
    let mut sets = vec![Vec::new()];
    for plan in &prepared.plans {
        add_plan(program, prepared, plan, &mut sets, true)?;
        close(&mut sets);
    }
    sets.retain(|set| !set.is_empty());
    Ok(sets)
}

/// Ends the set being filled.
fn close(sets: &mut Vec<Vec<(String, Action)>>) {
    if sets.last().is_some_and(|set| !set.is_empty()) {
        sets.push(Vec::new());
    }
}

fn add_plan(
    program: &Program,
    prepared: &Prepared,
    plan: &Plan,
    sets: &mut Vec<Vec<(String, Action)>>,
    closing: bool,
) -> Result<(), String> {
    let groups = plan
        .elements
        .split_inclusive(|e| e.separator == SeparatorKind::Sequential);
    for group in groups {
        let alone = group.len() == 1;
        for element in group {
            match &element.kind {
                PlanKind::Op(statement) => {
                    let module = (prepared.assignment.get(&statement.label)).ok_or_else(|| {
                        format!("no module for {}", statement.describe(&program.robot))
                    })?;
                    let action =
                        dynarole_replay::action(&program.robot, statement).ok_or_else(|| {
                            format!(
                                "`{}` is no operation the robot's model does",
                                statement.describe(&program.robot)
                            )
                        })?;
                    if let Some(set) = sets.last_mut() {
                        set.push((module.clone(), action));
                    }
                }
                // Alone in its group, its own groups are sets; one group, it joins this one.
                PlanKind::Block(inner) if alone => add_plan(program, prepared, inner, sets, true)?,
                PlanKind::Block(inner) if one_group(inner) => {
                    add_plan(program, prepared, inner, sets, false)?;
                }
                PlanKind::Block(_) => {
                    return Err("a block with steps in order runs beside other statements: it has no form as sets of moves made at the same time".into());
                }
            }
        }
        if closing {
            close(sets);
        }
    }
    Ok(())
}

/// Whether a block is one parallel group (its statements all joined by `&`, no inner steps).
fn one_group(plan: &Plan) -> bool {
    let last = plan.elements.len().saturating_sub(1);
    (plan.elements.iter().enumerate()).all(|(k, e)| {
        matches!(e.kind, PlanKind::Op(_)) && (k == last || e.separator == SeparatorKind::Parallel)
    })
}
