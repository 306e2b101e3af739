//! A RoFI configuration as the rest of dynarole sees one: the modules named (`M7` for ID 7
//! unless a file names them), in ID order, each joint in whole degrees, validated the way the
//! robot model keeps it (connected, every loop closed, no two shoes overlapping), answering
//! [`RobotShape`]. RoFICoM connectors are genderless: every one can connect and disconnect.

use crate::kinematics::poses;
use crate::module::{Connection, Connector, Joint, Module, RofiConfiguration};
use crate::turn::mate_of;
use crate::validity::validate;
use dynarole_world::file_format::{is_module_name, MAX_MODULE_ID};
use dynarole_world::rigid::{Body, Shape, Unnamed};
use dynarole_world::{ConfigError, Metadata, NamedConnection, Port, RobotShape, Rotation, Vec3};
use std::collections::BTreeMap;

/// How far a joint's angle may be from a whole number of degrees and still be that number:
/// angles are read as decimals, and a program turns joints by whole degrees.
const WHOLE_DEGREE_TOLERANCE: f64 = 1e-6;

/// A validated RoFI configuration with its module names and descriptive fields.
#[derive(Clone, Debug, PartialEq)]
pub struct RofiRobot {
    config: RofiConfiguration,
    /// By module index (ID order).
    names: Vec<String>,
    ids: Vec<u32>,
    metadata: Metadata,
    /// Its file names no module (a voxel world): it is compared by its shape alone.
    anonymous: bool,
}

impl RofiRobot {
    /// Validates `config`; modules without a name in `names` are called `M<id>`. Errors name
    /// the field (`modules` or `connections` of dynarole's own format, `document` otherwise).
    pub fn new(
        config: RofiConfiguration,
        names: &BTreeMap<u32, String>,
        metadata: Metadata,
    ) -> Result<RofiRobot, ConfigError> {
        let ids: Vec<u32> = config.modules().map(|m| m.id).collect();
        let names: Vec<String> = (ids.iter())
            .map(|id| names.get(id).cloned().unwrap_or_else(|| format!("M{id}")))
            .collect();
        check_ids_and_names(&ids, &names)?;
        for module in config.modules() {
            whole_degrees(module)?;
        }
        validate(&config).map_err(|e| ConfigError::new("document", e.to_string()))?;
        Ok(RofiRobot {
            config,
            names,
            ids,
            metadata,
            anonymous: false,
        })
    }

    /// The same robot, read from a file that names no module: compared with another by the
    /// shape alone (the IDs it was given are its reader's numbering).
    pub(crate) fn anonymous(self) -> RofiRobot {
        RofiRobot {
            anonymous: true,
            ..self
        }
    }

    /// The same robot with `config` in place of its configuration (the same modules), as the
    /// model leaves it after an operation it checked.
    pub(crate) fn with_configuration(&self, config: RofiConfiguration) -> RofiRobot {
        RofiRobot {
            config,
            ..self.clone()
        }
    }

    pub fn configuration(&self) -> &RofiConfiguration {
        &self.config
    }

    pub fn metadata(&self) -> &Metadata {
        &self.metadata
    }

    /// Module names by index.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The module ID at index `m`.
    pub fn id_at(&self, m: usize) -> Option<u32> {
        self.ids.get(m).copied()
    }

    /// The index of the module with ID `id`.
    pub fn index_of_id(&self, id: u32) -> Option<usize> {
        self.ids.binary_search(&id).ok()
    }

    /// The connector `port` as RoFI's (module ID, connector).
    pub(crate) fn rofi_port(&self, port: Port) -> Option<(u32, Connector)> {
        Some((
            self.id_at(port.module)?,
            Connector::from_index(port.connector)?,
        ))
    }

    /// RoFI's (module ID, connector) as a port.
    pub(crate) fn port_of(&self, (id, connector): (u32, Connector)) -> Option<Port> {
        Some(Port {
            module: self.index_of_id(id)?,
            connector: connector.index(),
        })
    }

    /// One line per module: name, ID and the three joints.
    pub fn module_lines(&self) -> Vec<String> {
        (self.config.modules().zip(&self.names))
            .map(|(m, name)| {
                format!(
                    "{name:<6} id {:<5} alpha {} beta {} gamma {} deg",
                    m.id, m.alpha, m.beta, m.gamma
                )
            })
            .collect()
    }

    /// The connections as names, each from the end that comes first in ID and connector order.
    pub fn named_connections(&self) -> Vec<NamedConnection> {
        self.ordered_connections()
            .into_iter()
            .filter_map(|c| {
                let (a, b) = (self.port_of(c.from)?, self.port_of(c.to)?);
                let name = |p: Port| self.names[p.module].clone();
                Some((name(a), a.connector, name(b), b.connector))
            })
            .collect()
    }

    /// Every connection from its lower end (module ID, then connector), sorted.
    pub(crate) fn ordered_connections(&self) -> Vec<Connection> {
        let mut all: Vec<Connection> = (self.config.connections().iter())
            .map(|c| if c.to < c.from { c.reversed() } else { *c })
            .collect();
        all.sort_by_key(|c| (c.from, c.to));
        all
    }

    /// What a rigid motion leaves of the configuration. A connected RoFI configuration is
    /// fixed up to a rigid motion by its joints and its connections with their twists, so
    /// those are compared and positions are not: every body is at the origin.
    pub fn rigid_shape(&self) -> Shape {
        let bodies = (self.config.modules().zip(&self.names))
            .map(|(m, name)| {
                let joints = Joint::ALL.map(|j| whole(m.joint(j)) as i32).to_vec();
                let body = Body {
                    id: Some(m.id),
                    position: [0; 3],
                    frame: Rotation::IDENTITY,
                    joints,
                };
                (name.clone(), body)
            })
            .collect();
        let connections = (self.ordered_connections().iter())
            .filter_map(|c| {
                let (a, b) = (self.port_of(c.from)?, self.port_of(c.to)?);
                let (na, nb) = (&self.names[a.module], &self.names[b.module]);
                let twist = c.orientation.letter();
                Some(format!(
                    "{na}.C{}-{nb}.C{} {twist}",
                    a.connector, b.connector
                ))
            })
            .collect();
        Shape {
            bodies,
            connections,
            name_frame: |_| String::new(),
            position_scale: 1,
            anchored: false,
            unnamed: crate::voxel::unnamed_form(&self.config).map(|form| Unnamed {
                form,
                anonymous: self.anonymous,
            }),
        }
    }

    /// A RoFI configuration holds no place in space (RoFI's own formats pin one shoe): turned
    /// or shifted, it is the same configuration.
    pub fn transformed(
        &self,
        _rotation: Rotation,
        _translation: Vec3,
    ) -> Result<Self, ConfigError> {
        Ok(self.clone())
    }
}

/// The joint's angle as the whole number of degrees it is.
pub(crate) fn whole(degrees: f64) -> i64 {
    degrees.round() as i64
}

fn whole_degrees(module: &Module) -> Result<(), ConfigError> {
    for joint in Joint::ALL {
        let degrees = module.joint(joint);
        if (degrees - degrees.round()).abs() > WHOLE_DEGREE_TOLERANCE {
            return Err(ConfigError::new(
                "document",
                format!(
                    "module {}: {} is {degrees} degrees; dynarole turns RoFI joints by whole \
                     degrees",
                    module.id,
                    joint.name()
                ),
            ));
        }
    }
    Ok(())
}

fn check_ids_and_names(ids: &[u32], names: &[String]) -> Result<(), ConfigError> {
    if let Some(id) = ids.iter().find(|id| **id > MAX_MODULE_ID) {
        return Err(ConfigError::new(
            "document",
            format!(
                "module ID {id} is beyond {MAX_MODULE_ID} (IDs are 16 bits on the modules, \
                 65535 means none)"
            ),
        ));
    }
    let mut seen = BTreeMap::new();
    for (name, id) in names.iter().zip(ids) {
        if !is_module_name(name) {
            return Err(ConfigError::new(
                "document",
                format!("module {id}'s name \"{name}\" is not a name a program can use (a letter or `_`, then letters, digits or `_`)"),
            ));
        }
        if let Some(other) = seen.insert(name.as_str(), id) {
            return Err(ConfigError::new(
                "document",
                format!("modules {other} and {id} are both called \"{name}\""),
            ));
        }
    }
    Ok(())
}

impl RobotShape for RofiRobot {
    fn connectors(&self) -> u8 {
        Connector::COUNT
    }

    /// Genderless: every connector connects and disconnects.
    fn is_male(&self, _connector: u8) -> bool {
        true
    }

    fn side(&self, connector: u8) -> usize {
        usize::from(connector / 3)
    }

    fn len(&self) -> usize {
        self.ids.len()
    }

    fn name(&self, m: usize) -> Option<&str> {
        self.names.get(m).map(String::as_str)
    }

    fn id(&self, m: usize) -> Option<u32> {
        self.id_at(m)
    }

    fn index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    fn index_by_id(&self, id: u32) -> Option<usize> {
        self.index_of_id(id)
    }

    fn joint(&self, m: usize, joint: u8) -> Option<i64> {
        let module = self.config.module(self.id_at(m)?)?;
        let joint = Joint::ALL.get(usize::from(joint))?;
        Some(whole(module.joint(*joint)))
    }

    fn latched_to(&self, port: Port) -> Option<Port> {
        let connection = self.config.connection_at(self.rofi_port(port)?)?;
        self.port_of(connection.to)
    }

    fn facing(&self, port: Port) -> Option<Port> {
        if let Some(partner) = self.latched_to(port) {
            return Some(partner);
        }
        let connection = mate_of(&self.config, self.rofi_port(port)?)?;
        self.port_of(connection.to)
    }

    /// A RoFICoM talks only to the connector it is connected to.
    fn link_target(&self, port: Port) -> Option<Port> {
        self.latched_to(port)
    }

    fn port_name(&self, port: Port) -> String {
        let name = self.name(port.module).unwrap_or("?");
        format!("{name}.C{}", port.connector)
    }
}

/// The configuration's shoe poses exist (it was validated): for the drawing and the model.
pub(crate) fn poses_of(config: &RofiConfiguration) -> Option<crate::kinematics::Poses> {
    poses(config).ok()
}
