//! `dynarole parallelise`: a sequence written in order becomes the most parallel sequence
//! that is provably safe on the model, printed as a complete `.dr` file with its makespan
//! (the critical path with the robot's default timing preset, which the printed line calls
//! the simulator's, as it always has) before and after.

use crate::load::{self, Failure};
use crate::world::{prepare, read_configuration};
use dynarole_codegen::{GroupRun, Protocol};
use dynarole_core::driver::Shape;
use dynarole_core::RobotApi;
use dynarole_replay::{parallelise, Form, FormKind, ParalleliseError, Parallelised, Request};
use dynarole_sim::{choose_form, makespan, Estimated};
use std::fmt::Write;
use std::process::ExitCode;

/// What `parallelise` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct ParalleliseArgs {
    /// The source file (.dr) holding the sequence.
    pub file: std::path::PathBuf,
    /// The sequence to parallelise.
    #[arg(long, value_name = "NAME")]
    pub sequence: String,
    /// The configuration it starts from (JSON).
    #[arg(long, value_name = "CONFIG")]
    pub from: std::path::PathBuf,
    /// Name of the new sequence (default: SEQUENCE_parallel).
    #[arg(long)]
    pub name: Option<String>,
    /// Write the file here instead of printing it.
    #[arg(short = 'o', long = "output", value_name = "OUT.dr")]
    pub out: Option<std::path::PathBuf>,
    /// `paper`: parallel groups only (no blocks), what the paper's protocol can run.
    #[arg(long, value_parser = crate::compile::choice::<dynarole_codegen::Protocol>(), default_value_t = dynarole_codegen::Protocol::Lattice)]
    pub protocol: dynarole_codegen::Protocol,
    /// Check only statements at most N apart in the input; farther ones stay ordered
    /// (faster on long sequences, less parallel). Default: every pair.
    #[arg(long, value_name = "N")]
    pub window: Option<usize>,
    #[command(flatten)]
    pub plugins: crate::load::PluginArgs,
}

/// What `parallelise` found: the file it writes, the sequence's statements and groups, and
/// the critical path (with the robot's default timing preset) before and after.
pub struct Found {
    pub text: String,
    pub name: String,
    pub statements: usize,
    pub groups: usize,
    pub before: Result<u64, String>,
    pub after: Result<u64, String>,
}

pub fn run(args: &ParalleliseArgs) -> Result<ExitCode, Failure> {
    let found = found(args)?;
    match &args.out {
        Some(path) => std::fs::write(path, &found.text)
            .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))?,
        None => print!("{}", found.text),
    }
    eprintln!(
        "{}: {} statements, {} groups; critical path {} before, {} after",
        args.sequence,
        found.statements,
        found.groups,
        seconds(&found.before),
        seconds(&found.after)
    );
    Ok(ExitCode::SUCCESS)
}

/// The parallel form of `args.sequence`, or why there is none (a sequence that does not replay
/// is `Failure::Checked`, concluded by why it cannot be parallelised).
pub fn found(args: &ParalleliseArgs) -> Result<Found, Failure> {
    let name = args
        .name
        .as_deref()
        .map_or_else(|| format!("{}_parallel", args.sequence), str::to_string);
    if !dynarole_core::lexer::is_identifier(&name) {
        return Err(Failure::Usage(format!(
            "--name `{name}` is not a sequence name (a letter or `_`, then letters, digits or `_`; not a keyword)"
        )));
    }
    if args.protocol.groups() == GroupRun::OneAtATime {
        let parallel = Protocol::names_where(|p| p.groups != GroupRun::OneAtATime);
        return Err(Failure::Usage(format!(
            "--protocol takes `{}` here: the {} runs one statement at a time",
            parallel.join("` or `"),
            args.protocol.info().description
        )));
    }
    load::with_program(&args.file, &args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let start = read_configuration(&args.from)?;
        let sequences = [args.sequence.to_string()];
        let prepared = match prepare(program, &display, &sequences, start)? {
            Ok(prepared) => prepared,
            Err(errors) => return Err(Failure::checked(&display, source, errors)),
        };
        let request = Request {
            program,
            sequence: &args.sequence,
            world: prepared.world.clone(),
            assignment: &prepared.assignment,
            name: &name,
            blocks: args.protocol.shape() != Shape::Flat,
            one_module_overlap: args.protocol.groups() == GroupRun::Overlapping,
            window: args.window,
        };
        let found = match parallelise(&request) {
            Ok(found) => found,
            Err(ParalleliseError::Input(diagnostics)) => {
                return Err(
                    Failure::checked(&display, source, diagnostics).concluded(format!(
                    "`{}` does not replay from {}; only a sequence that does can be parallelised",
                    args.sequence,
                    args.from.display()
                )),
                )
            }
            Err(ParalleliseError::Message(m)) => return Err(Failure::Input(m)),
        };
        let before = makespan(program, &prepared.plans, args.protocol);
        chosen(args, name, &found, before, &program.robot)
    })
}

/// The form the estimates choose, with its summary.
fn chosen(
    args: &ParalleliseArgs,
    name: String,
    found: &Parallelised,
    before: Result<u64, String>,
    robot: &RobotApi,
) -> Result<Found, Failure> {
    let Estimated {
        mut estimates,
        chosen,
    } = choose_form(found, &name, args.protocol, robot);
    let form = found
        .forms
        .get(chosen)
        .ok_or_else(|| Failure::Input("nothing to write".into()))?;
    let summary = Summary {
        args,
        found,
        form,
        before: &before,
        after: &estimates[chosen],
        others: found
            .forms
            .iter()
            .zip(&estimates)
            .enumerate()
            .filter(|(k, _)| *k != chosen)
            .map(|(_, pair)| pair)
            .collect(),
    };
    let text = format!("{}{}\n{}", summary.comments(), found.header, form.text);
    Ok(Found {
        text,
        name,
        statements: found.statements.len(),
        groups: form.groups,
        before,
        after: estimates.swap_remove(chosen),
    })
}

/// The comment block at the top of the output.
struct Summary<'a> {
    args: &'a ParalleliseArgs,
    found: &'a Parallelised,
    form: &'a Form,
    before: &'a Result<u64, String>,
    after: &'a Result<u64, String>,
    others: Vec<(&'a Form, &'a Result<u64, String>)>,
}

impl Summary<'_> {
    fn comments(&self) -> String {
        let file = self.args.file.file_name().map_or_else(
            || self.args.file.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        );
        let from = self.args.from.file_name().map_or_else(
            || self.args.from.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        );
        let mut out = String::new();
        let _ = writeln!(
            out,
            "// `{}` of {file}, parallelised on {from} by `dynarole parallelise`.",
            self.args.sequence
        );
        let _ = writeln!(
            out,
            "// {} statements in {} groups; {} dependency edges after transitive reduction.",
            self.found.statements.len(),
            self.form.groups,
            self.found.edges.len()
        );
        let _ = writeln!(
            out,
            "// Critical path with the simulator's timing preset: {} before, {} after.",
            seconds(self.before),
            seconds(self.after)
        );
        let _ = writeln!(out, "// {}", describe_form(self.form.kind));
        if let Some(window) = self.args.window {
            let _ = writeln!(
                out,
                "// Only statements at most {window} apart in the input were checked; farther ones stay ordered."
            );
        }
        for (form, estimate) in &self.others {
            let _ = writeln!(
                out,
                "// Not chosen: {} ({}).",
                short_name(form.kind),
                seconds(estimate)
            );
        }
        for note in &self.found.notes {
            let _ = writeln!(out, "// Note: {note}.");
        }
        out.push_str("// Every `&` below was checked on the model, forwards and in the reverse.\n");
        out
    }
}

fn describe_form(kind: FormKind) -> &'static str {
    match kind {
        FormKind::Levels => "Written as parallel groups: a statement waits for the whole group before it, not only for the statements it depends on.",
        FormKind::Blocks => "Written with blocks: chains that depend on each other only at their ends run side by side; where the graph is not series-parallel, more is ordered than needed.",
        FormKind::Sequential => "Written in the input order: no parallel form could be verified.",
        FormKind::AsWritten => "Written as the input groups it: its own `&` verify, and no form found here is shorter.",
    }
}

fn short_name(kind: FormKind) -> &'static str {
    match kind {
        FormKind::Levels => "parallel groups",
        FormKind::Blocks => "blocks",
        FormKind::Sequential => "the input order",
        FormKind::AsWritten => "the input's own groups",
    }
}

fn seconds(estimate: &Result<u64, String>) -> String {
    match estimate {
        Ok(ms) => format!("{:.2} s", *ms as f64 / 1000.0),
        Err(reason) => format!("not estimated ({reason})"),
    }
}
