//! A configuration of either built-in robot, as the data files hold it: which robot it is, its
//! metadata and rigid motions of it (reading and writing the JSON are in `json.rs`).

use crate::atron::config::AtronConfiguration;
use crate::common::{ConfigError, Metadata};
use crate::geometry::{Rotation, Vec3};
use crate::mtran::module::MtranConfiguration;

/// Which robot a configuration is for.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Robot {
    /// ATRON (lattice, one joint per module).
    Atron,
    /// M-TRAN (two blocks and a link, two joints).
    Mtran,
}

impl Robot {
    /// The name used in the `robot` field.
    pub fn name(self) -> &'static str {
        match self {
            Robot::Atron => "ATRON",
            Robot::Mtran => "MTRAN",
        }
    }
}

/// A validated configuration of either robot.
#[derive(Clone, Debug, PartialEq)]
pub enum Configuration {
    /// An ATRON configuration.
    Atron(AtronConfiguration),
    /// An M-TRAN configuration.
    Mtran(MtranConfiguration),
}

impl Configuration {
    /// Which robot this is.
    pub fn robot(&self) -> Robot {
        match self {
            Configuration::Atron(_) => Robot::Atron,
            Configuration::Mtran(_) => Robot::Mtran,
        }
    }

    /// The descriptive fields.
    pub fn metadata(&self) -> &Metadata {
        match self {
            Configuration::Atron(c) => c.metadata(),
            Configuration::Mtran(c) => c.metadata(),
        }
    }

    /// One line per module, in file order, as the robot summarises its modules (a command's
    /// printed final configuration).
    pub fn module_lines(&self) -> Vec<String> {
        match self {
            Configuration::Atron(c) => c.module_lines(),
            Configuration::Mtran(c) => c.module_lines(),
        }
    }

    /// The configuration as rigid bodies, as its robot reduces it (`compare.rs`).
    pub(crate) fn rigid_shape(&self) -> crate::rigid::Shape {
        match self {
            Configuration::Atron(c) => c.rigid_shape(),
            Configuration::Mtran(c) => c.rigid_shape(),
        }
    }

    /// The latches as names, male first, in latch order.
    pub fn named_connections(&self) -> Vec<crate::common::NamedConnection> {
        match self {
            Configuration::Atron(c) => c.named_connections(),
            Configuration::Mtran(c) => c.named_connections(),
        }
    }

    /// The ATRON configuration, if this is one.
    pub fn as_atron(&self) -> Option<&AtronConfiguration> {
        match self {
            Configuration::Atron(c) => Some(c),
            Configuration::Mtran(_) => None,
        }
    }

    /// The M-TRAN configuration, if this is one.
    pub fn as_mtran(&self) -> Option<&MtranConfiguration> {
        match self {
            Configuration::Atron(_) => None,
            Configuration::Mtran(c) => Some(c),
        }
    }

    /// The whole configuration turned by `rotation` and shifted by `translation` (in the file's
    /// position unit). Fails when the result leaves the robot's lattice.
    pub fn transformed(
        &self,
        rotation: Rotation,
        translation: Vec3,
    ) -> Result<Configuration, ConfigError> {
        Ok(match self {
            Configuration::Atron(c) => Configuration::Atron(c.transformed(rotation, translation)?),
            Configuration::Mtran(c) => Configuration::Mtran(c.transformed(rotation, translation)?),
        })
    }
}
