//! dynarole's data file for cubes (`cubes.schema.json`): `{"robot": "cubes", "modules":
//! [{"id": N, "position": [x, y, z]}, ...]}`, a module optionally named and `fixed`; read with
//! every error naming its field, written back one module per line like the other robots'
//! files.

use crate::robot::{Cube, CubesRobot};
use dynarole_world::file_format::{deserialize, list, object};
use dynarole_world::{ConfigError, Metadata};
use serde::Deserialize;
use serde_json::json;

/// The `robot` field of dynarole's cube files.
pub const FILE_TAG: &str = "cubes";

/// The farthest a cube may be from the origin along an axis: moves stay far inside `i32`.
pub const MAX_COORDINATE: i64 = 1_000_000;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CubesFile {
    name: String,
    #[allow(dead_code)]
    robot: String,
    source: Option<String>,
    modules: Vec<ModuleRecord>,
    note: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModuleRecord {
    name: Option<String>,
    id: u32,
    position: [i64; 3],
    #[serde(default)]
    fixed: bool,
}

/// Reads one of dynarole's cube files (its `robot` field already matched).
pub(crate) fn read(text: &str) -> Result<CubesRobot, ConfigError> {
    let file: CubesFile = deserialize(text)?;
    let cubes = (file.modules.into_iter().enumerate())
        .map(|(i, record)| cube(i, record))
        .collect::<Result<Vec<Cube>, ConfigError>>()?;
    let metadata = Metadata {
        name: file.name,
        source: file.source,
        note: file.note,
        ..Metadata::default()
    };
    CubesRobot::new(cubes, metadata)
}

fn cube(i: usize, record: ModuleRecord) -> Result<Cube, ConfigError> {
    let mut position = [0; 3];
    for (k, c) in record.position.iter().enumerate() {
        position[k] = i32::try_from(*c)
            .ok()
            .filter(|c| i64::from(*c).abs() <= MAX_COORDINATE)
            .ok_or_else(|| {
                ConfigError::new(
                    format!("modules[{i}].position[{k}]"),
                    format!("expected -{MAX_COORDINATE} to {MAX_COORDINATE}, found {c}"),
                )
            })?;
    }
    Ok(Cube {
        name: record.name.unwrap_or_else(|| format!("M{}", record.id)),
        id: record.id,
        position,
        fixed: record.fixed,
    })
}

impl CubesRobot {
    /// The configuration as dynarole's cube file.
    pub fn to_json_string(&self) -> String {
        let meta = self.metadata();
        let mut fields = vec![
            format!("\"name\": {}", json!(meta.name)),
            format!("\"robot\": {}", json!(FILE_TAG)),
        ];
        if let Some(source) = &meta.source {
            fields.push(format!("\"source\": {}", json!(source)));
        }
        let modules: Vec<String> = (self.cubes().iter())
            .map(|c| {
                object(vec![
                    ("name", Some(json!(c.name))),
                    ("id", Some(json!(c.id))),
                    ("position", Some(json!(c.position))),
                    ("fixed", c.fixed.then_some(json!(true))),
                ])
            })
            .collect();
        fields.push(format!("\"modules\": {}", list(&modules)));
        if let Some(note) = &meta.note {
            fields.push(format!("\"note\": {}", json!(note)));
        }
        format!("{{\n  {}\n}}\n", fields.join(",\n  "))
    }
}
