//! The dynarole command-line tool as a library: argument parsing and one module per subcommand.
//!
//! **Architecture invariant**: only this crate knows about files, exit codes and colours.

pub mod campaign;
pub mod check;
pub mod compile;
pub mod failure;
pub mod fmt;
pub mod load;
pub mod model;
pub mod parallelise;
pub mod render;
pub mod replay;
pub mod reverse;
pub mod show;
pub mod simulate;
pub mod verify;
#[cfg(unix)]
pub mod video;
pub mod view;
pub mod world;

use clap::{Parser, Subcommand};
use dynarole_codegen::Protocol;
use dynarole_sim::Stepping;
use std::path::PathBuf;
use std::process::ExitCode;

/// dynarole: robust and reversible self-reconfiguration of modular robots.
#[derive(Parser)]
#[command(name = "dynarole", version, about, long_about = LONG_ABOUT, after_help = AFTER_HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// What the tool is, for `dynarole --help`.
const LONG_ABOUT: &str = "dynarole: robust and reversible self-reconfiguration of modular robots.

A reconfiguration is written once, as a `.dr` script (one statement per module operation, `;`
for what depends on what came before, `&` for what may run together). dynarole checks it
against the robot's API, derives its reverse, replays it on a kinematic model of the robot,
compiles it to a distributed state machine in portable C (or nesC) that runs on every
module, simulates that C under lost packets, dead links and resets, sweeps fault rates in
campaigns, model-checks the protocol with spin, and shows runs in 3D.";

/// Where to go next, for `dynarole --help`.
const AFTER_HELP: &str = "Start with:
  dynarole check examples/atron/eight2car.dr
  dynarole simulate examples/atron/eight2car.dr --sequence eight2car \\
      --from examples/atron/eight.json --expect examples/atron/car.json

`dynarole help COMMAND` shows a command's options and an example. Documentation: the
repository's README.md, and docs/ (language.md: the language; simulator.md, cluster.md,
verification.md, viewer.md, runtime.md, limits.md).
Exit codes: 0 success, 1 bad input or a failed check, 2 bad usage, 3 a simulation that did
not reach its goal or a search that could not finish, 4 internal error.";

#[derive(Subcommand)]
enum Command {
    /// Check `.dr` files: syntax, names, types, reversibility. Exit 1 on any error.
    #[command(
        after_help = "Example:\n  dynarole check examples/atron/eight2car.dr --from examples/atron/eight.json"
    )]
    Check {
        /// The `.dr` files to check.
        #[arg(value_name = "FILE")]
        files: Vec<PathBuf>,
        #[command(flatten)]
        plugins: load::PluginArgs,
        /// Also report what the given protocol cannot run.
        #[arg(long, value_parser = compile::choice::<Protocol>(), default_value_t = Protocol::Lattice)]
        protocol: Protocol,
        /// Also run the sequences on this configuration: report refused and suspicious steps,
        /// and `&`-joined statements that are not independent.
        #[arg(long, value_name = "CONFIG")]
        from: Option<PathBuf>,
        /// With --from: the sequences to run, in turn (default: the first in the file).
        #[arg(long = "sequence", value_name = "NAME", requires = "from")]
        sequences: Vec<String>,
    },
    /// Compile sequences to a self-contained directory of C: runtime, state machine, Makefile.
    #[command(
        after_help = "Example:\n  dynarole compile examples/atron/eight2car.dr --sequence eight2car -o out/eight2car && make -C out/eight2car"
    )]
    Compile {
        /// The `.dr` file holding the sequences.
        file: PathBuf,
        /// Sequence to compile; repeat to run several in turn (default: the first in the file).
        #[arg(long = "sequence", value_name = "NAME")]
        sequences: Vec<String>,
        /// What to generate: C for the modules, nesC (TinyOS), or the Promela model for spin.
        #[arg(long, value_enum, default_value_t = compile::Target::C)]
        target: compile::Target,
        #[command(flatten)]
        options: compile::ProtocolOptions,
        /// Lattice protocol: how many times the whole sequence runs (0: forever).
        #[arg(long, default_value_t = 1)]
        epochs: u16,
        /// The directory to write.
        #[arg(short = 'o', long = "output", value_name = "DIR")]
        out_dir: PathBuf,
        /// The configuration the sequence starts from: required by `--target promela` (whose
        /// model uses its communication graph) and `--protocol token` (whose hand-over routes
        /// are computed on it).
        #[arg(long, value_name = "CONFIG")]
        from: Option<PathBuf>,
        #[command(flatten)]
        model: model::ModelArgs,
        #[command(flatten)]
        plugins: load::PluginArgs,
    },
    /// Model-check a compiled sequence on a configuration with spin: S1, S2, S3 and L under
    /// the stated bounds (exit 0 verified, 1 violated, 3 inconclusive, 4 internal error).
    #[command(
        after_help = "Example:\n  dynarole verify examples/verify/ab_c.dr --from examples/verify/line3.json --resets 1"
    )]
    Verify {
        /// The `.dr` file holding the sequences.
        file: PathBuf,
        /// Sequence to check; repeat to run several in turn (default: the first in the file).
        #[arg(long = "sequence", value_name = "NAME")]
        sequences: Vec<String>,
        /// The configuration to start from (JSON): modules, roles and who hears whom.
        #[arg(long, value_name = "CONFIG")]
        from: PathBuf,
        #[command(flatten)]
        options: compile::ProtocolOptions,
        #[command(flatten)]
        model: model::ModelArgs,
        /// Lattice protocol: how many times the whole sequence runs.
        #[arg(long, default_value_t = 1)]
        epochs: u16,
        /// Memory for each search (MB); beyond it the search falls back to bitstate hashing.
        #[arg(long, default_value_t = 4096, value_name = "MB")]
        memory: u64,
        /// Time for each search (seconds); beyond it the search falls back to bitstate hashing.
        #[arg(long, default_value_t = 600, value_name = "SECONDS")]
        time_limit: u64,
        /// Use bitstate hashing from the start (a partial search, never a proof).
        #[arg(long)]
        bitstate: bool,
        /// Check S1, S2 and S3 only (not L).
        #[arg(long)]
        safety_only: bool,
        /// Keep the model, spin's files and the trail in DIR.
        #[arg(long, value_name = "DIR")]
        keep: Option<PathBuf>,
        /// Check a deliberately broken lattice protocol (tests of the checker).
        #[arg(long, value_enum, hide = true)]
        fault: Option<model::FaultArg>,
        #[command(flatten)]
        record: view::RecordArgs,
        #[command(flatten)]
        plugins: load::PluginArgs,
    },
    /// Draw a configuration (JSON) as an SVG or PNG picture.
    #[command(after_help = "Example:\n  dynarole show examples/atron/car.json -o out/car.svg")]
    Show {
        /// The configuration to draw (JSON).
        config: PathBuf,
        /// The picture to write: FILE.svg or FILE.png.
        #[arg(short = 'o', long = "output", value_name = "FILE")]
        output: PathBuf,
    },
    /// Run sequences on the kinematic model of the robot (no network) and report the result.
    #[command(
        after_help = "Example:\n  dynarole replay examples/atron/eight2car.dr --sequence eight2car --from examples/atron/eight.json --expect examples/atron/car.json"
    )]
    Replay {
        /// The `.dr` file holding the sequences.
        file: PathBuf,
        #[command(flatten)]
        run: world::RunArgs,
        /// Write the final configuration (JSON) here.
        #[arg(long, value_name = "CONFIG")]
        out: Option<PathBuf>,
        #[command(flatten)]
        record: view::RecordArgs,
        #[command(flatten)]
        plugins: load::PluginArgs,
    },
    /// Run the generated C on every module over lossy infrared links, with faults (exit 3
    /// when the goal is not reached).
    #[command(
        after_help = "Example:\n  dynarole simulate examples/atron/eight2car.dr --sequence eight2car --from examples/atron/eight.json --expect examples/atron/car.json --scenario examples/scenarios/lossy.toml --seed 1"
    )]
    Simulate {
        /// The `.dr` file holding the sequences.
        file: PathBuf,
        #[command(flatten)]
        run: world::RunArgs,
        #[command(flatten)]
        options: compile::ProtocolOptions,
        /// Faults, network and timing (TOML; see crates/dynarole-sim/SCENARIO.md).
        #[arg(long, value_name = "FILE")]
        scenario: Option<PathBuf>,
        /// Per-packet loss at the receiving connector (overrides the scenario's).
        #[arg(long, value_name = "P")]
        loss: Option<f64>,
        /// How modules are stepped (overrides the scenario's `stepping`).
        #[arg(long, value_name = "MODE", value_parser = compile::choice::<Stepping>())]
        stepping: Option<Stepping>,
        /// Seed of every random draw (loss, faults, timing): the same seed and inputs give
        /// the same run, byte for byte.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Runs with seeds SEED, SEED+1, ... (at least 1).
        #[arg(long, default_value_t = 1, value_parser = at_least_one)]
        repeat: u64,
        /// Write the event trace (fixed columns) here.
        #[arg(long, value_name = "FILE")]
        trace: Option<PathBuf>,
        /// Print the report as JSON (one line per run).
        #[arg(long)]
        json: bool,
        /// Run every module's firmware on an emulated microcontroller instead of the C
        /// compiled for the host (docs/simulator.md; needs scripts/ensure-avr).
        #[arg(long, value_name = "MCU")]
        firmware: Option<simulate::FirmwareArg>,
        #[command(flatten)]
        record: view::RecordArgs,
        #[command(flatten)]
        plugins: load::PluginArgs,
    },
    /// Replay a recording in the browser: write one self-contained HTML page (or print
    /// poses at given times).
    #[command(
        after_help = "Example:\n  dynarole view out/run.json -o out/run.html   (a recording written by simulate --record out/run.json)"
    )]
    View {
        /// The recording (JSON, written by `--record`).
        recording: PathBuf,
        /// The page to write.
        #[arg(short = 'o', long = "output", value_name = "FILE.html")]
        output: Option<PathBuf>,
        /// Print every module's pose at these times (milliseconds, comma-separated), as JSON.
        #[arg(long, value_name = "MS,...", value_delimiter = ',')]
        poses_at: Vec<f64>,
        /// Render the run as a video (MP4; headless chromium and ffmpeg).
        #[arg(long, value_name = "FILE.mp4")]
        video: Option<PathBuf>,
        /// Frames per second of the video.
        #[arg(long, default_value_t = 25)]
        fps: u32,
        /// Run seconds per video second.
        #[arg(long, default_value_t = 1.0)]
        speed: f64,
    },
    /// Run a sweep of simulations described by a TOML file, in parallel: DIR/runs.csv (one
    /// row per run; an interrupted campaign resumes where it stopped), summary.csv, plots.
    /// On a cluster: --shard K/N per job, or --emit the job files; then `campaign merge`.
    #[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
    #[command(
        after_help = "Example:\n  dynarole campaign examples/campaigns/smoke.toml   (then: dynarole campaign status out/smoke)"
    )]
    Campaign {
        #[command(subcommand)]
        action: Option<campaign::Action>,
        /// The campaign file (TOML; see crates/dynarole-campaign/README.md).
        #[arg(required = true)]
        file: Option<PathBuf>,
        /// The output directory (default: out/NAME for NAME.toml).
        #[arg(short = 'o', long = "output", value_name = "DIR")]
        out_dir: Option<PathBuf>,
        /// Do at most N of the runs not yet recorded, then stop (run again to go on).
        #[arg(long, value_name = "N", conflicts_with = "emit")]
        max_runs: Option<u64>,
        /// Worker threads (default: one per core; with --emit: per shard, default 1).
        #[arg(short = 'j', long, value_name = "N")]
        jobs: Option<usize>,
        /// Write no plots.
        #[arg(long)]
        no_plots: bool,
        /// Run only shard K (from 0) of N into DIR/shard-K-of-N.csv (resumable); the split
        /// depends only on the campaign and N. Then `dynarole campaign merge DIR`.
        #[arg(long, value_name = "K/N", conflicts_with = "emit")]
        shard: Option<dynarole_campaign::Shard>,
        /// Write job files into DIR that run the campaign as --shards N shards on this
        /// scheduler, then merge them (docs/cluster.md).
        #[arg(long, value_enum, requires = "shards")]
        emit: Option<campaign::Emit>,
        /// With --emit: the number of shards.
        #[arg(long, value_name = "N", requires = "emit", value_parser = clap::value_parser!(u64).range(1..=dynarole_campaign::MAX_SHARDS))]
        shards: Option<u64>,
        /// With --emit: most shards running at once (default: all).
        #[arg(long, value_name = "T", requires = "emit", value_parser = clap::value_parser!(u64).range(1..))]
        throttle: Option<u64>,
    },
    /// Rewrite `.dr` files in the canonical layout (comments kept).
    #[command(after_help = "Example:\n  dynarole fmt --check examples/atron/eight2car.dr")]
    Fmt {
        /// The `.dr` files to format in place.
        #[arg(value_name = "FILE")]
        files: Vec<PathBuf>,
        /// Change nothing; exit 1 if a file is not formatted.
        #[arg(long)]
        check: bool,
        #[command(flatten)]
        plugins: load::PluginArgs,
    },
    /// Print the reverse of SEQUENCE as a complete `.dr` file that `check` accepts.
    #[command(after_help = "Example:\n  dynarole reverse examples/atron/eight2car.dr eight2car")]
    Reverse {
        /// The `.dr` file holding the sequence.
        file: PathBuf,
        /// The sequence to reverse.
        sequence: String,
        /// Name of the reversed sequence (default: the file's `X = reverse SEQUENCE`,
        /// else `b2a` for `a2b`, else `SEQUENCE_reversed`).
        #[arg(long)]
        name: Option<String>,
        #[command(flatten)]
        plugins: load::PluginArgs,
    },
    /// Rewrite a sequence written in order with the most parallelism that is provably safe
    /// on the model; prints a complete `.dr` file and the makespan before and after.
    #[command(
        after_help = "Example:\n  dynarole parallelise examples/atron/eight2car.dr --sequence eight2car --from examples/atron/eight.json -o out/parallel.dr"
    )]
    Parallelise {
        /// The source file (.dr) holding the sequence.
        file: PathBuf,
        /// The sequence to parallelise.
        #[arg(long, value_name = "NAME")]
        sequence: String,
        /// The configuration it starts from (JSON).
        #[arg(long, value_name = "CONFIG")]
        from: PathBuf,
        /// Name of the new sequence (default: SEQUENCE_parallel).
        #[arg(long)]
        name: Option<String>,
        /// Write the file here instead of printing it.
        #[arg(short = 'o', long = "output", value_name = "OUT.dr")]
        out: Option<PathBuf>,
        /// `paper`: parallel groups only (no blocks), what the paper's protocol can run.
        #[arg(long, value_parser = compile::choice::<Protocol>(), default_value_t = Protocol::Lattice)]
        protocol: Protocol,
        /// Check only statements at most N apart in the input; farther ones stay ordered
        /// (faster on long sequences, less parallel). Default: every pair.
        #[arg(long, value_name = "N")]
        window: Option<usize>,
        #[command(flatten)]
        plugins: load::PluginArgs,
    },
}

/// Runs the command line; the exit code follows the README (0 ok, 1 bad input, 2 usage).
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Check {
            files,
            plugins,
            protocol,
            from,
            sequences,
        } => {
            let on = from.as_deref().map(|path| check::OnConfiguration {
                path,
                sequences: &sequences,
            });
            check::run(&files, &plugins, protocol, on.as_ref())
        }
        Command::Replay {
            file,
            run,
            out,
            record,
            plugins,
        } => replay::run(&replay::ReplayArgs {
            file: &file,
            sequences: &run.sequences,
            from: &run.from,
            expect: run.expect.as_ref(),
            out: out.as_ref(),
            record: &record,
            plugins: &plugins,
        }),
        Command::Simulate {
            file,
            run,
            options,
            scenario,
            loss,
            stepping,
            seed,
            repeat,
            trace,
            json,
            firmware,
            record,
            plugins,
        } => simulate::run(&simulate::SimulateArgs {
            file: &file,
            sequences: &run.sequences,
            from: &run.from,
            expect: run.expect.as_ref(),
            options: &options,
            scenario: scenario.as_ref(),
            loss,
            stepping,
            seed,
            repeat,
            trace: trace.as_ref(),
            json,
            firmware,
            record: &record,
            plugins: &plugins,
        }),
        Command::View {
            recording,
            output,
            poses_at,
            video,
            fps,
            speed,
        } => view::run(&view::ViewArgs {
            recording: &recording,
            output: output.as_ref(),
            poses_at: &poses_at,
            video: video.as_deref(),
            fps,
            speed,
        }),
        Command::Campaign {
            action,
            file,
            out_dir,
            max_runs,
            jobs,
            no_plots,
            shard,
            emit,
            shards,
            throttle,
        } => match (action, file) {
            (Some(action), _) => campaign::act(&action),
            (None, Some(file)) => campaign::run(&campaign::CampaignArgs {
                file: &file,
                out_dir: out_dir.as_ref(),
                max_runs,
                jobs,
                no_plots,
                shard,
                emit: emit
                    .zip(shards)
                    .map(|(scheduler, shards)| campaign::EmitArgs {
                        scheduler,
                        shards,
                        throttle: throttle.unwrap_or(shards),
                    }),
            }),
            (None, None) => Err(load::Failure::Usage(
                "campaign: name a campaign file, or `merge DIR`, or `status DIR`".into(),
            )),
        },
        Command::Fmt {
            files,
            check,
            plugins,
        } => fmt::run(&files, check, &plugins),
        Command::Compile {
            file,
            sequences,
            target,
            options,
            epochs,
            out_dir,
            from,
            model,
            plugins,
        } => {
            let args = compile::CompileArgs {
                file: &file,
                sequences: &sequences,
                target,
                options: &options,
                epochs,
                out_dir: &out_dir,
                from: from.as_deref(),
                plugins: &plugins,
            };
            match target {
                compile::Target::Promela => model::compile(&args, &model),
                compile::Target::C | compile::Target::Nesc => compile::run(&args),
            }
        }
        Command::Verify {
            file,
            sequences,
            from,
            options,
            model,
            epochs,
            memory,
            time_limit,
            bitstate,
            safety_only,
            keep,
            fault,
            record,
            plugins,
        } => verify::run(&verify::VerifyArgs {
            asked: verify::Asked {
                file: &file,
                plugins: &plugins,
                sequences: &sequences,
                from: &from,
                options: &options,
                model: &model,
                epochs,
            },
            memory_mb: memory,
            time_s: time_limit,
            bitstate,
            safety_only,
            keep: keep.as_deref(),
            fault,
            record: &record,
        }),
        Command::Show { config, output } => show::run(&config, &output),
        Command::Reverse {
            file,
            sequence,
            name,
            plugins,
        } => reverse::run(&file, &sequence, name.as_deref(), &plugins),
        Command::Parallelise {
            file,
            sequence,
            from,
            name,
            out,
            protocol,
            window,
            plugins,
        } => parallelise::run(&parallelise::ParalleliseArgs {
            file: &file,
            sequence: &sequence,
            from: &from,
            name: name.as_deref(),
            out: out.as_ref(),
            protocol,
            window,
            plugins: &plugins,
        }),
    };
    match outcome {
        Ok(code) => code,
        Err(failure) => {
            render::failure(&failure);
            failure.exit_code()
        }
    }
}

/// `--repeat`: a count of runs, at least one (zero runs would report nothing and succeed).
fn at_least_one(text: &str) -> Result<u64, String> {
    match text.parse::<u64>() {
        Ok(0) => Err("expected at least 1 run, found 0".into()),
        Ok(n) => Ok(n),
        Err(e) => Err(format!("expected a count of runs (1 or more): {e}")),
    }
}

#[cfg(test)]
mod tests {
    use super::Cli;
    use clap::CommandFactory;

    /// `--help` explains every argument of every subcommand, positional ones included.
    #[test]
    fn every_argument_has_help() {
        let cli = Cli::command();
        for command in cli.get_subcommands() {
            for arg in command.get_arguments() {
                assert!(
                    arg.get_help().is_some() || arg.get_long_help().is_some(),
                    "`dynarole {}`: `{}` has no help text",
                    command.get_name(),
                    arg.get_id()
                );
            }
        }
    }
}
