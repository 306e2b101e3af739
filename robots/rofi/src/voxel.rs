//! RoFI's voxel JSON (`{"bodies": [...]}`, what `rofi-voxel` reads and writes): one world or
//! an array of them (a plan), read into [`RofiConfiguration`]s. A voxel world names no module
//! and no connection: a module is a body whose `body_dir` points to +axis (its shoe A) and the
//! body it points at (its shoe B); IDs are given from 1 in the order of the A bodies and every
//! two connectors that face each other are connected, as RoFI's own conversion does. Each
//! world of a plan is normalised on its own (placed and turned anyhow), so world k is matched
//! to world k − 1 by the physical shape alone, up to a rigid motion: the one ±90° turn of one
//! joint, with the connections it cuts (the two halves of the robot it separates must each stay
//! connected) and the ones its end makes, that turns world k − 1 into world k (`next_world`).
//! The modules keep their IDs from the first world through the plan.

use crate::kinematics::poses;
use crate::module::{
    Connection, Connector, Dock, Joint, Module, Orientation, RofiConfiguration, Side,
};
use crate::tree::{across_connection, face_to_dock, Shoe};
use nalgebra::{Matrix4, Rotation3, Unit, Vector3, Vector4};
use serde::Deserialize;
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

/// Why a voxel file cannot be read: the JSON path of the field (empty for the whole file or a
/// whole world), the line and column when the JSON itself is wrong, and what was expected.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelError {
    pub path: String,
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl fmt::Display for VoxelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.path.is_empty() {
            true => self.message.fmt(f),
            false => write!(f, "at `{}`: {}", self.path, self.message),
        }
    }
}

impl std::error::Error for VoxelError {}

/// The worlds of a voxel plan as configurations, each with the index of the world it is at:
/// a world whose turn makes new connections is two configurations (the turn, then the
/// connections), both of that world.
pub struct VoxelPlan {
    pub configurations: Vec<(usize, RofiConfiguration)>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WorldJson {
    bodies: Vec<BodyJson>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BodyJson {
    body_dir: DirectionJson,
    joint_pos: i64,
    pos: [i64; 3],
    shoe_rotated: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DirectionJson {
    axis: String,
    is_positive: bool,
}

/// An integer vector of the grid (a position, or a unit direction).
type Cell = [i32; 3];

/// A direction along one axis of the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Direction {
    axis: usize,
    positive: bool,
}

impl Direction {
    fn vector(self) -> Cell {
        let mut v = [0; 3];
        v[self.axis] = if self.positive { 1 } else { -1 };
        v
    }

    fn opposite(self) -> Direction {
        Direction {
            positive: !self.positive,
            ..self
        }
    }
}

/// One body of a voxel world: a shoe, where it is, where its module's other body is, which
/// axis its ±X connectors lie on and where its −Z connector faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Body {
    pos: Cell,
    body_dir: Direction,
    shoe_rotated: bool,
    joint_pos: i32,
}

impl Body {
    fn next_axis(self) -> usize {
        (self.body_dir.axis + 1) % 3
    }

    fn previous_axis(self) -> usize {
        (self.body_dir.axis + 2) % 3
    }

    /// Where the −Z connector faces (RoFI's `zConnDirection`).
    fn z_direction(self) -> Direction {
        let axis = match self.shoe_rotated {
            true => self.next_axis(),
            false => self.previous_axis(),
        };
        match self.joint_pos {
            0 => self.body_dir.opposite(),
            90 => Direction {
                axis,
                positive: true,
            },
            _ => Direction {
                axis,
                positive: false,
            },
        }
    }

    /// Where the connector of index 1 of the side faces (RoFI's `xPlusConnDirection`); index 0
    /// faces the other way.
    fn x_plus_direction(self) -> Direction {
        match self.shoe_rotated {
            true => Direction {
                axis: self.previous_axis(),
                positive: !self.body_dir.positive,
            },
            false => Direction {
                axis: self.next_axis(),
                positive: self.body_dir.positive,
            },
        }
    }

    fn shape(self) -> Shape {
        let x = self.x_plus_direction().vector();
        Shape {
            pos: self.pos,
            partner: self.body_dir.vector(),
            z: self.z_direction().vector(),
            x_axis: x.map(i32::abs),
        }
    }
}

/// What can be seen of one shoe, whatever its module's name or which side it is: its cell,
/// the direction of its module's other shoe, where its −Z connector faces and the axis of its
/// two X connectors (which a half turn of the shoe swaps, so only the axis is seen).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
struct Shape {
    pos: Cell,
    partner: Cell,
    z: Cell,
    x_axis: Cell,
}

impl Shape {
    fn rotated(self, r: &Turn24, by: Cell) -> Shape {
        Shape {
            pos: add(r.apply(self.pos), by),
            partner: r.apply(self.partner),
            z: r.apply(self.z),
            x_axis: r.apply(self.x_axis).map(i32::abs),
        }
    }

    fn directions(self) -> (Cell, Cell, Cell) {
        (self.partner, self.z, self.x_axis)
    }
}

fn add(a: Cell, b: Cell) -> Cell {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub(a: Cell, b: Cell) -> Cell {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// One of the 24 rotations of the grid: a signed permutation matrix of determinant 1.
#[derive(Clone, Copy, Debug)]
struct Turn24([[i32; 3]; 3]);

impl Turn24 {
    fn apply(&self, v: Cell) -> Cell {
        let m = &self.0;
        [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
    }

    fn all() -> Vec<Turn24> {
        let permutations = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        let mut out = Vec::with_capacity(24);
        for p in permutations {
            for signs in 0..8 {
                let mut m = [[0; 3]; 3];
                for (row, &column) in p.iter().enumerate() {
                    m[row][column] = if signs >> row & 1 == 1 { -1 } else { 1 };
                }
                if determinant(&m) == 1 {
                    out.push(Turn24(m));
                }
            }
        }
        out
    }
}

fn determinant(m: &[[i32; 3]; 3]) -> i32 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// The shapes of a world in a form that does not depend on where it is or how it is turned:
/// the least of its 24 rotations, each moved so that its lowest corner is at the origin.
fn canonical(shapes: &[Shape]) -> Vec<Shape> {
    Turn24::all()
        .iter()
        .map(|r| {
            let turned: Vec<Shape> = shapes.iter().map(|s| s.rotated(r, [0; 3])).collect();
            let corner = [0, 1, 2].map(|i| turned.iter().map(|s| s.pos[i]).min().unwrap_or(0));
            let mut moved: Vec<Shape> = (turned.iter())
                .map(|s| Shape {
                    pos: sub(s.pos, corner),
                    ..*s
                })
                .collect();
            moved.sort();
            moved
        })
        .min()
        .unwrap_or_default()
}

/// A configuration's shape without its modules' names or its placement, as text (`None` when
/// a shoe is off the grid: a joint that is not a multiple of 90 degrees).
pub(crate) fn unnamed_form(config: &RofiConfiguration) -> Option<String> {
    let shapes: Vec<Shape> = shapes_of(config)?.into_values().collect();
    let form: Vec<String> = (canonical(&shapes).iter())
        .map(|s| format!("{:?} {:?} {:?} {:?}", s.pos, s.partner, s.z, s.x_axis))
        .collect();
    // A voxel world connects every two connectors that face each other: a configuration
    // that leaves some apart is another one.
    let apart = facing_free(config)?.len();
    Some(format!("{}; {apart} facing pair(s) apart", form.join("; ")))
}

// ---------------------------------------------------------------------------------------
// Reading.

/// Whether a JSON text is voxel JSON: an object with a `bodies` field, or an array whose first
/// element is one.
pub(crate) fn is_voxel_json(text: &str) -> bool {
    let Ok(value) = serde_json::from_str::<serde_json::Value>(text) else {
        return false;
    };
    let world = match &value {
        serde_json::Value::Array(items) => items.first(),
        other => Some(other),
    };
    world.is_some_and(|w| w.get("bodies").is_some())
}

/// Reads one voxel world or an array of them (a plan), each world after the first matched to
/// the one before.
pub fn read_voxel(text: &str) -> Result<VoxelPlan, VoxelError> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| VoxelError {
        path: String::new(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    let (worlds, prefix): (Vec<serde_json::Value>, bool) = match value {
        serde_json::Value::Array(worlds) => (worlds, true),
        world => (vec![world], false),
    };
    let at = |k: usize| {
        if prefix {
            format!("[{k}]")
        } else {
            String::new()
        }
    };
    let mut bodies = Vec::with_capacity(worlds.len());
    for (k, world) in worlds.into_iter().enumerate() {
        bodies.push(read_world(world, &at(k))?);
    }
    let Some(first) = bodies.first() else {
        return Ok(VoxelPlan {
            configurations: Vec::new(),
        });
    };
    let start = configuration_of(first).map_err(|m| semantic(&at(0), m))?;
    let shape: Vec<Shape> = first.iter().map(|b| b.shape()).collect();
    if shapes_of(&start).map(|s| canonical(&s.into_values().collect::<Vec<_>>()))
        != Some(canonical(&shape))
    {
        let message = "the modules and connections this world makes do not have its shape \
                       (bodies whose joints, rotations and positions do not fit together)";
        return Err(semantic(&at(0), message.to_string()));
    }
    let mut configurations = vec![(0, start)];
    for (k, world) in bodies.iter().enumerate().skip(1) {
        let before = &configurations.last().expect("the first world").1;
        let target: Vec<Shape> = world.iter().map(|b| b.shape()).collect();
        let next = next_world(before, &target).ok_or_else(|| {
            let message = format!(
                "world {k} is not world {} with one joint turned by 90 degrees (rofi-voxel \
                 makes one such turn per step), whatever the placement of either",
                k - 1
            );
            semantic(&at(k), message)
        })?;
        configurations.push((k, next.turned));
        if let Some(joined) = next.joined {
            configurations.push((k, joined));
        }
    }
    Ok(VoxelPlan { configurations })
}

/// One world's bodies, each field checked; `at` is the world's place in the file.
fn read_world(value: serde_json::Value, at: &str) -> Result<Vec<Body>, VoxelError> {
    if !value.is_object() {
        return Err(semantic(at, "expected a voxel world (`bodies`)".into()));
    }
    let world: WorldJson = serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        semantic(&format!("{at}.{path}"), e.into_inner().to_string())
    })?;
    if world.bodies.len() > MAX_BODIES {
        let message = format!(
            "{} bodies: at most {MAX_BODIES} are read ({} modules; rofi-voxel's own grid holds \
             fewer in a line)",
            world.bodies.len(),
            MAX_BODIES / 2
        );
        return Err(semantic(&format!("{at}.bodies"), message));
    }
    if world.bodies.is_empty() {
        return Err(semantic(
            &format!("{at}.bodies"),
            "a world needs a body or more".into(),
        ));
    }
    (world.bodies.iter().enumerate())
        .map(|(i, b)| body(b, &format!("{at}.bodies[{i}]")))
        .collect()
}

/// The most bodies a world may have: matching a world to the one before costs about the
/// square of its size times the turns tried, so a hostile file stays within seconds.
const MAX_BODIES: usize = 256;

/// How far from the origin a body may be: positions stay far from overflowing once moved.
const MAX_COORDINATE: i64 = 1 << 20;

fn body(b: &BodyJson, path: &str) -> Result<Body, VoxelError> {
    let axis = match b.body_dir.axis.as_str() {
        "X" => 0,
        "Y" => 1,
        "Z" => 2,
        other => {
            let message = format!("expected an axis: \"X\", \"Y\" or \"Z\", not \"{other}\"");
            return Err(semantic(&format!("{path}.body_dir.axis"), message));
        }
    };
    if ![0, 90, -90].contains(&b.joint_pos) {
        let message = format!("expected 0, 90 or -90 (degrees), not {}", b.joint_pos);
        return Err(semantic(&format!("{path}.joint_pos"), message));
    }
    if let Some(c) = b.pos.iter().find(|c| c.abs() > MAX_COORDINATE) {
        let message = format!("{c} is beyond ±{MAX_COORDINATE}, farther than any robot reaches");
        return Err(semantic(&format!("{path}.pos"), message));
    }
    Ok(Body {
        pos: b.pos.map(|c| c as i32),
        body_dir: Direction {
            axis,
            positive: b.body_dir.is_positive,
        },
        shoe_rotated: b.shoe_rotated,
        joint_pos: b.joint_pos as i32,
    })
}

fn semantic(path: &str, message: String) -> VoxelError {
    VoxelError {
        path: path.trim_start_matches('.').to_string(),
        line: 0,
        column: 0,
        message,
    }
}

// ---------------------------------------------------------------------------------------
// One world as a configuration.

/// The configuration of one world: modules from 1 in the order of their A bodies (alpha the
/// A body's joint, beta the B body's, gamma ±90° when one of the two shoes is rotated), every
/// two connectors that face each other connected; it must have the world's shape.
fn configuration_of(bodies: &[Body]) -> Result<RofiConfiguration, String> {
    let at: BTreeMap<Cell, (usize, Body)> = bodies
        .iter()
        .enumerate()
        .map(|(i, b)| (b.pos, (i, *b)))
        .collect();
    if at.len() < bodies.len() {
        let twice = (bodies.iter().enumerate())
            .find(|(i, b)| at[&b.pos].0 != *i)
            .map_or(0, |(i, _)| i);
        return Err(format!(
            "bodies[{twice}] is at {:?}, where another body is",
            bodies[twice].pos
        ));
    }
    let mut config = RofiConfiguration::new();
    let mut sockets: BTreeMap<(Cell, Direction), (Connector, u32, Direction)> = BTreeMap::new();
    let mut paired = BTreeSet::new();
    for (i, a) in bodies
        .iter()
        .enumerate()
        .filter(|(_, b)| b.body_dir.positive)
    {
        let other = add(a.pos, a.body_dir.vector());
        let Some(&(j, b)) = at
            .get(&other)
            .filter(|(_, b)| b.body_dir == a.body_dir.opposite())
        else {
            return Err(format!(
                "bodies[{i}] points to {other:?}, where no body points back: a module is two \
                 bodies, each pointing at the other"
            ));
        };
        let id = u32::try_from(config.len() + 1).map_err(|_| "too many modules".to_string())?;
        let gamma = match (a.shoe_rotated, b.shoe_rotated) {
            (x, y) if x == y => 0.0,
            (true, _) => 90.0,
            _ => -90.0,
        };
        let module = Module::new(id, f64::from(a.joint_pos), f64::from(b.joint_pos), gamma);
        config.add_module(module).map_err(|e| e.to_string())?;
        paired.extend([i, j]);
        for (side, shoe) in [(Side::A, *a), (Side::B, b)] {
            for (dock, dir, orient) in connectors_of(&shoe) {
                sockets.insert((shoe.pos, dir), (Connector::new(side, dock), id, orient));
            }
        }
    }
    if let Some(lone) = (0..bodies.len()).find(|i| !paired.contains(i)) {
        return Err(format!(
            "bodies[{lone}] belongs to no module: no body with a positive `body_dir` points at it"
        ));
    }
    for ((pos, dir), (connector, id, orient)) in &sockets {
        if !dir.positive {
            continue;
        }
        let facing = (add(*pos, dir.vector()), dir.opposite());
        if let Some((other, other_id, other_orient)) = sockets.get(&facing) {
            let connection = Connection {
                from: (*id, *connector),
                orientation: orientation(*dir, *orient, *other_orient),
                to: (*other_id, *other),
            };
            config.connect(connection).map_err(|e| e.to_string())?;
        }
    }
    Ok(config)
}

/// A shoe's three connectors: the dock (by its index on the side), where it faces, and the
/// direction RoFI measures its orientation against.
fn connectors_of(shoe: &Body) -> [(Dock, Direction, Direction); 3] {
    let x = shoe.x_plus_direction();
    let z = shoe.z_direction();
    [
        (Dock::PlusX, x.opposite(), z.opposite()),
        (Dock::MinusX, x, z),
        (Dock::MinusZ, z, x),
    ]
}

/// The twist of two facing connectors from their orientation directions (RoFI's
/// `getConnOrientation`).
fn orientation(facing: Direction, mine: Direction, other: Direction) -> Orientation {
    if mine.axis == other.axis {
        return match mine.positive == other.positive {
            true => Orientation::North,
            false => Orientation::South,
        };
    }
    let next = (facing.axis + 1) % 3 == mine.axis;
    match facing.positive ^ next ^ (mine.positive == other.positive) {
        true => Orientation::West,
        false => Orientation::East,
    }
}

// ---------------------------------------------------------------------------------------
// The shape of a configuration.

/// Every shoe's shape in a configuration, from its kinematics (shoe A of the lowest ID at the
/// origin); `None` when the kinematics fails or a shoe is off the grid.
fn shapes_of(config: &RofiConfiguration) -> Option<BTreeMap<Shoe, Shape>> {
    shapes_placed(config, &poses(config).ok()?)
}

/// Every shoe's shape at the poses the kinematics found for `config`.
fn shapes_placed(
    config: &RofiConfiguration,
    placed: &crate::kinematics::Poses,
) -> Option<BTreeMap<Shoe, Shape>> {
    let all: BTreeMap<Shoe, Matrix4<f64>> = config
        .modules()
        .flat_map(|m| [(m.id, Side::A), (m.id, Side::B)])
        .map(|shoe| placed.pose(shoe).map(|p| (shoe, *p)))
        .collect::<Option<_>>()?;
    shapes_at(&all)
}

/// The shapes of shoes at `poses` (both shoes of each module present).
fn shapes_at(poses: &BTreeMap<Shoe, Matrix4<f64>>) -> Option<BTreeMap<Shoe, Shape>> {
    poses
        .iter()
        .map(|(&(id, side), pose)| {
            let partner = poses.get(&(id, side.other()))?;
            let pos = on_grid(&centre(pose))?;
            let shape = Shape {
                pos,
                partner: sub(on_grid(&centre(partner))?, pos),
                z: on_grid(&facing(pose, Dock::MinusZ))?,
                x_axis: on_grid(&facing(pose, Dock::MinusX))?.map(i32::abs),
            };
            Some(((id, side), shape))
        })
        .collect()
}

fn centre(pose: &Matrix4<f64>) -> Vector3<f64> {
    Vector3::new(pose[(0, 3)], pose[(1, 3)], pose[(2, 3)])
}

/// Where a dock of a shoe at `pose` faces.
fn facing(pose: &Matrix4<f64>, dock: Dock) -> Vector3<f64> {
    let out = pose * face_to_dock(dock) * Vector4::new(0.0, 0.0, -1.0, 0.0);
    Vector3::new(out.x, out.y, out.z)
}

/// How far from the grid a position found by the kinematics may be.
const GRID_TOLERANCE: f64 = 1e-6;

fn on_grid(v: &Vector3<f64>) -> Option<Cell> {
    let cell = [v.x, v.y, v.z].map(f64::round);
    let close = (0..3).all(|i| (v[i] - cell[i]).abs() <= GRID_TOLERANCE);
    close.then(|| cell.map(|c| c as i32))
}

// ---------------------------------------------------------------------------------------
// One step of a plan.

/// World k as reached from world k − 1: the configuration after the turn (the connections it
/// cuts gone), and, when the turn ends with connectors facing each other, the same with them
/// connected.
struct Next {
    turned: RofiConfiguration,
    joined: Option<RofiConfiguration>,
}

/// How world k − 1 (`before`) becomes the world of shape `target` with one ±90° turn.
fn next_world(before: &RofiConfiguration, target: &[Shape]) -> Option<Next> {
    let placed = poses(before).ok()?;
    let shapes = shapes_placed(before, &placed)?;
    let want = canonical(target);
    let placements: Vec<BTreeMap<Cell, Shape>> = (alignments(&shapes, target, before.len()))
        .into_iter()
        .map(|(turn, by)| {
            (target.iter())
                .map(|s| s.rotated(&turn, by))
                .map(|s| (s.pos, s))
                .collect()
        })
        .collect();
    // Turns outermost, in the order of the modules' IDs: a symmetric robot whose world can
    // be reached by several turns gets the first, whatever the placement of the world.
    for candidate in moves(before) {
        for seen in &placements {
            let Some(turned) = try_move(before, &placed, &shapes, seen, candidate) else {
                continue;
            };
            if shapes_of(&turned).map(|s| canonical(&s.into_values().collect::<Vec<_>>()))
                == Some(want.clone())
            {
                return Some(Next {
                    joined: joined(&turned),
                    turned,
                });
            }
        }
    }
    None
}

/// The placements of the target world that put many of its shoes where `before`'s are, as
/// they are (the side of a turn that stays, up to its pivot shoe): most shoes first.
fn alignments(
    shapes: &BTreeMap<Shoe, Shape>,
    target: &[Shape],
    modules: usize,
) -> Vec<(Turn24, Cell)> {
    let mut by_directions: BTreeMap<(Cell, Cell, Cell), Vec<Cell>> = BTreeMap::new();
    for s in shapes.values() {
        by_directions.entry(s.directions()).or_default().push(s.pos);
    }
    let turns = Turn24::all();
    let mut votes: BTreeMap<(usize, Cell), usize> = BTreeMap::new();
    for (r, turn) in turns.iter().enumerate() {
        for t in target {
            let turned = t.rotated(turn, [0; 3]);
            for pos in by_directions
                .get(&turned.directions())
                .into_iter()
                .flatten()
            {
                *votes.entry((r, sub(*pos, turned.pos))).or_default() += 1;
            }
        }
    }
    // The larger side of a turn holds at least one shoe of each module but its pivot.
    let least = modules.saturating_sub(1).max(1);
    let mut ranked: Vec<((usize, Cell), usize)> =
        votes.into_iter().filter(|(_, n)| *n >= least).collect();
    ranked.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    ranked.truncate(MAX_ALIGNMENTS);
    ranked
        .into_iter()
        .map(|((r, by), _)| (turns[r], by))
        .collect()
}

/// How many placements of a world are tried against the one before it: a symmetric world
/// has several that keep most of its shoes in place.
const MAX_ALIGNMENTS: usize = 96;

/// A turn to try: the module, the joint and by how much, and which side stays where it is.
#[derive(Clone, Copy, Debug)]
struct Move {
    module: u32,
    joint: Joint,
    by: f64,
    b_side_stays: bool,
}

/// Every ±90° turn of `config` within the joints' limits, each with either side staying.
fn moves(config: &RofiConfiguration) -> Vec<Move> {
    let mut out = Vec::new();
    for m in config.modules() {
        for joint in Joint::ALL {
            for by in [90.0, -90.0] {
                let to = m.joint(joint) + by;
                if joint != Joint::Gamma && to.abs() > crate::module::SHOE_JOINT_LIMIT_DEG {
                    continue;
                }
                for b_side_stays in [false, true] {
                    out.push(Move {
                        module: m.id,
                        joint,
                        by,
                        b_side_stays,
                    });
                }
            }
        }
    }
    out
}

/// `before` with `candidate` done, when the shoes it moves and those it leaves are each where
/// `seen` (the target, placed) has them and each side stays connected; the connections
/// between the sides are cut.
fn try_move(
    before: &RofiConfiguration,
    placed: &crate::kinematics::Poses,
    shapes: &BTreeMap<Shoe, Shape>,
    seen: &BTreeMap<Cell, Shape>,
    candidate: Move,
) -> Option<RofiConfiguration> {
    let module = *before.module(candidate.module)?;
    let motion = relative_motion(placed, &module, candidate)?;
    let (stays, moves_with) = match candidate.b_side_stays {
        false => ((module.id, Side::A), (module.id, Side::B)),
        true => ((module.id, Side::B), (module.id, Side::A)),
    };
    let moved = |shoe: Shoe| placed.pose(shoe).map(|p| motion * p);
    // The turned module's own shoes: one stays, one moves, each must be where the target has it.
    let mut pair = BTreeMap::new();
    pair.insert(stays, *placed.pose(stays)?);
    pair.insert(moves_with, moved(moves_with)?);
    let own = shapes_at(&pair)?;
    if own.values().any(|s| seen.get(&s.pos) != Some(s)) {
        return None;
    }
    let mut moving = BTreeSet::new();
    let mut staying = BTreeSet::new();
    for m in before.modules().filter(|m| m.id != module.id) {
        let shoes = [(m.id, Side::A), (m.id, Side::B)];
        let kept = shoes
            .iter()
            .all(|s| seen.get(&shapes[s].pos) == Some(&shapes[s]));
        let mut pair = BTreeMap::new();
        for s in shoes {
            pair.insert(s, moved(s)?);
        }
        let carried = shapes_at(&pair)?
            .values()
            .all(|s| seen.get(&s.pos) == Some(s));
        match (kept, carried) {
            (true, false) => staying.insert(m.id),
            (false, true) => moving.insert(m.id),
            // A module the turn could leave or carry (a symmetric one) goes with its neighbours.
            (true, true) => continue,
            (false, false) => return None,
        };
    }
    sides(before, module.id, stays.1, &mut staying, &mut moving)?;
    let side_of = |(id, c): crate::module::Port| match id == module.id {
        true => c.side() != stays.1,
        false => moving.contains(&id),
    };
    let kept: Vec<Connection> = (before.connections().iter())
        .filter(|c| side_of(c.from) == side_of(c.to))
        .copied()
        .collect();
    let modules: Vec<Module> = before.modules().copied().collect();
    let mut turned = RofiConfiguration::from_parts(&modules, &kept).ok()?;
    turned.set_joint(
        module.id,
        candidate.joint,
        module.joint(candidate.joint) + candidate.by,
    );
    Some(turned)
}

/// The rigid motion the turn gives the side that moves, in the frame of `placed`.
fn relative_motion(
    placed: &crate::kinematics::Poses,
    module: &Module,
    candidate: Move,
) -> Option<Matrix4<f64>> {
    let a = *placed.pose((module.id, Side::A))?;
    let b = *placed.pose((module.id, Side::B))?;
    let radians = candidate.by.to_radians();
    // From shoe A, shoe B is A·Rx(α)·Rz(γ)·T(0,0,1)·Ry(π)·Rx(−β): each joint's change turns
    // the B side about that joint's axis.
    let carries_b = match candidate.joint {
        Joint::Alpha => a * rotation(Vector3::x(), radians) * a.try_inverse()?,
        Joint::Beta => b * rotation(Vector3::x(), -radians) * b.try_inverse()?,
        Joint::Gamma => {
            let body = a * rotation(Vector3::x(), module.alpha.to_radians());
            body * rotation(Vector3::z(), radians) * body.try_inverse()?
        }
    };
    match candidate.b_side_stays {
        false => Some(carries_b),
        true => carries_b.try_inverse(),
    }
}

fn rotation(axis: Vector3<f64>, radians: f64) -> Matrix4<f64> {
    Rotation3::from_axis_angle(&Unit::new_normalize(axis), radians).to_homogeneous()
}

/// Settles the modules the target places either way by the side of the connections they
/// have, then checks that each side is connected on its own; `None` when it is not.
fn sides(
    config: &RofiConfiguration,
    turned: u32,
    staying_side: Side,
    staying: &mut BTreeSet<u32>,
    moving: &mut BTreeSet<u32>,
) -> Option<()> {
    let graph = shoe_graph(config, turned);
    let stay_root = (turned, staying_side);
    let move_root = (turned, staying_side.other());
    let undecided: Vec<u32> = (config.modules().map(|m| m.id))
        .filter(|id| !staying.contains(id) && !moving.contains(id) && *id != turned)
        .collect();
    // Reach each side from the turned module's shoe on it, through modules of that side or
    // undecided ones; an undecided module reached from one side only joins it.
    let from_stay = reach(&graph, stay_root, |id| {
        id == turned || !moving.contains(&id)
    });
    let from_move = reach(&graph, move_root, |id| {
        id == turned || !staying.contains(&id)
    });
    for m in undecided {
        match (from_stay.contains(&m), from_move.contains(&m)) {
            (true, false) => staying.insert(m),
            (false, true) => moving.insert(m),
            _ => return None,
        };
    }
    let stay_only = reach(&graph, stay_root, |id| {
        id == turned || staying.contains(&id)
    });
    let move_only = reach(&graph, move_root, |id| id == turned || moving.contains(&id));
    let all_staying = staying.iter().all(|id| stay_only.contains(id));
    let all_moving = moving.iter().all(|id| move_only.contains(id));
    (all_staying && all_moving).then_some(())
}

/// The modules' shoes joined by their connections and by each module's own joints, but the
/// turned module's two shoes not joined to each other.
fn shoe_graph(config: &RofiConfiguration, turned: u32) -> BTreeMap<Shoe, Vec<Shoe>> {
    let mut graph: BTreeMap<Shoe, Vec<Shoe>> = BTreeMap::new();
    let mut join = |a: Shoe, b: Shoe| {
        graph.entry(a).or_default().push(b);
        graph.entry(b).or_default().push(a);
    };
    for m in config.modules().filter(|m| m.id != turned) {
        join((m.id, Side::A), (m.id, Side::B));
    }
    for c in config.connections() {
        join((c.from.0, c.from.1.side()), (c.to.0, c.to.1.side()));
    }
    graph
}

/// The modules reached from `root` through shoes of modules `allowed` lets through.
fn reach(
    graph: &BTreeMap<Shoe, Vec<Shoe>>,
    root: Shoe,
    allowed: impl Fn(u32) -> bool,
) -> BTreeSet<u32> {
    let mut seen = BTreeSet::from([root]);
    let mut stack = vec![root];
    while let Some(shoe) = stack.pop() {
        for &next in graph.get(&shoe).into_iter().flatten() {
            if allowed(next.0) && next.0 != root.0 && seen.insert(next) {
                stack.push(next);
            }
        }
    }
    seen.into_iter().map(|(id, _)| id).collect()
}

/// `config` with every two free connectors that face each other connected, when there are
/// any (what a voxel world means: the end of a turn latches what it brings together).
fn joined(config: &RofiConfiguration) -> Option<RofiConfiguration> {
    let mut out = config.clone();
    let facing = facing_free(config)?;
    for connection in &facing {
        out.connect(*connection).ok()?;
    }
    (!facing.is_empty()).then_some(out)
}

/// The connections two free connectors that face each other would make.
fn facing_free(config: &RofiConfiguration) -> Option<Vec<Connection>> {
    let placed = poses(config).ok()?;
    let mut sockets: BTreeMap<(Cell, Cell), (u32, Connector)> = BTreeMap::new();
    for m in config.modules() {
        for index in 0..Connector::COUNT {
            let connector = Connector::from_index(index)?;
            if config.connection_at((m.id, connector)).is_some() {
                continue;
            }
            let pose = placed.pose((m.id, connector.side()))?;
            let (pos, dir) = (
                on_grid(&centre(pose))?,
                on_grid(&facing(pose, connector.dock()))?,
            );
            sockets.insert((pos, dir), (m.id, connector));
        }
    }
    let mut out = Vec::new();
    for (&(pos, dir), &(id, connector)) in &sockets {
        let facing_back = (add(pos, dir), dir.map(|c| -c));
        let Some(&(other, other_connector)) = sockets.get(&facing_back) else {
            continue;
        };
        if (id, connector) > (other, other_connector) || id == other {
            continue;
        }
        let from = placed.pose((id, connector.side()))?;
        let to = placed.pose((other, other_connector.side()))?;
        let twist = (0..4u8).find(|&q| {
            let there = from * across_connection(connector.dock(), q, other_connector.dock());
            (there - to).abs().max() <= crate::tree::LOOP_TOLERANCE
        })?;
        let connection = Connection {
            from: (id, connector),
            orientation: Orientation::ALL[usize::from(twist)],
            to: (other, other_connector),
        };
        out.push(connection);
    }
    Some(out)
}
