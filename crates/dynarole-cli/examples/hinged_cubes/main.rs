//! A program that embeds dynarole with a robot of its own, the hinged cubes of `robot/`: every
//! command of the tool (check, replay, simulate, compile, verify, show, view, campaign, ...)
//! knows the built-in robots and this one, and nothing in the tool's crates names it.
//!
//! `cargo run -p dynarole-cli --example hinged_cubes -- check ring.dr` (from this folder).

mod robot;

fn main() -> std::process::ExitCode {
    dynarole_cli::main_with(dynarole_robots::robots().with(&robot::KIND))
}
