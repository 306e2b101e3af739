//! The M-TRAN module model (see `README.md`): two blocks joined by a link through two joints,
//! on an idealised cubic block lattice, and the validated M-TRAN configuration.
//!
//! Units: positions are kept in *quarter pitches* (0.035 m), half the file's unit, so that
//! block centres (0.5 file units from the module centre) are integers. A block pitch (the
//! distance between the centres of two face-to-face blocks) is 2 quarter pitches.
//!
//! Joint sign (our convention, USSR does not pin it): a positive angle turns the side beyond
//! the joint (link and south block for the north joint, south block for the south joint)
//! right-handed about the joint axis, which is the module's local +y (world: `joint_axis`),
//! relative to the side before it. Joint axes pass through the centre of their block.

use dynarole_world::common::{check_translation, ConfigError, Metadata, NamedConnection, Port};
use dynarole_world::geometry::{
    add, axis_name, scale, sub, within_bounds, Rotation, Vec3, MAX_COORDINATE,
};
use dynarole_world::rigid::{shape_of, Body, Shape};
use dynarole_world::structure::{RobotModule, Structure};
use std::collections::BTreeMap;
use std::fmt;

/// Number of connectors: 0-2 on the north block (male), 3-5 on the south block (female).
pub const MTRAN_CONNECTOR_COUNT: u8 = 6;
/// Metres per file position unit (half the 0.14 m module pitch).
pub const MTRAN_LATTICE_UNIT_M: f64 = 0.07;
/// Joint limit in degrees (both joints, both directions).
pub const MTRAN_JOINT_LIMIT_DEG: i16 = 90;
/// Smallest centre distance, in block pitches, between a block that moves during a joint turn
/// and one that stays still. Face-to-face neighbours sit at 1; a block swinging past the edge
/// of another comes within about 0.41. The value is our estimate (USSR has no such check).
pub const MTRAN_MIN_SWEEP_DISTANCE_BLOCKS: f64 = 0.9;
/// USSR block centre offset from the module centre along local x (m), for the redundant
/// `connector_positions_m` field.
pub const USSR_BLOCK_OFFSET_M: f64 = 0.0375;
/// USSR connector offset from its block centre (m).
pub const USSR_CONNECTOR_OFFSET_M: f64 = 0.0325;

/// Outward normal of each connector in its block's frame.
const LOCAL_NORMALS: [Vec3; 6] = [
    [-1, 0, 0],
    [0, -1, 0],
    [0, 1, 0],
    [1, 0, 0],
    [0, -1, 0],
    [0, 1, 0],
];

/// True for the male connectors 0-2 (north block), the only ones commanded to connect or
/// disconnect.
pub fn is_mtran_male(connector: u8) -> bool {
    connector < 3
}

/// One of the two joints.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub enum MtranJoint {
    /// Actuator 0: between the north block and the link.
    North,
    /// Actuator 1: between the link and the south block.
    South,
}

impl MtranJoint {
    /// The actuator number (0 north, 1 south).
    pub fn index(self) -> usize {
        match self {
            MtranJoint::North => 0,
            MtranJoint::South => 1,
        }
    }
}

/// The frame of a module's north block (equal to the whole module's frame when the joints are
/// straight): one of the 24 lattice rotations.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct MtranOrientation {
    frame: Rotation,
}

impl MtranOrientation {
    /// USSR's ORI2: rotation by -90 deg about x (local y -> world -z, local z -> world +y).
    pub const ORI2: MtranOrientation = MtranOrientation {
        frame: Rotation::from_rows_unchecked([[1, 0, 0], [0, 0, 1], [0, -1, 0]]),
    };

    /// The orientation with this frame.
    pub fn from_frame(frame: Rotation) -> MtranOrientation {
        MtranOrientation { frame }
    }

    /// Parses `ORI2` or three signed axes giving the world directions of local x, y and z
    /// (`+x-z+y` is ORI2).
    pub fn parse(name: &str) -> Result<MtranOrientation, String> {
        if name == "ORI2" {
            return Ok(MtranOrientation::ORI2);
        }
        let error = || {
            format!(
                "unknown M-TRAN orientation \"{name}\"; expected ORI2 or the world directions \
                 of local x, y, z as signed axes, e.g. \"+x-z+y\""
            )
        };
        let bytes = name.as_bytes();
        if bytes.len() != 6 {
            return Err(error());
        }
        let mut columns = [[0; 3]; 3];
        for (column, pair) in columns.iter_mut().zip(bytes.chunks(2)) {
            let sign = match pair.first() {
                Some(b'+') => 1,
                Some(b'-') => -1,
                _ => return Err(error()),
            };
            let axis = match pair.get(1) {
                Some(b'x') => 0,
                Some(b'y') => 1,
                Some(b'z') => 2,
                _ => return Err(error()),
            };
            column[axis] = sign;
        }
        Rotation::from_columns(columns[0], columns[1], columns[2])
            .map(MtranOrientation::from_frame)
            .ok_or_else(|| format!("orientation \"{name}\" is not a right-handed frame"))
    }

    /// `ORI2` when it is that constant, otherwise the signed-axes form.
    pub fn name(&self) -> String {
        if *self == MtranOrientation::ORI2 {
            return "ORI2".to_string();
        }
        (0..3).map(|i| axis_name(self.frame.column(i))).collect()
    }

    /// The frame.
    pub fn frame(&self) -> Rotation {
        self.frame
    }
}

impl fmt::Display for MtranOrientation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

/// Position and frame of one block.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct BlockPose {
    /// Block centre in quarter pitches.
    pub centre_quarter_pitch: Vec3,
    /// Block frame.
    pub frame: Rotation,
}

/// Where a connector is and which way it faces.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct ConnectorPose {
    /// Centre of the connector face, in quarter pitches.
    pub face_quarter_pitch: Vec3,
    /// Outward unit normal (world).
    pub normal: Vec3,
}

/// One M-TRAN module. A plain record: [`MtranConfiguration::new`] checks it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MtranModule {
    /// Label used in sequences.
    pub name: String,
    /// Numeric ID, if given.
    pub id: Option<u32>,
    /// USSR name, if given.
    pub ussr_name: Option<String>,
    /// Where the module centre would be with both joints straight and the north block where it
    /// is, in quarter pitches (the file's `position` times 2).
    pub centre_quarter_pitch: Vec3,
    /// Frame of the north block.
    pub orientation: MtranOrientation,
    /// North and south joint angles in degrees: -90, 0 or 90.
    pub joints_deg: [i16; 2],
}

/// Quarter turns about local y for a joint angle (which is a multiple of 90 once validated).
fn joint_rotation(angle_deg: i16) -> Rotation {
    Rotation::about_axis([0, 1, 0], i32::from(angle_deg / 90)).unwrap_or(Rotation::IDENTITY)
}

impl MtranModule {
    /// The north block.
    pub fn north_block(&self) -> BlockPose {
        let frame = self.orientation.frame;
        BlockPose {
            centre_quarter_pitch: sub(self.centre_quarter_pitch, frame.column(0)),
            frame,
        }
    }

    /// The south block: one block pitch from the north block along the link.
    pub fn south_block(&self) -> BlockPose {
        let north = self.north_block();
        let link = north.frame.compose(&joint_rotation(self.joints_deg[0]));
        BlockPose {
            centre_quarter_pitch: add(north.centre_quarter_pitch, scale(link.column(0), 2)),
            frame: link.compose(&joint_rotation(self.joints_deg[1])),
        }
    }

    /// World direction of both joint axes (local +y of the north block).
    pub fn joint_axis(&self) -> Vec3 {
        self.orientation.frame.column(1)
    }

    /// Pose of connector `connector` (0..=5).
    pub fn connector(&self, connector: u8) -> Option<ConnectorPose> {
        let local = *LOCAL_NORMALS.get(usize::from(connector))?;
        let block = if is_mtran_male(connector) {
            self.north_block()
        } else {
            self.south_block()
        };
        let normal = block.frame.apply(local);
        Some(ConnectorPose {
            face_quarter_pitch: add(block.centre_quarter_pitch, normal),
            normal,
        })
    }

    /// Both block centres (north, south).
    pub fn block_centres(&self) -> [Vec3; 2] {
        [
            self.north_block().centre_quarter_pitch,
            self.south_block().centre_quarter_pitch,
        ]
    }

    /// Outward normals of connectors 0..5 with the joints straight (the redundant
    /// `connector_normals` field).
    pub fn straight_connector_normals(&self) -> [Vec3; 6] {
        LOCAL_NORMALS.map(|n| self.orientation.frame.apply(n))
    }

    /// Connector positions relative to the module centre with the joints straight, in metres,
    /// using USSR's block geometry (the redundant `connector_positions_m` field).
    pub fn straight_connector_positions_m(&self) -> [[f64; 3]; 6] {
        let mut out = [[0.0; 3]; 6];
        for (i, (o, n)) in out.iter_mut().zip(LOCAL_NORMALS).enumerate() {
            let side = if i < 3 { -1.0 } else { 1.0 };
            let local = [
                side * USSR_BLOCK_OFFSET_M + f64::from(n[0]) * USSR_CONNECTOR_OFFSET_M,
                f64::from(n[1]) * USSR_CONNECTOR_OFFSET_M,
                f64::from(n[2]) * USSR_CONNECTOR_OFFSET_M,
            ];
            let rows = self.orientation.frame.rows();
            for (value, row) in o.iter_mut().zip(rows) {
                *value = (0..3).map(|k| f64::from(row[k]) * local[k]).sum();
            }
        }
        out
    }
}

/// A validated M-TRAN configuration: unique names and ids, joints at -90, 0 or 90, every block
/// on one cubic block lattice, no two blocks in one cell, and latches joining a male (0-2) and
/// a female (3-5) connector whose faces touch with opposite normals, no connector used twice.
#[derive(Clone, PartialEq)]
pub struct MtranConfiguration {
    pub(crate) metadata: Metadata,
    pub(crate) structure: Structure<MtranModule>,
}

impl MtranConfiguration {
    /// The configuration as rigid bodies (positions in quarter pitches, written in pitches;
    /// frames named as M-TRAN orientations), for the comparison up to a rigid motion.
    pub(crate) fn rigid_shape(&self) -> Shape {
        shape_of(
            &self.structure,
            |m| Body {
                id: m.id,
                position: m.centre_quarter_pitch,
                frame: m.orientation.frame(),
                joints: m.joints_deg.iter().map(|j| i32::from(*j)).collect(),
            },
            |r| MtranOrientation::from_frame(r).name(),
            2,
        )
    }

    /// One line per module, in file order, for a summary: name, orientation and the two joint
    /// angles.
    pub fn module_lines(&self) -> Vec<String> {
        (self.modules().iter())
            .map(|m| {
                let [n, s] = m.joints_deg;
                format!(
                    "{:<6} {:<12} joints {n} / {s} deg",
                    m.name,
                    m.orientation.name()
                )
            })
            .collect()
    }

    /// Validates modules and connections (error paths as in the JSON format).
    pub fn new(
        metadata: Metadata,
        modules: Vec<MtranModule>,
        connections: &[NamedConnection],
    ) -> Result<MtranConfiguration, ConfigError> {
        let mut structure = Structure::new(modules)?;
        check_blocks(structure.modules())?;
        structure.connect_all(connections)?;
        Ok(MtranConfiguration {
            metadata,
            structure,
        })
    }

    dynarole_world::configuration_queries!(MtranModule);

    /// The connector of another module whose face touches `port`'s face with the opposite
    /// normal, if any.
    /// Where a packet sent on `port` goes: the latched partner, or, for an unlatched male
    /// connector, an unlatched female connector facing it.
    pub fn link_target(&self, port: Port) -> Option<Port> {
        dynarole_world::latched_or_male_to_free_female(self, port)
    }

    pub fn facing(&self, port: Port) -> Option<Port> {
        let pose = self
            .structure
            .module(port.module)?
            .connector(port.connector)?;
        self.modules().iter().enumerate().find_map(|(index, m)| {
            if index == port.module {
                return None;
            }
            (0..MTRAN_CONNECTOR_COUNT)
                .find(|c| m.connector(*c).is_some_and(|other| faces(&pose, &other)))
                .map(|connector| Port {
                    module: index,
                    connector,
                })
        })
    }

    /// The configuration turned by `rotation` about the origin and shifted by `translation`
    /// file units (half pitches).
    pub fn transformed(
        &self,
        rotation: Rotation,
        translation: Vec3,
    ) -> Result<MtranConfiguration, ConfigError> {
        check_translation(translation)?;
        let modules = self
            .modules()
            .iter()
            .map(|m| MtranModule {
                centre_quarter_pitch: add(
                    rotation.apply(m.centre_quarter_pitch),
                    scale(translation, 2),
                ),
                orientation: MtranOrientation::from_frame(rotation.compose(&m.orientation.frame)),
                ..m.clone()
            })
            .collect();
        MtranConfiguration::new(self.metadata.clone(), modules, &self.named_connections())
    }
}

// Written out so that the output stays what it was before the indices: they only repeat the
// modules and latches.
impl fmt::Debug for MtranConfiguration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MtranConfiguration")
            .field("metadata", &self.metadata)
            .field("modules", &self.modules())
            .field("latches", self.latches())
            .finish()
    }
}

impl RobotModule for MtranModule {
    const ROBOT: &'static str = "M-TRAN";
    const CONNECTOR_COUNT: u8 = MTRAN_CONNECTOR_COUNT;
    const FEMALE_CONNECTOR: &'static str = "a female connector (3-5)";

    fn name(&self) -> &str {
        &self.name
    }

    fn id(&self) -> Option<u32> {
        self.id
    }

    fn is_male(connector: u8) -> bool {
        is_mtran_male(connector)
    }

    /// The male connectors are the north block's.
    fn is_north_side(connector: u8) -> bool {
        is_mtran_male(connector)
    }

    fn same_gender_message(label_a: &str, label_b: &str, _both_male: bool) -> String {
        format!("{label_a} and {label_b}: a latch joins a male (0-2) and a female (3-5) connector")
    }

    /// The two faces must touch with opposite normals.
    fn check_facing(
        modules: &[MtranModule],
        path: &str,
        (a, la): (Port, &str),
        (b, lb): (Port, &str),
    ) -> Result<(), ConfigError> {
        let pose = |p: Port| modules.get(p.module).and_then(|m| m.connector(p.connector));
        match (pose(a), pose(b)) {
            (Some(pa), Some(pb)) if faces(&pa, &pb) => Ok(()),
            _ => Err(ConfigError::new(
                path,
                format!("{la} and {lb} do not face each other"),
            )),
        }
    }
}

/// Two connector faces touch with opposite normals.
pub(crate) fn faces(a: &ConnectorPose, b: &ConnectorPose) -> bool {
    a.face_quarter_pitch == b.face_quarter_pitch && add(a.normal, b.normal) == [0, 0, 0]
}

/// Joints, coordinates, one block lattice, one block per cell.
fn check_blocks(modules: &[MtranModule]) -> Result<(), ConfigError> {
    let mut cells: BTreeMap<Vec3, (usize, &str)> = BTreeMap::new();
    let mut lattice_parity: Option<Vec3> = None;
    for (i, m) in modules.iter().enumerate() {
        for (j, angle) in m.joints_deg.iter().enumerate() {
            if !matches!(angle, -90 | 0 | 90) {
                return Err(ConfigError::new(
                    format!("modules[{i}].joints_deg[{j}]"),
                    format!(
                        "joint angle {angle} is not modelled; the range is -90..90 and only \
                         -90, 0 and 90 keep the blocks on the lattice"
                    ),
                ));
            }
        }
        if !within_bounds(m.centre_quarter_pitch) {
            return Err(ConfigError::new(
                format!("modules[{i}].position"),
                format!("coordinates must be within +-{}", MAX_COORDINATE / 2),
            ));
        }
        for (centre, block) in m.block_centres().into_iter().zip(["north", "south"]) {
            let parity = centre.map(|c| c.rem_euclid(2));
            let expected = *lattice_parity.get_or_insert(parity);
            if parity != expected {
                return Err(ConfigError::new(
                    format!("modules[{i}].position"),
                    format!(
                        "the {block} block of {} is off the block lattice fixed by modules[0] \
                         (block centres must differ by whole block pitches)",
                        m.name
                    ),
                ));
            }
            if let Some((j, other_block)) = cells.insert(centre, (i, block)) {
                return Err(ConfigError::new(
                    format!("modules[{i}].position"),
                    format!(
                        "the {block} block of {} overlaps the {other_block} block of modules[{j}]",
                        m.name
                    ),
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn straight(x: i32) -> MtranModule {
        MtranModule {
            name: format!("T{x}"),
            id: None,
            ussr_name: None,
            centre_quarter_pitch: [2 * x, 0, 0],
            orientation: MtranOrientation::ORI2,
            joints_deg: [0, 0],
        }
    }

    #[test]
    fn ori2_connectors_match_the_data_file() {
        let m = straight(0);
        let normals = m.straight_connector_normals();
        assert_eq!(
            normals,
            [
                [-1, 0, 0],
                [0, 0, 1],
                [0, 0, -1],
                [1, 0, 0],
                [0, 0, 1],
                [0, 0, -1]
            ]
        );
        assert_eq!(m.joint_axis(), [0, 0, -1]);
        let positions = m.straight_connector_positions_m();
        assert!((positions[1][0] + 0.0375).abs() < 1e-12);
        assert!((positions[1][2] - 0.0325).abs() < 1e-12);
        assert!((positions[0][0] + 0.07).abs() < 1e-12);
    }

    #[test]
    fn consecutive_snake_modules_face_male_0_to_female_3() {
        let (a, b) = (straight(0), straight(2));
        let male = b.connector(0);
        let female = a.connector(3);
        assert!(matches!((male, female), (Some(m), Some(f)) if faces(&m, &f)));
    }

    #[test]
    fn positive_north_joint_turns_the_south_block_about_the_joint_axis() {
        let mut m = straight(0);
        m.joints_deg = [90, 0];
        // North block at x = -1, link turned +90 deg about world -z: +x goes to -y.
        assert_eq!(m.north_block().centre_quarter_pitch, [-1, 0, 0]);
        assert_eq!(m.south_block().centre_quarter_pitch, [-1, -2, 0]);
    }

    #[test]
    fn orientation_names_round_trip() -> Result<(), String> {
        for frame in Rotation::all() {
            let o = MtranOrientation::from_frame(frame);
            assert_eq!(MtranOrientation::parse(&o.name())?, o);
        }
        assert_eq!(MtranOrientation::parse("+x-z+y")?, MtranOrientation::ORI2);
        assert!(MtranOrientation::parse("+x+x+y").is_err());
        assert!(MtranOrientation::parse("ORI9").is_err());
        Ok(())
    }
}
