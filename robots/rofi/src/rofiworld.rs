//! RoFI's JSON configurations (RofiWorld: `modules`, `moduleJoints`, `spaceJoints`), one world
//! or an array of them (a plan), read into [`RofiConfiguration`]s; an error names the field
//! by its JSON path (`[1].moduleJoints[0].from.connector`) and what was expected.
//!
//! Connectors are numbered as in the old format; RofiWorld names them "A-X", "A+X", "A-Z",
//! "B-X", "B+X", "B-Z" for 0 to 5 (its ±X names are the old format's swapped: only the
//! numbers carry the geometry). Space joints fix a module in space; the kinematics here needs
//! only relative poses, so they are read and checked (they must name a known module) but
//! their placement is not used. Fields RoFI may add beside these are ignored.

use crate::module::{Connection, Connector, Module, Orientation, RofiConfiguration};
use serde::Deserialize;
use std::fmt;

/// Why a RofiWorld file cannot be read: the JSON path of the field (empty for the whole
/// file), its line and column when the JSON itself is wrong, and what was expected.
#[derive(Clone, Debug, PartialEq)]
pub struct RofiWorldError {
    pub path: String,
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl fmt::Display for RofiWorldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = if self.path.is_empty() {
            String::new()
        } else {
            format!(" at `{}`", self.path)
        };
        write!(
            f,
            "line {}, column {}{at}: {}",
            self.line, self.column, self.message
        )
    }
}

impl std::error::Error for RofiWorldError {}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct World {
    modules: Vec<WorldModule>,
    #[serde(default)]
    module_joints: Vec<ModuleJoint>,
    #[serde(default)]
    space_joints: Vec<SpaceJoint>,
}

#[derive(Deserialize)]
struct WorldModule {
    id: u32,
    #[serde(rename = "type")]
    kind: String,
    // Optional so that a module of another kind (a pad has `width` and `height`) is refused
    // for its kind, not for a missing angle.
    alpha: Option<f64>,
    beta: Option<f64>,
    gamma: Option<f64>,
}

#[derive(Deserialize)]
struct ModuleJoint {
    orientation: String,
    from: End,
    to: End,
}

#[derive(Deserialize)]
struct End {
    id: u32,
    connector: ConnectorName,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum ConnectorName {
    Index(u8),
    Name(String),
}

#[derive(Deserialize)]
struct SpaceJoint {
    to: SpaceEnd,
}

#[derive(Deserialize)]
struct SpaceEnd {
    id: u32,
}

/// Reads one RofiWorld (one configuration) or an array of them (a plan, in order).
pub fn read_rofiworld(text: &str) -> Result<Vec<RofiConfiguration>, RofiWorldError> {
    // The syntax first, where serde knows the line and column; then each world's fields,
    // where it knows the path.
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| RofiWorldError {
        path: String::new(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    match value {
        serde_json::Value::Array(worlds) => (worlds.into_iter().enumerate())
            .map(|(i, world)| read_world(world, &format!("[{i}]")))
            .collect(),
        world => Ok(vec![read_world(world, "")?]),
    }
}

/// One world's configuration; `at` is its place in the file.
fn read_world(value: serde_json::Value, at: &str) -> Result<RofiConfiguration, RofiWorldError> {
    if !value.is_object() {
        let message = "expected a RofiWorld object (`modules`, `moduleJoints`, `spaceJoints`)";
        return Err(semantic(at, message.to_string()));
    }
    let world: World = serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        semantic(&format!("{at}.{path}"), e.into_inner().to_string())
    })?;
    configuration(&world, at)
}

/// One world's configuration; `at` is its place in the file (`[3]`, or empty for one world).
fn configuration(world: &World, at: &str) -> Result<RofiConfiguration, RofiWorldError> {
    let mut config = RofiConfiguration::new();
    for (i, m) in world.modules.iter().enumerate() {
        let path = format!("{at}.modules[{i}]");
        if m.kind != "universal" {
            let message = format!(
                "module {} is of type \"{}\": only universal modules (\"universal\") are known \
                 (RoFI's pads and other module kinds are not modelled)",
                m.id, m.kind
            );
            return Err(semantic(&format!("{path}.type"), message));
        }
        let module = Module {
            id: m.id,
            alpha: angle(m.alpha, &path, "alpha")?,
            beta: angle(m.beta, &path, "beta")?,
            gamma: angle(m.gamma, &path, "gamma")?,
        };
        config
            .add_module(module)
            .map_err(|e| semantic(&path, e.to_string()))?;
    }
    for (i, joint) in world.module_joints.iter().enumerate() {
        let path = format!("{at}.moduleJoints[{i}]");
        let connection = Connection {
            from: (
                joint.from.id,
                connector(&joint.from.connector, &path, "from")?,
            ),
            orientation: orientation(&joint.orientation, &path)?,
            to: (joint.to.id, connector(&joint.to.connector, &path, "to")?),
        };
        config
            .connect(connection)
            .map_err(|e| semantic(&path, e.to_string()))?;
    }
    for (i, space) in world.space_joints.iter().enumerate() {
        if config.module(space.to.id).is_none() {
            let path = format!("{at}.spaceJoints[{i}].to.id");
            let message = format!("no module {} in this world", space.to.id);
            return Err(semantic(&path, message));
        }
    }
    Ok(config)
}

/// A field at `path` that does not read or breaks a rule (no line: the text is parsed).
/// A universal module's joint angle, which RofiWorld requires.
fn angle(value: Option<f64>, path: &str, joint: &str) -> Result<f64, RofiWorldError> {
    value.ok_or_else(|| {
        let message = format!("missing field `{joint}` (a universal module's angle in degrees)");
        semantic(&format!("{path}.{joint}"), message)
    })
}

fn semantic(path: &str, message: String) -> RofiWorldError {
    RofiWorldError {
        path: path.trim_start_matches('.').to_string(),
        line: 0,
        column: 0,
        message,
    }
}

const CONNECTOR_NAMES: [&str; 6] = ["A-X", "A+X", "A-Z", "B-X", "B+X", "B-Z"];

fn connector(name: &ConnectorName, path: &str, end: &str) -> Result<Connector, RofiWorldError> {
    let index = match name {
        ConnectorName::Index(k) => Some(*k),
        ConnectorName::Name(text) => (CONNECTOR_NAMES.iter())
            .position(|n| n == text)
            .and_then(|k| u8::try_from(k).ok()),
    };
    index.and_then(Connector::from_index).ok_or_else(|| {
        let message = format!(
            "expected a connector: 0 to 5 or one of {}",
            CONNECTOR_NAMES.join(", ")
        );
        semantic(&format!("{path}.{end}.connector"), message)
    })
}

fn orientation(text: &str, path: &str) -> Result<Orientation, RofiWorldError> {
    let names = [
        ("North", Orientation::North),
        ("East", Orientation::East),
        ("South", Orientation::South),
        ("West", Orientation::West),
    ];
    let found = names
        .iter()
        .find(|(name, _)| text == *name || text == &name[..1]);
    found.map(|(_, o)| *o).ok_or_else(|| {
        let message = format!(
            "expected an orientation: North, East, South, West (or N, E, S, W), not \"{text}\""
        );
        semantic(&format!("{path}.orientation"), message)
    })
}
