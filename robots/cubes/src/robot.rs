//! A configuration of cubes as the rest of dynarole sees one: modules named (`M7` for ID 7
//! unless a file names them), in file order, each at a lattice cell, some fixed (a ground
//! that never moves), connected by their shared faces, answering [`RobotShape`]. Each face is
//! a connector (numbered as [`Dir::ALL`]): a face talks to the face it touches, nothing else.
//! Two more connectors are the ground's wiring: where two or more cubes are fixed, the ground
//! that joins them (`lattice.rs`) also carries their packets, along a chain of the fixed
//! cubes in file order, connector [`GROUND_NEXT`] to the next one's [`GROUND_PREVIOUS`].

use crate::lattice::{Cell, Dir, Lattice};
use dynarole_world::file_format::{is_module_name, MAX_MODULE_ID};
use dynarole_world::rigid::{Body, Shape};
use dynarole_world::{ConfigError, Metadata, NamedConnection, Port, RobotShape, Rotation, Vec3};
use std::collections::BTreeMap;

/// The connector of a fixed cube wired through the ground to the next fixed cube, and the one
/// wired to the previous (after the six faces).
pub const GROUND_NEXT: u8 = 6;
pub const GROUND_PREVIOUS: u8 = 7;

/// One cube of a configuration.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Cube {
    pub name: String,
    pub id: u32,
    pub position: Cell,
    pub fixed: bool,
}

/// A validated configuration of cubes: names and IDs unique, no two cubes at one cell, every
/// cube reachable from every other through shared faces.
#[derive(Clone, Debug, PartialEq)]
pub struct CubesRobot {
    cubes: Vec<Cube>,
    lattice: Lattice,
    /// The fixed cubes in file order, when there are two or more (the ground's chain).
    ground: Vec<usize>,
    by_name: BTreeMap<String, usize>,
    by_id: BTreeMap<u32, usize>,
    metadata: Metadata,
}

impl CubesRobot {
    /// Validates `cubes`; errors name the field (`modules[i]...`) or `document`.
    pub fn new(cubes: Vec<Cube>, metadata: Metadata) -> Result<CubesRobot, ConfigError> {
        let (by_name, by_id) = index(&cubes)?;
        let positions = cubes.iter().map(|c| c.position).collect();
        let fixed = cubes.iter().map(|c| c.fixed).collect();
        let lattice = Lattice::new(positions, fixed)
            .map_err(|e| ConfigError::new("modules", e.to_string()))?;
        if !lattice.is_connected() {
            return Err(ConfigError::new(
                "modules",
                "the cubes do not all touch through faces: a robot is one connected piece",
            ));
        }
        let fixed: Vec<usize> = (0..cubes.len()).filter(|&m| cubes[m].fixed).collect();
        let ground = if fixed.len() > 1 { fixed } else { Vec::new() };
        Ok(CubesRobot {
            cubes,
            lattice,
            ground,
            by_name,
            by_id,
            metadata,
        })
    }

    /// The same robot with its cubes where `lattice` has them (the model's checked moves).
    pub(crate) fn with_lattice(&self, lattice: Lattice) -> CubesRobot {
        let mut robot = self.clone();
        for (m, cube) in robot.cubes.iter_mut().enumerate() {
            if let Some(position) = lattice.position(m) {
                cube.position = position;
            }
        }
        robot.lattice = lattice;
        robot
    }

    /// The same cubes under another configuration name.
    pub(crate) fn rename(&mut self, name: String) {
        self.metadata.name = name;
    }

    pub fn cubes(&self) -> &[Cube] {
        &self.cubes
    }

    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    pub fn metadata(&self) -> &Metadata {
        &self.metadata
    }

    /// One line per module: name, ID, cell and whether it is fixed.
    pub fn module_lines(&self) -> Vec<String> {
        (self.cubes.iter())
            .map(|c| {
                let [x, y, z] = c.position;
                let fixed = if c.fixed { " fixed" } else { "" };
                format!("{:<6} id {:<5} at ({x}, {y}, {z}){fixed}", c.name, c.id)
            })
            .collect()
    }

    /// The fixed cube wired to `port` through the ground, if any.
    fn ground_partner(&self, port: Port) -> Option<Port> {
        let place = self.ground.iter().position(|&m| m == port.module)?;
        let (other, connector) = match port.connector {
            GROUND_NEXT => (self.ground.get(place + 1)?, GROUND_PREVIOUS),
            GROUND_PREVIOUS => (self.ground.get(place.checked_sub(1)?)?, GROUND_NEXT),
            _ => return None,
        };
        Some(Port {
            module: *other,
            connector,
        })
    }

    /// Every two cubes that share a face, from the lower index, by the faces' numbers, then
    /// the ground's wiring.
    pub fn named_connections(&self) -> Vec<NamedConnection> {
        let mut out = Vec::new();
        for (m, cube) in self.cubes.iter().enumerate() {
            for (face, dir) in Dir::ALL.iter().enumerate() {
                let Some(other) = self.lattice.neighbour(m, *dir).filter(|o| *o > m) else {
                    continue;
                };
                let back = face_of(dir.reversed());
                let name = self.cubes[other].name.clone();
                out.push((cube.name.clone(), face as u8, name, back));
            }
        }
        for pair in self.ground.windows(2) {
            let name = |m: usize| self.cubes[m].name.clone();
            out.push((name(pair[0]), GROUND_NEXT, name(pair[1]), GROUND_PREVIOUS));
        }
        out
    }

    /// Cubes are compared where they stand: a move changes cells exactly, and a plan's end
    /// is a set of cells.
    pub fn rigid_shape(&self) -> Shape {
        let bodies = (self.cubes.iter())
            .map(|c| {
                let body = Body {
                    id: Some(c.id),
                    position: c.position,
                    frame: Rotation::IDENTITY,
                    joints: Vec::new(),
                };
                (c.name.clone(), body)
            })
            .collect();
        let connections = (self.named_connections().into_iter())
            .map(|(a, ca, b, cb)| format!("{a}.C{ca}-{b}.C{cb}"))
            .collect();
        Shape {
            bodies,
            connections,
            name_frame: |_| String::new(),
            position_scale: 1,
            anchored: true,
            unnamed: None,
        }
    }

    /// The cubes turned by `rotation` (a lattice rotation) and shifted by `translation`.
    pub fn transformed(&self, rotation: Rotation, translation: Vec3) -> Result<Self, ConfigError> {
        let cubes = (self.cubes.iter())
            .map(|c| {
                let turned = rotation.apply(c.position);
                let position = std::array::from_fn(|k| turned[k].saturating_add(translation[k]));
                Cube {
                    position,
                    ..c.clone()
                }
            })
            .collect();
        CubesRobot::new(cubes, self.metadata.clone())
    }
}

/// The connector number of the face towards `dir` (its place in [`Dir::ALL`]).
pub fn face_of(dir: Dir) -> u8 {
    let place = Dir::ALL.iter().position(|d| *d == dir).unwrap_or(0);
    place as u8
}

/// Module indices by name and by ID, each unique and usable by a program.
type Indices = (BTreeMap<String, usize>, BTreeMap<u32, usize>);

fn index(cubes: &[Cube]) -> Result<Indices, ConfigError> {
    let mut by_name = BTreeMap::new();
    let mut by_id = BTreeMap::new();
    for (i, cube) in cubes.iter().enumerate() {
        let at = |field: &str| format!("modules[{i}].{field}");
        if cube.id > MAX_MODULE_ID {
            let message = format!(
                "expected 0 to {MAX_MODULE_ID} (IDs are 16 bits on the modules, 65535 means \
                 none), found {}",
                cube.id
            );
            return Err(ConfigError::new(at("id"), message));
        }
        if !is_module_name(&cube.name) {
            let message = format!(
                "\"{}\" is not a name a program can use (a letter or `_`, then letters, digits \
                 or `_`)",
                cube.name
            );
            return Err(ConfigError::new(at("name"), message));
        }
        if let Some(other) = by_name.insert(cube.name.clone(), i) {
            let message = format!("\"{}\" also names modules[{other}]", cube.name);
            return Err(ConfigError::new(at("name"), message));
        }
        if let Some(other) = by_id.insert(cube.id, i) {
            let message = format!("ID {} is also modules[{other}]'s", cube.id);
            return Err(ConfigError::new(at("id"), message));
        }
    }
    Ok((by_name, by_id))
}

impl RobotShape for CubesRobot {
    /// One per face, and the two of the ground's wiring.
    fn connectors(&self) -> u8 {
        GROUND_PREVIOUS + 1
    }

    /// Faces are alike: none is the side of a latch that releases.
    fn is_male(&self, _connector: u8) -> bool {
        true
    }

    /// A cube is one rigid body.
    fn side(&self, _connector: u8) -> usize {
        0
    }

    fn len(&self) -> usize {
        self.cubes.len()
    }

    fn name(&self, m: usize) -> Option<&str> {
        self.cubes.get(m).map(|c| c.name.as_str())
    }

    fn id(&self, m: usize) -> Option<u32> {
        self.cubes.get(m).map(|c| c.id)
    }

    fn index(&self, name: &str) -> Option<usize> {
        self.by_name.get(name).copied()
    }

    fn index_by_id(&self, id: u32) -> Option<usize> {
        self.by_id.get(&id).copied()
    }

    fn joint(&self, _m: usize, _joint: u8) -> Option<i64> {
        None
    }

    /// Cubes that share a face are connected, face to face; fixed cubes also through the
    /// ground.
    fn latched_to(&self, port: Port) -> Option<Port> {
        if port.connector >= GROUND_NEXT {
            return self.ground_partner(port);
        }
        let dir = *Dir::ALL.get(usize::from(port.connector))?;
        let other = self.lattice.neighbour(port.module, dir)?;
        Some(Port {
            module: other,
            connector: face_of(dir.reversed()),
        })
    }

    fn facing(&self, port: Port) -> Option<Port> {
        self.latched_to(port)
    }

    /// A face talks to the face it touches.
    fn link_target(&self, port: Port) -> Option<Port> {
        self.latched_to(port)
    }

    fn port_name(&self, port: Port) -> String {
        let name = self.name(port.module).unwrap_or("?");
        format!("{name}.C{}", port.connector)
    }
}
