//! dynarole's own data file for RoFI (`rofi.schema.json`): named modules with their three
//! joints in degrees, and connections as `[module, connector, module, connector, twist]`;
//! read with every error naming its field, and written back one module and one connection
//! per line like the other robots' files.

use crate::module::{Connection, Connector, Module, Orientation, RofiConfiguration};
use crate::robot::{whole, RofiRobot};
use dynarole_world::file_format::{deserialize, list, object};
use dynarole_world::{ConfigError, Metadata};
use serde::Deserialize;
use serde_json::json;
use std::collections::BTreeMap;

/// The `robot` field of dynarole's RoFI files.
pub const FILE_TAG: &str = "ROFI";

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RofiFile {
    name: String,
    #[allow(dead_code)]
    robot: String,
    source: Option<String>,
    modules: Vec<ModuleRecord>,
    connections: Vec<(String, i64, String, i64, String)>,
    note: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModuleRecord {
    name: Option<String>,
    id: u32,
    alpha: i64,
    beta: i64,
    gamma: i64,
}

/// Reads one of dynarole's RoFI files (its `robot` field already matched).
pub(crate) fn read(text: &str) -> Result<RofiRobot, ConfigError> {
    let file: RofiFile = deserialize(text)?;
    let mut config = RofiConfiguration::new();
    let mut names = BTreeMap::new();
    let mut by_name = BTreeMap::new();
    for (i, record) in file.modules.iter().enumerate() {
        let [alpha, beta, gamma] = [record.alpha, record.beta, record.gamma].map(|d| d as f64);
        let module = Module::new(record.id, alpha, beta, gamma);
        config
            .add_module(module)
            .map_err(|e| ConfigError::new(format!("modules[{i}]"), e.to_string()))?;
        let name = record
            .name
            .clone()
            .unwrap_or_else(|| format!("M{}", record.id));
        if by_name.insert(name.clone(), record.id).is_some() {
            return Err(ConfigError::new(
                format!("modules[{i}].name"),
                format!("\"{name}\" names two modules"),
            ));
        }
        names.insert(record.id, name);
    }
    for (k, raw) in file.connections.iter().enumerate() {
        let connection = connection(k, raw, &by_name)?;
        config
            .connect(connection)
            .map_err(|e| ConfigError::new(format!("connections[{k}]"), e.to_string()))?;
    }
    let metadata = Metadata {
        name: file.name,
        source: file.source,
        note: file.note,
        ..Metadata::default()
    };
    RofiRobot::new(config, &names, metadata)
}

fn connection(
    k: usize,
    (a, ca, b, cb, twist): &(String, i64, String, i64, String),
    by_name: &BTreeMap<String, u32>,
) -> Result<Connection, ConfigError> {
    let at = |field: usize| format!("connections[{k}][{field}]");
    let module = |name: &String, field: usize| {
        by_name
            .get(name)
            .copied()
            .ok_or_else(|| ConfigError::new(at(field), format!("no module is called \"{name}\"")))
    };
    let connector = |c: i64, field: usize| {
        u8::try_from(c)
            .ok()
            .and_then(Connector::from_index)
            .ok_or_else(|| {
                ConfigError::new(
                    at(field),
                    format!("connector {c} does not exist; connectors are 0-5 (3 * side + dock)"),
                )
            })
    };
    let orientation = Orientation::ALL
        .into_iter()
        .find(|o| o.letter() == twist)
        .ok_or_else(|| {
            ConfigError::new(
                at(4),
                format!("unknown twist \"{twist}\"; expected \"N\", \"E\", \"S\" or \"W\""),
            )
        })?;
    Ok(Connection {
        from: (module(a, 0)?, connector(*ca, 1)?),
        orientation,
        to: (module(b, 2)?, connector(*cb, 3)?),
    })
}

impl RofiRobot {
    /// The configuration as dynarole's RoFI file.
    pub fn to_json_string(&self) -> String {
        write(self)
    }
}

/// Writes the file: the descriptive fields, one module and one connection per line.
fn write(robot: &RofiRobot) -> String {
    let meta = robot.metadata();
    let mut fields = vec![
        format!("\"name\": {}", json!(meta.name)),
        format!("\"robot\": {}", json!(FILE_TAG)),
    ];
    if let Some(source) = &meta.source {
        fields.push(format!("\"source\": {}", json!(source)));
    }
    let modules: Vec<String> = (robot.configuration().modules().zip(robot.names()))
        .map(|(m, name)| {
            object(vec![
                ("name", Some(json!(name))),
                ("id", Some(json!(m.id))),
                ("alpha", Some(json!(whole(m.alpha)))),
                ("beta", Some(json!(whole(m.beta)))),
                ("gamma", Some(json!(whole(m.gamma)))),
            ])
        })
        .collect();
    fields.push(format!("\"modules\": {}", list(&modules)));
    let name = |id: u32| robot.index_of_id(id).map(|m| robot.names()[m].clone());
    let connections: Vec<String> = (robot.ordered_connections().iter())
        .filter_map(|c| {
            let (a, b) = (name(c.from.0)?, name(c.to.0)?);
            Some(format!(
                "[{}, {}, {}, {}, {}]",
                json!(a),
                c.from.1.index(),
                json!(b),
                c.to.1.index(),
                json!(c.orientation.letter())
            ))
        })
        .collect();
    fields.push(format!("\"connections\": {}", list(&connections)));
    if let Some(note) = &meta.note {
        fields.push(format!("\"note\": {}", json!(note)));
    }
    format!("{{\n  {}\n}}\n", fields.join(",\n  "))
}
