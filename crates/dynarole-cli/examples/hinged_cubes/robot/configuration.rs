//! A validated configuration of hinged cubes and its data file: the shared top level of
//! `dynarole_world::file_format` with one record per cube,
//! `{"name", "id", "cell": [x, y], "heading": [dx, dy], "hinge": deg}`, read field by field
//! (every error naming its field path) and written back in the same layout.

use super::FILE_TAG;
use dynarole_world::file_format::{check_id, object, read_document, write_document};
use dynarole_world::geometry::{Rotation, Vec3, MAX_COORDINATE};
use dynarole_world::{ConfigError, Metadata, NamedConnection, Port};
use serde_json::{json, Map, Value};
use std::collections::{BTreeMap, BTreeSet};

/// A square cell of the plane, or a direction in it.
pub type Cell = [i32; 2];

/// The male connector, on the hinged front face.
pub const FRONT: u8 = 0;
/// The female connector, on the back face.
pub const BACK: u8 = 1;
/// Connectors of every cube.
pub const CONNECTOR_COUNT: u8 = 2;
/// Metres per cell (a cube's edge): the data file's `lattice_unit_m`.
pub const CELL_M: f64 = 0.05;
/// The hinge angles a cube takes, in degrees.
pub const HINGE_ANGLES: [i32; 3] = [-90, 0, 90];

/// The fields of a cube's record, in the order the writer puts them.
const FIELDS: [&str; 5] = ["name", "id", "cell", "heading", "hinge"];

/// One cube: its name and ID, its cell, the way its body faces (its back connector faces the
/// other way) and its hinge angle (counterclockwise positive).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Cube {
    pub name: String,
    pub id: Option<u32>,
    pub cell: Cell,
    pub heading: Cell,
    pub hinge: i32,
}

/// Cubes on distinct cells, with unique names and IDs, and their latches (male front first),
/// each joining a front and a back face that touch.
#[derive(Clone, Debug, PartialEq)]
pub struct CubesConfiguration {
    pub(super) metadata: Metadata,
    pub(super) cubes: Vec<Cube>,
    pub(super) latches: BTreeSet<(Port, Port)>,
}

/// `v` turned counterclockwise by `degrees` (a multiple of 90).
pub fn turned(v: Cell, degrees: i32) -> Cell {
    let mut v = v;
    for _ in 0..(degrees / 90).rem_euclid(4) {
        v = [-v[1], v[0]];
    }
    v
}

pub fn plus(a: Cell, b: Cell) -> Cell {
    [a[0] + b[0], a[1] + b[1]]
}

pub fn minus(a: Cell, b: Cell) -> Cell {
    [a[0] - b[0], a[1] - b[1]]
}

/// Counterclockwise quarter turns from +x to the unit direction `heading`.
pub fn quarters(heading: Cell) -> i32 {
    (0..4)
        .find(|q| turned([1, 0], 90 * q) == heading)
        .unwrap_or(0)
}

/// Reads a configuration file of this robot (its `robot` field already checked).
pub(super) fn read(text: &str) -> Result<CubesConfiguration, ConfigError> {
    let (metadata, cubes, connections) =
        read_document::<Value, _>(text, CELL_M, CONNECTOR_COUNT, cube)?;
    CubesConfiguration::new(metadata, cubes, &connections)
}

/// Builds cube `i` from its record, naming the field of anything wrong.
fn cube(i: usize, record: Value) -> Result<Cube, ConfigError> {
    let at = |field: &str| format!("modules[{i}].{field}");
    let Value::Object(fields) = record else {
        return Err(ConfigError::new(
            format!("modules[{i}]"),
            "expected a cube record (an object)",
        ));
    };
    if let Some(unknown) = fields.keys().find(|k| !FIELDS.contains(&k.as_str())) {
        let expected = FIELDS.join(", ");
        return Err(ConfigError::new(
            at(unknown),
            format!("unknown field; expected {expected}"),
        ));
    }
    let name = required(&fields, "name", &at)?
        .as_str()
        .filter(|n| !n.is_empty())
        .ok_or_else(|| ConfigError::new(at("name"), "expected a non-empty string"))?;
    Ok(Cube {
        name: name.to_string(),
        id: check_id(i, id(&fields, &at)?)?,
        cell: cell(required(&fields, "cell", &at)?, &at("cell"))?,
        heading: heading(required(&fields, "heading", &at)?, &at("heading"))?,
        hinge: hinge(required(&fields, "hinge", &at)?, &at("hinge"))?,
    })
}

/// The field `field` of a record, which must be there.
fn required<'a>(
    fields: &'a Map<String, Value>,
    field: &str,
    at: &dyn Fn(&str) -> String,
) -> Result<&'a Value, ConfigError> {
    fields
        .get(field)
        .ok_or_else(|| ConfigError::new(at(field), "missing field"))
}

/// The optional `id`: a whole number that fits 32 bits (the range is `check_id`'s).
fn id(
    fields: &Map<String, Value>,
    at: &dyn Fn(&str) -> String,
) -> Result<Option<u32>, ConfigError> {
    match fields.get("id") {
        None | Some(Value::Null) => Ok(None),
        Some(v) => v
            .as_u64()
            .and_then(|id| u32::try_from(id).ok())
            .map(Some)
            .ok_or_else(|| {
                ConfigError::new(at("id"), format!("expected a whole number, found {v}"))
            }),
    }
}

/// `[x, y]`, two whole numbers within the coordinate bounds.
fn pair(value: &Value, path: &str) -> Result<Cell, ConfigError> {
    let bad = || {
        ConfigError::new(
            path,
            format!("expected [x, y], two whole numbers within +-{MAX_COORDINATE}, found {value}"),
        )
    };
    let items = value.as_array().filter(|a| a.len() == 2).ok_or_else(bad)?;
    let mut out = [0; 2];
    for (o, item) in out.iter_mut().zip(items) {
        *o = item
            .as_i64()
            .and_then(|c| i32::try_from(c).ok())
            .filter(|c| c.abs() <= MAX_COORDINATE)
            .ok_or_else(bad)?;
    }
    Ok(out)
}

fn cell(value: &Value, path: &str) -> Result<Cell, ConfigError> {
    pair(value, path)
}

/// One of the four unit directions of the plane.
fn heading(value: &Value, path: &str) -> Result<Cell, ConfigError> {
    let h = pair(value, path)?;
    if h[0].abs() + h[1].abs() == 1 {
        Ok(h)
    } else {
        Err(ConfigError::new(
            path,
            format!("{h:?} is not a direction; expected [1, 0], [0, 1], [-1, 0] or [0, -1]"),
        ))
    }
}

fn hinge(value: &Value, path: &str) -> Result<i32, ConfigError> {
    value
        .as_i64()
        .and_then(|h| i32::try_from(h).ok())
        .filter(|h| HINGE_ANGLES.contains(h))
        .ok_or_else(|| {
            ConfigError::new(
                path,
                format!("expected -90, 0 or 90 (degrees), found {value}"),
            )
        })
}

impl CubesConfiguration {
    /// Validates the cubes and their latches (error paths as in the data file).
    pub fn new(
        metadata: Metadata,
        cubes: Vec<Cube>,
        connections: &[NamedConnection],
    ) -> Result<CubesConfiguration, ConfigError> {
        check_cubes(&cubes)?;
        let mut config = CubesConfiguration {
            metadata,
            cubes,
            latches: BTreeSet::new(),
        };
        for (k, connection) in connections.iter().enumerate() {
            let latch = config.latch_of(k, connection)?;
            config.latches.insert(latch);
        }
        Ok(config)
    }

    /// Connection `k` as a latch (male first): both cubes known, one front and one back,
    /// touching, neither already latched.
    fn latch_of(
        &self,
        k: usize,
        (a, ca, b, cb): &NamedConnection,
    ) -> Result<(Port, Port), ConfigError> {
        let port = |name: &str, connector: u8, field: usize| {
            self.module_index(name)
                .map(|module| Port { module, connector })
                .ok_or_else(|| {
                    ConfigError::new(
                        format!("connections[{k}][{field}]"),
                        format!("no cube is called {name:?}"),
                    )
                })
        };
        let (pa, pb) = (port(a, *ca, 0)?, port(b, *cb, 2)?);
        let at = format!("connections[{k}]");
        let (male, female) = match (*ca, *cb) {
            (FRONT, BACK) => (pa, pb),
            (BACK, FRONT) => (pb, pa),
            _ => {
                return Err(ConfigError::new(
                    at,
                    "a latch joins a front connector (0) and a back connector (1)",
                ))
            }
        };
        if self.touching(male) != Some(female) {
            return Err(ConfigError::new(
                at,
                format!("{a}.C{ca} and {b}.C{cb} do not face each other"),
            ));
        }
        if let Some(p) = [male, female]
            .into_iter()
            .find(|p| self.latched(*p).is_some())
        {
            return Err(ConfigError::new(
                at,
                format!("{} is latched twice", self.port_label(p)),
            ));
        }
        Ok((male, female))
    }

    /// The descriptive fields.
    pub fn metadata(&self) -> &Metadata {
        &self.metadata
    }

    /// Index of the cube called `name`.
    pub fn module_index(&self, name: &str) -> Option<usize> {
        self.cubes.iter().position(|c| c.name == name)
    }

    /// Where connector `connector` of cube `m` points.
    pub fn direction(&self, m: usize, connector: u8) -> Option<Cell> {
        let cube = self.cubes.get(m)?;
        match connector {
            FRONT => Some(turned(cube.heading, cube.hinge)),
            BACK => Some(turned(cube.heading, 180)),
            _ => None,
        }
    }

    /// The connector of the cube on the cell `port` points at, if that one points back.
    pub fn touching(&self, port: Port) -> Option<Port> {
        let here = self.cubes.get(port.module)?.cell;
        let there = plus(here, self.direction(port.module, port.connector)?);
        let other = self.cubes.iter().position(|c| c.cell == there)?;
        [FRONT, BACK]
            .into_iter()
            .find(|c| self.direction(other, *c).map(|d| plus(there, d)) == Some(here))
            .map(|connector| Port {
                module: other,
                connector,
            })
    }

    /// The port latched to `port`.
    pub fn latched(&self, port: Port) -> Option<Port> {
        self.latches.iter().find_map(|(a, b)| {
            if *a == port {
                Some(*b)
            } else if *b == port {
                Some(*a)
            } else {
                None
            }
        })
    }

    /// `M3.C0`, for messages.
    pub fn port_label(&self, port: Port) -> String {
        let cube = self.cubes.get(port.module).map_or("?", |c| c.name.as_str());
        format!("{cube}.C{}", port.connector)
    }

    /// The latches as names, male first, in latch order.
    pub fn named_connections(&self) -> Vec<NamedConnection> {
        let name = |p: &Port| self.cubes[p.module].name.clone();
        self.latches
            .iter()
            .map(|(m, f)| (name(m), m.connector, name(f), f.connector))
            .collect()
    }

    /// One line per cube: name, cell, heading and hinge.
    pub fn module_lines(&self) -> Vec<String> {
        self.cubes
            .iter()
            .map(|c| {
                let heading = heading_name(c.heading);
                format!(
                    "{:<6} at {:?} heading {heading} hinge {} deg",
                    c.name, c.cell, c.hinge
                )
            })
            .collect()
    }

    /// The whole chain turned about z and shifted in the plane; a rotation or shift that
    /// leaves the plane (z = 0, up along +z) is refused, as the chain has no such pose.
    pub fn transformed(
        &self,
        rotation: Rotation,
        translation: Vec3,
    ) -> Result<CubesConfiguration, ConfigError> {
        if rotation.apply([0, 0, 1]) != [0, 0, 1] {
            return Err(ConfigError::new(
                "rotation",
                "a chain of cubes only turns about z (its plane's normal)",
            ));
        }
        if translation[2] != 0 || translation.iter().any(|c| c.abs() > MAX_COORDINATE) {
            return Err(ConfigError::new(
                "translation",
                "a chain of cubes only moves within its plane (z = 0)",
            ));
        }
        let x = rotation.apply([1, 0, 0]);
        let quarter_turns = quarters([x[0], x[1]]);
        let cubes = self
            .cubes
            .iter()
            .map(|c| Cube {
                cell: plus(
                    turned(c.cell, 90 * quarter_turns),
                    [translation[0], translation[1]],
                ),
                heading: turned(c.heading, 90 * quarter_turns),
                ..c.clone()
            })
            .collect();
        CubesConfiguration::new(self.metadata.clone(), cubes, &self.named_connections())
    }

    /// Writes the configuration in its data-file format.
    pub fn to_json_string(&self) -> String {
        let modules: Vec<String> = self.cubes.iter().map(cube_value).collect();
        write_document(
            FILE_TAG,
            CELL_M,
            &modules,
            &self.named_connections(),
            &self.metadata,
        )
    }
}

/// Names unique, IDs unique, one cube per cell, at least one cube.
fn check_cubes(cubes: &[Cube]) -> Result<(), ConfigError> {
    if cubes.is_empty() {
        return Err(ConfigError::new("modules", "expected at least one cube"));
    }
    let mut seen: [BTreeMap<String, usize>; 3] = Default::default();
    for (i, c) in cubes.iter().enumerate() {
        let keys = [
            ("name", Some(c.name.clone())),
            ("id", c.id.map(|id| id.to_string())),
            ("cell", Some(format!("{:?}", c.cell))),
        ];
        for ((field, key), seen) in keys.into_iter().zip(seen.iter_mut()) {
            let Some(key) = key else { continue };
            if let Some(first) = seen.insert(key.clone(), i) {
                return Err(ConfigError::new(
                    format!("modules[{i}].{field}"),
                    format!("{key} is also the {field} of modules[{first}]"),
                ));
            }
        }
    }
    Ok(())
}

/// `+x`, `-y`, ...: a heading as its axis.
pub fn heading_name(heading: Cell) -> String {
    dynarole_world::geometry::axis_name([heading[0], heading[1], 0])
}

fn cube_value(c: &Cube) -> String {
    object(vec![
        ("name", Some(json!(c.name))),
        ("id", c.id.map(|id| json!(id))),
        ("cell", Some(json!(c.cell))),
        ("heading", Some(json!(c.heading))),
        ("hinge", Some(json!(c.hinge))),
    ])
}
