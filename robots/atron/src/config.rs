//! The validated ATRON configuration: modules on lattice sites, latches, and its queries.

use crate::lattice::{
    is_joint_position, is_male, is_north, LatticePhase, Orientation, CONNECTOR_COUNT,
};
use dynarole_world::common::{check_translation, ConfigError, Metadata, NamedConnection, Port};
use dynarole_world::geometry::{add, sub, within_bounds, Rotation, Vec3, MAX_COORDINATE};
use dynarole_world::rigid::{shape_of, Body, Shape};
use dynarole_world::structure::{RobotModule, Structure};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

/// One ATRON module. A plain record: [`AtronConfiguration::new`] checks it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AtronModule {
    /// Label used in sequences (`M0`).
    pub name: String,
    /// Numeric ID the roles test, if given.
    pub id: Option<u32>,
    /// The module's name in USSR, if given.
    pub ussr_name: Option<String>,
    /// Centre in lattice units (y up).
    pub position: Vec3,
    /// Frame of the south hemisphere.
    pub orientation: Orientation,
    /// Joint angle in 1/432 turn: 0, 108, 216 or 324.
    pub joint_units: u16,
}

impl AtronModule {
    /// World offset of the site connector `connector` faces in the current pose.
    pub fn connector_offset(&self, connector: u8) -> Option<Vec3> {
        self.orientation
            .connector_offset(self.joint_units, connector)
    }
}

/// A validated ATRON configuration: unique names and ids, legal sites in one lattice phase, at
/// most one module per site, legal joint angles, and latches that join a male and a female
/// connector facing each other, no connector used twice.
#[derive(Clone, PartialEq)]
pub struct AtronConfiguration {
    pub(crate) metadata: Metadata,
    pub(crate) structure: Structure<AtronModule>,
    /// Module index by site. Positions change only through [`AtronConfiguration::turn_modules`],
    /// which keeps it in step.
    sites: BTreeMap<Vec3, usize>,
    pub(crate) phase: Option<LatticePhase>,
}

impl AtronConfiguration {
    /// The configuration as rigid bodies (positions in lattice units, frames named as ATRON
    /// orientations), for the comparison up to a rigid motion.
    pub(crate) fn rigid_shape(&self) -> Shape {
        shape_of(
            &self.structure,
            |m| Body {
                id: m.id,
                position: m.position,
                frame: m.orientation.frame(),
                joints: vec![i32::from(m.joint_units)],
            },
            |r| Orientation::from_frame(r).name(),
            1,
        )
    }

    /// One line per module, in file order, for a summary: name, lattice position,
    /// orientation and joint angle.
    pub fn module_lines(&self) -> Vec<String> {
        (self.modules().iter())
            .map(|m| {
                let [x, y, z] = m.position;
                format!(
                    "{:<6} at ({x}, {y}, {z})  {:<12} joint {}",
                    m.name,
                    m.orientation.name(),
                    m.joint_units
                )
            })
            .collect()
    }

    /// Validates modules and connections (paths in errors are `modules[i]...` and
    /// `connections[k]...`, as in the JSON format).
    pub fn new(
        metadata: Metadata,
        modules: Vec<AtronModule>,
        connections: &[NamedConnection],
    ) -> Result<AtronConfiguration, ConfigError> {
        let mut structure = Structure::new(modules)?;
        let (phase, sites) = check_sites(structure.modules())?;
        structure.connect_all(connections)?;
        Ok(AtronConfiguration {
            metadata,
            structure,
            sites,
            phase,
        })
    }

    dynarole_world::configuration_queries!(AtronModule);

    /// Index of the module at lattice site `site`.
    pub fn module_at(&self, site: Vec3) -> Option<usize> {
        self.sites.get(&site).copied()
    }

    /// The structure's lattice phase (`None` only for an empty configuration).
    pub fn phase(&self) -> Option<LatticePhase> {
        self.phase
    }

    /// The connector of another module that `port` faces (any gender), if a module sits on the
    /// site it points at.
    /// Where a packet sent on `port` goes: the latched partner, or, for an unlatched male
    /// connector, an unlatched female connector facing it.
    pub fn link_target(&self, port: Port) -> Option<Port> {
        dynarole_world::latched_or_male_to_free_female(self, port)
    }

    pub fn facing(&self, port: Port) -> Option<Port> {
        let module = self.module(port.module)?;
        let site = add(module.position, module.connector_offset(port.connector)?);
        let other_index = self.module_at(site)?;
        let other = self.module(other_index)?;
        let back = sub(module.position, other.position);
        (0..CONNECTOR_COUNT)
            .find(|c| other.connector_offset(*c) == Some(back))
            .map(|connector| Port {
                module: other_index,
                connector,
            })
    }

    /// The configuration turned by `rotation` about the origin, then shifted by `translation`
    /// lattice units; an error when the result is not a legal lattice configuration (a
    /// translation must keep the sites on the lattice of some phase).
    pub fn transformed(
        &self,
        rotation: Rotation,
        translation: Vec3,
    ) -> Result<AtronConfiguration, ConfigError> {
        check_translation(translation)?;
        let modules = self
            .modules()
            .iter()
            .map(|m| AtronModule {
                position: add(rotation.apply(m.position), translation),
                orientation: m.orientation.rotated(&rotation),
                ..m.clone()
            })
            .collect();
        AtronConfiguration::new(self.metadata.clone(), modules, &self.named_connections())
    }

    /// Turns the modules `moving` by `rotation` about `pivot`, keeping the site index in step.
    pub(crate) fn turn_modules(
        &mut self,
        moving: &BTreeSet<usize>,
        pivot: Vec3,
        rotation: &Rotation,
    ) {
        for i in moving {
            if let Some(m) = self.structure.module_mut(*i) {
                self.sites.remove(&m.position);
                m.position = add(pivot, rotation.apply(sub(m.position, pivot)));
                m.orientation = m.orientation.rotated(rotation);
            }
        }
        // Entered only once all have left: a module may move onto a site another one vacated.
        for i in moving {
            if let Some(m) = self.structure.module(*i) {
                self.sites.insert(m.position, *i);
            }
        }
    }
}

// Written out so that the output stays what it was before the indices: they only repeat the
// modules and latches.
impl fmt::Debug for AtronConfiguration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("AtronConfiguration")
            .field("metadata", &self.metadata)
            .field("modules", &self.modules())
            .field("latches", self.latches())
            .field("phase", &self.phase)
            .finish()
    }
}

impl RobotModule for AtronModule {
    const ROBOT: &'static str = "ATRON";
    const CONNECTOR_COUNT: u8 = CONNECTOR_COUNT;
    const FEMALE_CONNECTOR: &'static str = "a female connector";

    fn name(&self) -> &str {
        &self.name
    }

    fn id(&self) -> Option<u32> {
        self.id
    }

    fn is_male(connector: u8) -> bool {
        is_male(connector)
    }

    fn is_north_side(connector: u8) -> bool {
        is_north(connector)
    }

    fn same_gender_message(label_a: &str, label_b: &str, both_male: bool) -> String {
        let kind = if both_male { "male" } else { "female" };
        format!(
            "{label_a} and {label_b} are both {kind}; a latch joins a male (even) and a female \
             (odd) connector"
        )
    }

    /// Each connector must point at the other module's site.
    fn check_facing(
        modules: &[AtronModule],
        path: &str,
        (a, la): (Port, &str),
        (b, lb): (Port, &str),
    ) -> Result<(), ConfigError> {
        for ((from, lfrom), (to, _)) in [((a, la), (b, lb)), ((b, lb), (a, la))] {
            let (Some(m_from), Some(m_to)) = (modules.get(from.module), modules.get(to.module))
            else {
                return Err(ConfigError::new(
                    path,
                    "connection refers to a missing module",
                ));
            };
            let offset = m_from.connector_offset(from.connector);
            let target = offset.map(|o| add(m_from.position, o));
            if target != Some(m_to.position) {
                return Err(ConfigError::new(
                    path,
                    format!(
                        "{la} and {lb} do not face each other: {lfrom} points at site {:?} but \
                         {} is at {:?}",
                        target.unwrap_or(m_from.position),
                        m_to.name,
                        m_to.position
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Checks joints, coordinates, the single lattice phase and one module per site; returns the
/// phase and the module index by site.
fn check_sites(
    modules: &[AtronModule],
) -> Result<(Option<LatticePhase>, BTreeMap<Vec3, usize>), ConfigError> {
    let mut phase: Option<LatticePhase> = None;
    let mut sites: BTreeMap<Vec3, usize> = BTreeMap::new();
    for (i, m) in modules.iter().enumerate() {
        if !is_joint_position(m.joint_units) {
            return Err(ConfigError::new(
                format!("modules[{i}].joint"),
                format!("joint {} is not one of 0, 108, 216, 324", m.joint_units),
            ));
        }
        if !within_bounds(m.position) {
            return Err(ConfigError::new(
                format!("modules[{i}].position"),
                format!("coordinates must be within +-{MAX_COORDINATE}"),
            ));
        }
        let axis = m.orientation.axis();
        let fixed = match phase {
            Some(p) => p,
            None => LatticePhase::for_module(m.position, axis).ok_or_else(|| {
                ConfigError::new(
                    format!("modules[{i}].position"),
                    format!(
                        "site {:?} with axis {:?} is not a legal ATRON site in any lattice phase \
                         (p + c must have exactly one odd coordinate, the axis coordinate)",
                        m.position, axis
                    ),
                )
            })?,
        };
        if !fixed.allows(m.position, axis) {
            return Err(ConfigError::new(
                format!("modules[{i}].position"),
                format!(
                    "site {:?} with axis {:?} is not legal in the lattice phase c = {:?} fixed \
                     by modules[0] (p + c must have exactly one odd coordinate, the axis one)",
                    m.position,
                    axis,
                    fixed.vector()
                ),
            ));
        }
        phase = Some(fixed);
        if let Some(j) = sites.insert(m.position, i) {
            return Err(ConfigError::new(
                format!("modules[{i}].position"),
                format!("site {:?} is already occupied by modules[{j}]", m.position),
            ));
        }
    }
    Ok((phase, sites))
}
