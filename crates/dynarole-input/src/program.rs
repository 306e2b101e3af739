//! The robots a `.dr` file can name, read from files: the built-in ones, the plugins given,
//! then a `NAME.robot.toml` beside the source for a `robot NAME;` still unknown. The one
//! loader of plugin files, for the commands (`dynarole-cli`'s `load.rs`) and for campaigns
//! (`dynarole-campaign`'s `load.rs`); each turns `PluginError` into its own error.

use crate::{read_input, InputError};
use dynarole_core::driver;
use dynarole_core::toml_error::TomlError;
use dynarole_core::{RobotApi, RobotRegistry};
use std::path::{Path, PathBuf};

/// A robot plugin file that could not be loaded.
#[derive(Debug)]
pub enum PluginError {
    /// The file could not be read.
    Read(InputError),
    /// Its text is not a plugin: the error (not yet located in `text`) and the text.
    Invalid {
        path: PathBuf,
        text: String,
        error: Box<TomlError>,
    },
}

/// The plugin in `text`, read from `path`.
pub fn plugin(path: &Path, text: String) -> Result<RobotApi, PluginError> {
    RobotApi::from_toml(&text).map_err(|error| PluginError::Invalid {
        path: path.to_path_buf(),
        text,
        error: Box::new(error),
    })
}

/// The plugin file at `path`; `seen` is told its text once read (a campaign records every
/// file its runs are computed from).
pub fn read_plugin(
    path: &Path,
    seen: &mut dyn FnMut(&Path, &str),
) -> Result<RobotApi, PluginError> {
    let text = read_input(path).map_err(PluginError::Read)?;
    seen(path, &text);
    plugin(path, text)
}

/// The robots the source at `source_path`, whose `robot NAME;` is `robot`, can name: those of
/// `built_in` (the robot kinds' plugins), then `plugins`, then, for a `robot` still unknown, the `NAME.robot.toml`
/// beside the source when there is one (read by [`read_plugin`] with `seen`).
pub fn registry(
    built_in: RobotRegistry,
    source_path: &Path,
    robot: Option<&str>,
    plugins: Vec<RobotApi>,
    seen: &mut dyn FnMut(&Path, &str),
) -> Result<RobotRegistry, PluginError> {
    driver::registry(built_in, robot, plugins, |file| {
        let beside = source_path.with_file_name(file);
        beside
            .is_file()
            .then(|| read_plugin(&beside, seen))
            .transpose()
    })
}
