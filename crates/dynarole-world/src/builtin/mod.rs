//! The built-in robots behind the robot API: each one's `RobotShape` and `RobotModel`
//! (`atron.rs`, `mtran.rs`) and the model made from a configuration of the data files.
//!
//! The layering that keeps the crate free of import circles: a robot's folder (`atron/`,
//! `mtran/`: lattice, data-file configuration, world) is below `Configuration` and
//! `compare`, which are below the API (`model.rs`); only this module, above all of them,
//! joins a robot to the API.

mod atron;
mod mtran;

use crate::atron::world::World;
use crate::configuration::Configuration;
use crate::model::RobotModel;
use crate::mtran::world::MtranWorld;

impl Configuration {
    /// The robot model that starts from this configuration.
    pub fn into_model(self) -> Box<dyn RobotModel> {
        match self {
            Configuration::Atron(c) => Box::new(World::new(c)),
            Configuration::Mtran(c) => Box::new(MtranWorld::new(c)),
        }
    }
}
