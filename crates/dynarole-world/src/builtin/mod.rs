//! The built-in robots behind the robot API: each one's `RobotShape` and `RobotModel`
//! (`atron.rs`, `mtran.rs`), the model made from a configuration of the data files, and the
//! one place that knows the built-in robots by plugin name (`BUILTIN_ROBOTS`).
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

/// `impl RobotShape` for a built-in robot's configuration (`$config`, of `$module`s): the
/// questions its modules, latches and connector rules answer alike for every built-in robot;
/// `$joint(module, joint)` reads a joint's angle in the plugin's unit, the robot's own part.
macro_rules! robot_shape {
    ($config:ty, $module:ty, $joint:path) => {
        impl $crate::model::RobotShape for $config {
            fn connectors(&self) -> u8 {
                <$module as $crate::structure::RobotModule>::CONNECTOR_COUNT
            }

            fn is_male(&self, connector: u8) -> bool {
                <$module as $crate::structure::RobotModule>::is_male(connector)
            }

            fn side(&self, connector: u8) -> usize {
                usize::from(!<$module as $crate::structure::RobotModule>::is_north_side(
                    connector,
                ))
            }

            fn len(&self) -> usize {
                self.modules().len()
            }

            fn name(&self, m: usize) -> Option<&str> {
                self.module(m).map(|x| x.name.as_str())
            }

            fn id(&self, m: usize) -> Option<u32> {
                self.module(m).and_then(|x| x.id)
            }

            fn index(&self, name: &str) -> Option<usize> {
                self.module_index(name)
            }

            fn index_by_id(&self, id: u32) -> Option<usize> {
                self.module_index_by_id(id)
            }

            fn joint(&self, m: usize, joint: u8) -> Option<i64> {
                self.module(m).and_then(|x| $joint(x, joint))
            }

            fn latched_to(&self, port: $crate::common::Port) -> Option<$crate::common::Port> {
                <$config>::latched_to(self, port)
            }

            fn facing(&self, port: $crate::common::Port) -> Option<$crate::common::Port> {
                <$config>::facing(self, port)
            }

            fn port_name(&self, port: $crate::common::Port) -> String {
                <$config>::port_name(self, port)
            }
        }
    };
}
use robot_shape;

/// The plugin names of the robots this crate has a model of.
pub const BUILTIN_ROBOTS: [&str; 2] = [atron::NAME, mtran::NAME];
