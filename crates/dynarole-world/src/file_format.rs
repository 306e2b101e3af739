//! What every robot's configuration file shares: reading the whole text with the field path of
//! any error, the descriptive fields, the connections, module IDs, the check of redundant
//! floating-point fields, and the writer's layout (one module and one connection per line).
//! Each robot's own records are in its folder (`robots/NAME/`); `robot_set.rs`
//! picks the robot.

use crate::common::{ConfigError, Metadata, NamedConnection};
use serde::de::DeserializeOwned;
use serde::Deserialize;
use serde_json::{json, Value};

/// A data file's top level, the same for every robot; `R` is the robot's module record.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DataFile<R> {
    name: String,
    #[allow(dead_code)]
    robot: String,
    source: Option<String>,
    lattice_unit_m: Option<f64>,
    origin_m: Option<[f64; 3]>,
    modules: Vec<R>,
    connections: Vec<(String, i64, String, i64)>,
    derivation: Option<String>,
    note: Option<String>,
}

/// A robot's data file read: its descriptive fields (`lattice_unit_m` checked against
/// `unit_m`), its modules, each built from its record by `module` (index, record), and its
/// connections checked against `connector_count`.
pub fn read_document<R: DeserializeOwned, M>(
    text: &str,
    unit_m: f64,
    connector_count: u8,
    module: fn(usize, R) -> Result<M, ConfigError>,
) -> Result<(Metadata, Vec<M>, Vec<NamedConnection>), ConfigError> {
    let file: DataFile<R> = deserialize(text)?;
    let metadata = metadata(
        file.name,
        file.source,
        (file.lattice_unit_m, unit_m),
        file.origin_m,
        (file.derivation, file.note),
    )?;
    let modules = (file.modules.into_iter().enumerate())
        .map(|(i, record)| module(i, record))
        .collect::<Result<Vec<_>, _>>()?;
    let connections = connections(&file.connections, connector_count)?;
    Ok((metadata, modules, connections))
}

/// Tolerance for the floating-point redundant fields (metres, unit normals).
pub const FLOAT_TOLERANCE: f64 = 1e-6;

/// Deserializes the whole text, tracking the field path of any error and rejecting trailing
/// characters.
pub fn deserialize<T: DeserializeOwned>(text: &str) -> Result<T, ConfigError> {
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let value: T = serde_path_to_error::deserialize(&mut deserializer).map_err(|e| {
        let path = e.path().to_string();
        let path = if path == "." {
            "document".to_string()
        } else {
            path
        };
        ConfigError::new(path, e.into_inner().to_string())
    })?;
    deserializer
        .end()
        .map_err(|e| ConfigError::new("document", e.to_string()))?;
    Ok(value)
}

/// Checks the common top-level fields and builds the metadata.
fn metadata(
    name: String,
    source: Option<String>,
    (lattice_unit_m, expected_unit_m): (Option<f64>, f64),
    origin_m: Option<[f64; 3]>,
    (derivation, note): (Option<String>, Option<String>),
) -> Result<Metadata, ConfigError> {
    if let Some(unit) = lattice_unit_m {
        if (unit - expected_unit_m).abs() > 1e-12 {
            return Err(ConfigError::new(
                "lattice_unit_m",
                format!("{unit} does not match the model's {expected_unit_m} m per unit"),
            ));
        }
    }
    if origin_m.is_some_and(|o| o.iter().any(|c| !c.is_finite())) {
        return Err(ConfigError::new("origin_m", "coordinates must be finite"));
    }
    Ok(Metadata {
        name,
        source,
        origin_m,
        derivation,
        note,
    })
}

/// Converts connector numbers, naming the field of an out-of-range one.
fn connections(
    raw: &[(String, i64, String, i64)],
    count: u8,
) -> Result<Vec<NamedConnection>, ConfigError> {
    raw.iter()
        .enumerate()
        .map(|(k, (a, ca, b, cb))| {
            let convert = |c: i64, field: usize| {
                u8::try_from(c).ok().filter(|c| *c < count).ok_or_else(|| {
                    ConfigError::new(
                        format!("connections[{k}][{field}]"),
                        format!(
                            "connector {c} does not exist; connectors are 0-{}",
                            count - 1
                        ),
                    )
                })
            };
            Ok((a.clone(), convert(*ca, 1)?, b.clone(), convert(*cb, 3)?))
        })
        .collect()
}

/// Largest module ID: the runtime's `dr_hal_id` is 16 bits and 65,535 means "no ID".
pub const MAX_MODULE_ID: u32 = 65_534;

/// Whether `name` can name a module in a program: a letter or `_`, then letters, digits or
/// `_`, at most 64 characters.
pub fn is_module_name(name: &str) -> bool {
    let mut chars = name.chars();
    let first = chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    first && name.len() <= 64 && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// A module ID the runtime can hold, or an error naming `modules[i].id`.
pub fn check_id(i: usize, id: Option<u32>) -> Result<Option<u32>, ConfigError> {
    match id {
        Some(id) if id > MAX_MODULE_ID => Err(ConfigError::new(
            format!("modules[{i}].id"),
            format!("expected 0 to {MAX_MODULE_ID} (IDs are 16 bits on the modules, 65535 means none), found {id}"),
        )),
        _ => Ok(id),
    }
}

pub fn check_float_vector(
    path: &str,
    given: [f64; 3],
    expected: [f64; 3],
) -> Result<(), ConfigError> {
    let close = given
        .iter()
        .zip(expected)
        .all(|(g, e)| (g - e).abs() <= FLOAT_TOLERANCE);
    if close {
        Ok(())
    } else {
        Err(ConfigError::new(
            path,
            format!("{given:?} does not match the model's {expected:?}"),
        ))
    }
}

pub fn check_float_list(
    path: &str,
    given: &[[f64; 3]],
    expected: &[[f64; 3]],
) -> Result<(), ConfigError> {
    if given.len() != expected.len() {
        return Err(ConfigError::new(
            path,
            format!("{} entries; expected {}", given.len(), expected.len()),
        ));
    }
    for (k, (g, e)) in given.iter().zip(expected).enumerate() {
        check_float_vector(&format!("{path}[{k}]"), *g, *e)?;
    }
    Ok(())
}

/// A JSON array with one element per line.
pub fn list(items: &[String]) -> String {
    if items.is_empty() {
        return "[]".to_string();
    }
    let lines: Vec<String> = items.iter().map(|v| format!("    {v}")).collect();
    format!("[\n{}\n  ]", lines.join(",\n"))
}

/// One-line JSON with a space after each comma and colon, as in the data files (serde_json's
/// compact form has none).
pub fn compact(value: &Value) -> String {
    match value {
        Value::Array(items) => {
            let parts: Vec<String> = items.iter().map(compact).collect();
            format!("[{}]", parts.join(", "))
        }
        Value::Object(map) => {
            let parts: Vec<String> = map
                .iter()
                .map(|(k, v)| format!("{}: {}", json!(k), compact(v)))
                .collect();
            format!("{{{}}}", parts.join(", "))
        }
        other => other.to_string(),
    }
}

/// A one-line JSON object with the fields that are present, in the data files' field order
/// (written by hand because `serde_json::Map` sorts its keys).
pub fn object(entries: Vec<(&str, Option<Value>)>) -> String {
    let fields: Vec<String> = entries
        .into_iter()
        .filter_map(|(key, value)| value.map(|v| format!("{}: {}", json!(key), compact(&v))))
        .collect();
    format!("{{{}}}", fields.join(", "))
}

/// Writes a configuration file of robot `robot` (its `robot` field): top-level fields one per
/// line, one module (`modules`, each robot's own one-line objects) and one connection per
/// line, like the data files.
pub fn write_document(
    robot: &str,
    unit: f64,
    modules: &[String],
    connections: &[NamedConnection],
    meta: &Metadata,
) -> String {
    let mut fields: Vec<String> = vec![
        format!("\"name\": {}", json!(meta.name)),
        format!("\"robot\": {}", json!(robot)),
    ];
    if let Some(source) = &meta.source {
        fields.push(format!("\"source\": {}", json!(source)));
    }
    fields.push(format!("\"lattice_unit_m\": {}", json!(unit)));
    if let Some(origin) = meta.origin_m {
        fields.push(format!("\"origin_m\": {}", compact(&json!(origin))));
    }
    fields.push(format!("\"modules\": {}", list(modules)));
    let connection_values: Vec<String> = connections
        .iter()
        .map(|(a, ca, b, cb)| format!("[{}, {ca}, {}, {cb}]", json!(a), json!(b)))
        .collect();
    fields.push(format!("\"connections\": {}", list(&connection_values)));
    if let Some(derivation) = &meta.derivation {
        fields.push(format!("\"derivation\": {}", json!(derivation)));
    }
    if let Some(note) = &meta.note {
        fields.push(format!("\"note\": {}", json!(note)));
    }
    format!("{{\n  {}\n}}\n", fields.join(",\n  "))
}
