//! `dynarole import`: a planner's plan (a list of configurations in the planner's own format,
//! recognised from the content by the robot whose planners write it) becomes a program with
//! one sequence, its first and last configurations; the sequence is then replayed on the
//! model to its last configuration, and its steps and critical path are printed.

use crate::load::{self, Failure};
use dynarole_codegen::Protocol;
use dynarole_world::{compare_with_expected, Configuration, ImportedPlan};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// What `import` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct ImportArgs {
    /// The plan, in a format of a robot's planners (docs/robots.md lists them), recognised
    /// from its content.
    pub file: PathBuf,
    /// The directory to write `STEM.dr`, `STEM.from.json` and `STEM.expect.json` into (made
    /// when missing); STEM is the plan's file name without its extension.
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub out: PathBuf,
    /// A group of the plan's modules that is a fixed ground, never moving (a cube
    /// scenario's static modules); repeat for several.
    #[arg(long = "ground", value_name = "GROUP", allow_hyphen_values = true)]
    pub ground: Vec<i64>,
}

pub fn run(args: &ImportArgs) -> Result<ExitCode, Failure> {
    let text = load::read_source(&args.file)?;
    let stem = stem_of(&args.file)?;
    let sequence = sequence_name(&stem);
    let display = args.file.display().to_string();
    let options = dynarole_world::ImportOptions {
        ground: args.ground.clone(),
    };
    let plan = match crate::robots::robots().import_plan(&text, &sequence, &options) {
        Some(Ok(plan)) => plan,
        Some(Err(e)) => {
            return Err(Failure::Input(format!(
                "{display}:{}:{}: {}",
                e.line, e.column, e.message
            )))
        }
        None => {
            let formats = crate::robots::robots().plan_formats().join("; ");
            return Err(Failure::Input(format!(
                "{display}: not a plan any robot's planners write (expected {formats})"
            )));
        }
    };
    let written = write_files(&args.out, &stem, &plan)?;
    println!(
        "imported {display} ({}): sequence `{sequence}`, {} steps",
        plan.format,
        plan.steps.len()
    );
    for line in &plan.steps {
        println!("  {line}");
    }
    for path in &written {
        println!("wrote {}", path.display());
    }
    replay_to_the_end(&written[0], &sequence, &plan)
}

/// The plan's file name without its extension.
fn stem_of(path: &Path) -> Result<String, Failure> {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .ok_or_else(|| Failure::Usage(format!("{}: no file name", path.display())))
}

/// The stem made a sequence name: every character that cannot be in one becomes `_`, one
/// that cannot start one is preceded by `plan_`, and a keyword is followed by `_plan`.
pub fn sequence_name(stem: &str) -> String {
    let mut name: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if !name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        name = format!("plan_{name}");
    }
    if !dynarole_core::lexer::is_identifier(&name) {
        name.push_str("_plan");
    }
    name
}

/// Writes the program and the two configurations; the program's path comes first.
fn write_files(dir: &Path, stem: &str, plan: &ImportedPlan) -> Result<Vec<PathBuf>, Failure> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Failure::Input(format!("cannot make {}: {e}", dir.display())))?;
    let files = [
        (format!("{stem}.dr"), plan.program.clone()),
        (format!("{stem}.from.json"), plan.from.to_json_string()),
        (format!("{stem}.expect.json"), plan.expect.to_json_string()),
    ];
    let mut written = Vec::new();
    for (name, text) in files {
        let path = dir.join(name);
        std::fs::write(&path, text)
            .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))?;
        written.push(path);
    }
    Ok(written)
}

/// Replays the imported sequence on the model: it must reach the plan's last configuration.
/// Prints the critical path (the robot's default timing, the lattice protocol).
fn replay_to_the_end(
    program_path: &Path,
    sequence: &str,
    plan: &ImportedPlan,
) -> Result<ExitCode, Failure> {
    let plugins = crate::load::PluginArgs::default();
    load::with_program(program_path, &plugins, |program, source| {
        let display = program_path.display().to_string();
        let sequences = [sequence.to_string()];
        let run = (program, source, display.as_str());
        let what = ("the imported sequence", "");
        let (prepared, result) =
            match crate::replay::replayed_whole(run, &sequences, plan.from.clone(), what)? {
                Ok(done) => done,
                Err(code) => return Ok(code),
            };
        let reached: Option<Configuration> = result.final_world.configuration();
        let difference = reached.and_then(|r| compare_with_expected(&r, &plan.expect).err());
        if let Some(difference) = difference {
            eprintln!(
                "error: the imported sequence does not reach the plan's last configuration:\n{difference}"
            );
            return Ok(ExitCode::from(1));
        }
        println!("replays to the plan's last configuration");
        match dynarole_sim::makespan(program, &prepared.plans, Protocol::Lattice) {
            Ok(ms) => println!(
                "critical path: {:.3} s (the robot's default timing)",
                ms as f64 / 1000.0
            ),
            Err(e) => return Err(Failure::Internal(format!("the critical path: {e}"))),
        }
        Ok(ExitCode::SUCCESS)
    })
}
