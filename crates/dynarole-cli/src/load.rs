//! Reading inputs: source files and robot plugins, with errors that name the file.

use dynarole_core::driver;
pub use dynarole_core::driver::robot_name;
use dynarole_core::RobotRegistry;
use dynarole_input::program::{self, PluginError};
use std::path::{Path, PathBuf};

pub use crate::failure::{Failure, INTERNAL_EXIT};

#[derive(clap::Args, Clone, Debug, Default)]
pub struct PluginArgs {
    /// Load a robot API plugin (TOML); may be repeated. A file `NAME.robot.toml` beside the
    /// source is loaded automatically when the source says `robot NAME;`.
    #[arg(long = "plugin", value_name = "FILE")]
    pub plugins: Vec<PathBuf>,
}

/// Every user file the commands read comes through here (`dynarole_input`: the size limit,
/// the error naming the file).
pub fn read_source(path: &Path) -> Result<String, Failure> {
    dynarole_input::read_input(path).map_err(|e| Failure::Input(e.to_string()))
}

/// This run's robot kinds (`robots.rs`), then `--plugin` files, then a `NAME.robot.toml` beside `source_path`
/// for a `robot NAME;` that is still unknown (`dynarole_input::program`, the loader campaigns
/// use too).
pub fn registry(
    args: &PluginArgs,
    source_path: &Path,
    robot_name: Option<&str>,
) -> Result<RobotRegistry, Failure> {
    let plugins = args
        .plugins
        .iter()
        .map(|path| program::read_plugin(path, &mut |_, _| {}))
        .collect::<Result<Vec<_>, _>>()
        .map_err(plugin_failure)?;
    program::registry(
        crate::robots::plugins()?,
        source_path,
        robot_name,
        plugins,
        &mut |_, _| {},
    )
    .map_err(plugin_failure)
}

/// A plugin that cannot be read is bad input, as any unreadable file; one that is not a
/// plugin shows its TOML error.
fn plugin_failure(error: PluginError) -> Failure {
    match error {
        PluginError::Read(e) => Failure::Input(e.to_string()),
        PluginError::Invalid { path, text, error } => Failure::toml(&path, text, *error),
    }
}

/// Reads, parses and checks a source file: fails with its errors (`Failure::Checked`), or hands the checked
/// program and its text to `then` (every command that works on a checked file starts here).
pub fn with_program<T>(
    path: &Path,
    plugins: &PluginArgs,
    then: impl FnOnce(&dynarole_core::Program, &str) -> Result<T, Failure>,
) -> Result<T, Failure> {
    let source = read_source(path)?;
    let parsed = dynarole_core::parse(&source);
    let registry = registry(plugins, path, robot_name(&parsed.file))?;
    match driver::check(&parsed, &registry) {
        Ok(program) => then(&program, &source),
        Err(diagnostics) => Err(Failure::checked(
            &path.display().to_string(),
            &source,
            diagnostics,
        )),
    }
}

/// The sequences a command runs (`check --from`, `compile`, `replay`, `simulate`, `verify`):
/// the named ones, or the first one the file declares when none is named.
pub fn select_sequences(
    program: &dynarole_core::Program,
    display: &str,
    wanted: &[String],
) -> Result<Vec<String>, Failure> {
    driver::select_sequences(program, wanted).map_err(|e| selection(&e, display))
}

/// A sequence that cannot be run is bad input (exit 1): the name on the command line is well
/// formed but the file has no such sequence.
pub fn selection(error: &driver::SelectError, display: &str) -> Failure {
    Failure::Input(error.message(display))
}

/// `no sequence `x` in FILE; did you mean `y`? sequences in FILE: a, b`.
pub fn unknown_sequence(program: &dynarole_core::Program, display: &str, name: &str) -> Failure {
    selection(&driver::unknown_sequence(program, 0, name), display)
}

/// A fresh folder name for scratch files (`dynarole-WHAT-PID-NANOS` in the system's temporary
/// folder); the caller creates it and removes it when done.
pub fn scratch_dir(what: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    std::env::temp_dir().join(format!("dynarole-{what}-{}-{nanos}", std::process::id()))
}
