//! The dynarole command-line tool as a library: argument parsing and one module per subcommand.
//!
//! **Architecture invariant**: only this crate knows about files, exit codes and colours.

pub mod api;
mod bounds;
mod campaign;
pub mod check;
mod compile;
mod export;
mod failure;
mod fmt;
mod help;
mod import;
pub mod load;
mod model;
mod parallelise;
mod progress;
pub mod render;
mod replay;
mod reverse;
pub mod robots;
pub mod show;
mod simulate;
mod verify;
#[cfg(unix)]
pub mod video;
mod view;
mod world;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// dynarole: robust and reversible self-reconfiguration of modular robots.
#[derive(Parser)]
#[command(name = "dynarole", version, about, long_about = LONG_ABOUT, after_help = help::after_help())]
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

#[derive(Subcommand)]
enum Command {
    /// Check `.dr` files: syntax, names, types, reversibility. Exit 1 on any error.
    #[command(
        after_help = help::example("check")
    )]
    Check(check::CheckArgs),
    /// Compile sequences to a self-contained directory of C: runtime, state machine, Makefile.
    #[command(
        after_help = help::example("compile")
    )]
    Compile(compile::CompileArgs),
    /// Model-check a compiled sequence on a configuration with spin: S1, S2, S3 and L under
    /// the stated bounds (exit 0 verified, 1 violated, 3 inconclusive, 4 internal error).
    #[command(
        after_help = help::example("verify")
    )]
    Verify(verify::VerifyArgs),
    /// Draw a configuration (JSON) as an SVG or PNG picture.
    #[command(after_help = help::example("show"))]
    Show(show::ShowArgs),
    /// Run sequences on the kinematic model of the robot (no network) and report the result.
    #[command(
        after_help = help::example("replay")
    )]
    Replay(replay::ReplayArgs),
    /// Run the generated C on every module over lossy infrared links, with faults (exit 3
    /// when the goal is not reached).
    #[command(
        after_help = help::example("simulate")
    )]
    Simulate(simulate::SimulateArgs),
    /// Replay a recording in the browser: write one self-contained HTML page (or print
    /// poses at given times).
    #[command(
        after_help = help::example("view")
    )]
    View(view::ViewArgs),
    /// Run a sweep of simulations described by a TOML file, in parallel: DIR/runs.csv (one
    /// row per run; an interrupted campaign resumes where it stopped), summary.csv, plots.
    /// On a cluster: --shard K/N per job, or --emit the job files; then `campaign merge`.
    #[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
    #[command(
        after_help = help::example("campaign")
    )]
    Campaign(campaign::CampaignArgs),
    /// Rewrite `.dr` files in the canonical layout (comments kept).
    #[command(after_help = help::example("fmt"))]
    Fmt(fmt::FmtArgs),
    /// Print the reverse of SEQUENCE as a complete `.dr` file that `check` accepts.
    #[command(after_help = help::example("reverse"))]
    Reverse(reverse::ReverseArgs),
    /// Rewrite a sequence written in order with the most parallelism that is provably safe
    /// on the model; prints a complete `.dr` file and the makespan before and after.
    #[command(
        after_help = help::example("parallelise")
    )]
    Parallelise(parallelise::ParalleliseArgs),
    /// Read a planner's plan (a list of configurations, its format recognised from the
    /// content) into DIR/STEM.dr, STEM.from.json and STEM.expect.json; replay it to its last
    /// configuration and print its steps and critical path.
    #[command(after_help = help::example("import"))]
    Import(import::ImportArgs),
    /// Write a sequence in a format of its robot's own tools (`scen`: the cube planners'
    /// scenario, one move set per parallel group), after it replays from --from.
    #[command(after_help = help::example("export"))]
    Export(export::ExportArgs),
}

/// Runs the command line with the registry's robot kinds; the exit code follows the README
/// (0 ok, 1 bad input, 2 usage).
pub fn main() -> ExitCode {
    main_with(dynarole_robots::robots())
}

/// Runs the command line knowing the robot kinds `robots` (the registry's, with robots of
/// the embedding program's own): every command takes each of them.
pub fn main_with(robots: dynarole_world::Robots) -> ExitCode {
    robots::install(robots);
    let cli = Cli::parse();
    let outcome = match &cli.command {
        Command::Check(args) => check::run(args),
        Command::Compile(args) => compile_or_model(args),
        Command::Verify(args) => verify::run(args),
        Command::Show(args) => show::run(args),
        Command::Replay(args) => replay::run(args),
        Command::Simulate(args) => simulate::run(args),
        Command::View(args) => view::run(args),
        Command::Campaign(args) => campaign::run(args),
        Command::Fmt(args) => fmt::run(args),
        Command::Reverse(args) => reverse::run(args),
        Command::Parallelise(args) => parallelise::run(args),
        Command::Import(args) => import::run(args),
        Command::Export(args) => export::run(args),
    };
    match outcome {
        Ok(code) => code,
        Err(failure) => {
            render::failure(&failure);
            failure.exit_code()
        }
    }
}

/// `compile --target promela` writes a model (`model.rs`), the other targets code.
fn compile_or_model(args: &compile::CompileArgs) -> Result<ExitCode, load::Failure> {
    match args.target {
        compile::Target::Promela => model::compile(args),
        compile::Target::C | compile::Target::Nesc => compile::run(args),
    }
}

/// `--repeat`: a count of runs, at least one (zero runs would report nothing and succeed).
pub(crate) fn at_least_one(text: &str) -> Result<u64, String> {
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
