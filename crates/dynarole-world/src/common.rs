//! What every robot's configuration shares: ports, latches, the descriptive metadata and the
//! error of a configuration that does not load.

use crate::geometry::{within_bounds, Vec3, MAX_COORDINATE};
use std::fmt;

/// A configuration that failed to load or validate. `path` names the offending field the way a
/// reader finds it in the JSON (`modules[3].orientation`, `connections[2][1]`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConfigError {
    /// Field path, `document` when the problem is not in one field.
    pub path: String,
    /// What is wrong and, where possible, what was expected.
    pub message: String,
}

impl ConfigError {
    /// An error at `path`.
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> ConfigError {
        ConfigError {
            path: path.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

impl std::error::Error for ConfigError {}

/// Descriptive fields of a configuration file that the model carries along but does not use.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Metadata {
    /// The configuration's name (`eight`, `car`, ...).
    pub name: String,
    /// Where the data comes from.
    pub source: Option<String>,
    /// Simulator world position (metres) of lattice point [0, 0, 0].
    pub origin_m: Option<[f64; 3]>,
    /// How the shape was obtained.
    pub derivation: Option<String>,
    /// Free remark.
    pub note: Option<String>,
}

/// One connector of one module: `module` is the index into the configuration's module list.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct Port {
    /// Index of the module in its configuration's module order.
    pub module: usize,
    /// Connector number on that module.
    pub connector: u8,
}

/// A physical latch: always one male and one female connector facing each other.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct Latch {
    /// The male side (the one that can release).
    pub male: Port,
    /// The female side.
    pub female: Port,
}

impl Latch {
    /// The port at the other end of the latch from `port`, if `port` is one of its ends.
    pub fn other_end(&self, port: Port) -> Option<Port> {
        if self.male == port {
            Some(self.female)
        } else if self.female == port {
            Some(self.male)
        } else {
            None
        }
    }
}

/// A connection as written in a file: module name, connector, module name, connector (either
/// order of genders).
pub type NamedConnection = (String, u8, String, u8);

/// Rejects a translation outside the coordinate bounds, before it can overflow the arithmetic
/// of the positions it shifts.
pub fn check_translation(translation: Vec3) -> Result<(), ConfigError> {
    if within_bounds(translation) {
        return Ok(());
    }
    Err(ConfigError::new(
        "translation",
        format!("coordinates must be within +-{MAX_COORDINATE}"),
    ))
}
