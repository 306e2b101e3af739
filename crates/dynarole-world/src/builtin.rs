//! The built-in robots' models, made from a configuration of the data files.

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
