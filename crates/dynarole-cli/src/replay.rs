//! `dynarole replay`: run sequences on the kinematic model, with no network, and compare the
//! result with the expected configuration.

use crate::load::{self, Failure};
use crate::render;
use crate::world::{prepare, read_configuration};
use dynarole_world::{compare_with_expected, Configuration};
use std::path::Path;
use std::process::ExitCode;

/// What `replay` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct ReplayArgs {
    /// The `.dr` file holding the sequences.
    pub file: std::path::PathBuf,
    #[command(flatten)]
    pub run: crate::world::RunArgs,
    /// Write the final configuration (JSON) here.
    #[arg(long, value_name = "CONFIG")]
    pub out: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub record: crate::view::RecordArgs,
    #[command(flatten)]
    pub plugins: crate::load::PluginArgs,
}

/// What a replay found: the prepared sequences, the model's run, its diagnostics (errors for
/// refused statements, warnings), the final configuration and, with `--expect`, how it
/// compares (`Err` holds the difference).
pub struct Replayed {
    pub prepared: crate::world::Prepared,
    pub result: dynarole_replay::Replay,
    pub diagnostics: Vec<dynarole_core::Diagnostic>,
    pub final_configuration: Configuration,
    pub expected: Option<(Configuration, Result<(), dynarole_world::Difference>)>,
}

pub fn run(args: &ReplayArgs) -> Result<ExitCode, Failure> {
    load::with_program(&args.file, &args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let found = replayed_on(args, program, source)?;
        render::diagnostics(&display, source, &found.diagnostics);
        let result = &found.result;
        let warnings = found.diagnostics.len() - result.n_rejected;
        println!(
            "replayed {} from {}: {} statements, {} rejected, {warnings} warning{}",
            found.prepared.names.join(", "),
            args.run.from.display(),
            result.n_statements,
            result.n_rejected,
            if warnings == 1 { "" } else { "s" }
        );
        print_configuration(&found.final_configuration);
        if let Some(out) = &args.out {
            std::fs::write(out, found.final_configuration.to_json_string())
                .map_err(|e| Failure::Input(format!("cannot write {}: {e}", out.display())))?;
            println!("final configuration written to {}", out.display());
        }
        let matches = match (&found.expected, &args.run.expect) {
            (Some((expected, compared)), Some(path)) => print_comparison(expected, compared, path),
            _ => true,
        };
        Ok(ExitCode::from(u8::from(result.n_rejected > 0 || !matches)))
    })
}

/// `args`' sequences replayed on the model of the checked `program` (its text `source`), the
/// recording written when asked for; a label without a module is `Failure::Checked`.
pub fn replayed_on(
    args: &ReplayArgs,
    program: &dynarole_core::Program,
    source: &str,
) -> Result<Replayed, Failure> {
    let display = args.file.display().to_string();
    let start = read_configuration(&args.run.from)?;
    let prepared = match prepare(program, &display, &args.run.sequences, start)? {
        Ok(prepared) => prepared,
        Err(errors) => return Err(Failure::checked(&display, source, errors)),
    };
    let (result, diagnostics) = replayed(program, &prepared);
    if args.record.wanted() {
        record(args, program, &prepared, &display, source)?;
    }
    // A configuration file's robot always has the file format.
    let final_configuration = result
        .final_world
        .configuration()
        .ok_or_else(|| Failure::Internal("the robot model has no configuration format".into()))?;
    let expected = match &args.run.expect {
        Some(path) => {
            let expected = read_configuration(path)?;
            let compared = compare_with_expected(&final_configuration, &expected);
            Some((expected, compared))
        }
        None => None,
    };
    Ok(Replayed {
        prepared,
        result,
        diagnostics,
        final_configuration,
        expected,
    })
}

/// The replay as a recording: the statements in the order the model does them.
/// The prepared sequences replayed on the model, with the same warnings as `check --from`:
/// the replay's, then the `&`s that are not independent (once left out, so that replay said
/// "0 warnings" where check warned), in source order.
pub(crate) fn replayed(
    program: &dynarole_core::Program,
    prepared: &dynarole_replay::Prepared,
) -> (dynarole_replay::Replay, Vec<dynarole_core::Diagnostic>) {
    let result = dynarole_replay::replay(
        program,
        &prepared.plans,
        prepared.world.clone(),
        &prepared.assignment,
    );
    let mut diagnostics = result.diagnostics.clone();
    diagnostics.extend(dynarole_replay::check_independence(
        program,
        &prepared.plans,
        prepared.world.clone(),
        &prepared.assignment,
    ));
    diagnostics.sort_by_key(|d| d.span);
    (result, diagnostics)
}

/// `sequences` prepared on `start` and replayed, their diagnostics rendered: the run, or the
/// exit code 1 when a label has no module or the model refuses a statement (the message
/// says `what` was refused, and that `refusal`).
pub(crate) fn replayed_whole(
    (program, source, display): (&dynarole_core::Program, &str, &str),
    sequences: &[String],
    start: Configuration,
    (what, refusal): (&str, &str),
) -> Result<Result<(crate::world::Prepared, dynarole_replay::Replay), ExitCode>, Failure> {
    let prepared = match prepare(program, display, sequences, start)? {
        Ok(prepared) => prepared,
        Err(errors) => {
            render::diagnostics(display, source, &errors);
            return Ok(Err(ExitCode::from(1)));
        }
    };
    let (result, diagnostics) = replayed(program, &prepared);
    render::diagnostics(display, source, &diagnostics);
    if result.n_rejected > 0 {
        let n = result.n_rejected;
        eprintln!("error: the model refuses {n} statement(s) of {what}{refusal}");
        return Ok(Err(ExitCode::from(1)));
    }
    Ok(Ok((prepared, result)))
}

fn record(
    args: &ReplayArgs,
    program: &dynarole_core::Program,
    prepared: &crate::world::Prepared,
    display: &str,
    source: &str,
) -> Result<(), Failure> {
    let statements = prepared.statements();
    let steps = dynarole_sim::replay_steps(&statements, &prepared.assignment);
    let start = prepared.start.clone();
    let title = format!("replay of {} ({display})", prepared.names.join(" + "));
    let recording = dynarole_sim::ModelRecording {
        kind: "replay",
        title: &title,
        robot: &program.robot,
        steps: &steps,
        statements: &statements,
        start: &start,
        source: Some(dynarole_recording::Source {
            name: display,
            text: source,
        }),
    }
    .record(vec![title.clone()])
    .map_err(crate::view::model_failure)?;
    args.record.write(&recording)
}

fn print_comparison(
    expected: &Configuration,
    compared: &Result<(), dynarole_world::Difference>,
    path: &Path,
) -> bool {
    match compared {
        Ok(()) => {
            println!("matches {} ({})", path.display(), expected.equality());
            true
        }
        Err(difference) => {
            println!("does NOT match {}:\n{difference}", path.display());
            false
        }
    }
}

/// One line per module and the latches, in file order.
fn print_configuration(config: &Configuration) {
    println!("final configuration:");
    for line in config.module_lines() {
        println!("  {line}");
    }
    let connections: Vec<String> = (config.named_connections().into_iter())
        .map(|(a, ca, b, cb)| format!("{a}.{ca}-{b}.{cb}"))
        .collect();
    println!("  latches: {}", connections.join(" "));
}
