//! Reading and writing configurations in the data-file JSON format, with every error naming
//! the field path; redundant fields are optional on input, checked when present, and always
//! written. This file picks the robot by the `robot` field; each robot's records are in its
//! folder (`atron/json.rs`, `mtran/json.rs`), what they share in `file_format.rs`.

use crate::atron::LATTICE_UNIT_M;
use crate::common::ConfigError;
use crate::configuration::Configuration;
use crate::file_format::{deserialize, write_document};
use crate::mtran::MTRAN_LATTICE_UNIT_M;
use serde::Deserialize;

/// Top-level fields common to both robots, read first to pick the robot.
#[derive(Deserialize)]
struct Probe {
    robot: Option<String>,
}

// The file format's entry points live beside the format, so that the configuration types do
// not depend on it.
impl Configuration {
    /// Parses and validates a configuration in the data-file format (see the crate README).
    pub fn from_json_str(text: &str) -> Result<Configuration, ConfigError> {
        parse_configuration(text)
    }

    /// Writes the configuration in the same format, including the redundant fields.
    pub fn to_json_string(&self) -> String {
        write_configuration(self)
    }
}

/// Parses either robot's file.
fn parse_configuration(text: &str) -> Result<Configuration, ConfigError> {
    not_an_object(text)?;
    let probe: Probe = deserialize(text)?;
    match probe.robot.as_deref() {
        Some("ATRON") => crate::atron::json::read(text).map(Configuration::Atron),
        Some("MTRAN") => crate::mtran::json::read(text).map(Configuration::Mtran),
        Some(other) => Err(ConfigError::new(
            "robot",
            format!("unknown robot \"{other}\"; expected \"ATRON\" or \"MTRAN\""),
        )),
        None => Err(ConfigError::new(
            "robot",
            "missing field; expected \"ATRON\" or \"MTRAN\"",
        )),
    }
}

/// A file that does not start as a JSON object is not a configuration at all (a program given
/// as `--from`, say): said as such, where JSON's own message would be "expected value".
fn not_an_object(text: &str) -> Result<(), ConfigError> {
    let Some((offset, found)) = text.char_indices().find(|(_, c)| !c.is_whitespace()) else {
        return Err(ConfigError::new(
            "document",
            "the file is empty; expected a configuration (a JSON object)",
        ));
    };
    if found == '{' {
        return Ok(());
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    let program = text[offset..].starts_with("robot") || text.contains("sequence ");
    let hint = if program {
        "; this looks like a DynaRole program (.dr), not a configuration (.json)"
    } else {
        ""
    };
    Err(ConfigError::new(
        "document",
        format!(
            "expected a configuration (a JSON object, starting with `{{`), found `{}` at line \
             {line}, column {column}{hint}",
            found.escape_debug()
        ),
    ))
}

/// Writes a configuration in its robot's data-file format.
fn write_configuration(config: &Configuration) -> String {
    let (robot, unit, modules) = match config {
        Configuration::Atron(c) => (
            "ATRON",
            LATTICE_UNIT_M,
            (c.modules().iter().map(crate::atron::json::atron_value)).collect::<Vec<_>>(),
        ),
        Configuration::Mtran(c) => (
            "MTRAN",
            MTRAN_LATTICE_UNIT_M,
            (c.modules().iter().map(crate::mtran::json::mtran_value)).collect::<Vec<_>>(),
        ),
    };
    let connections = config.named_connections();
    write_document(robot, unit, &modules, &connections, config.metadata())
}
