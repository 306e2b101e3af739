//! Reading and writing configurations in the data-file JSON format, with every error naming
//! the field path; redundant fields are optional on input, checked when present, and always
//! written.

use crate::atron::config::{AtronConfiguration, AtronModule};
use crate::atron::lattice::{
    is_joint_position, Orientation, OrientationBase, CONNECTOR_COUNT, LATTICE_UNIT_M,
};
use crate::common::{ConfigError, Metadata, NamedConnection};
use crate::configuration::Configuration;
use crate::geometry::{within_bounds, Vec3, MAX_COORDINATE};
use crate::mtran::module::{
    MtranConfiguration, MtranModule, MtranOrientation, MTRAN_CONNECTOR_COUNT, MTRAN_LATTICE_UNIT_M,
};
use serde::de::DeserializeOwned;
use serde::Deserialize;
use serde_json::{json, Value};

/// Tolerance for the floating-point redundant fields (metres, unit normals).
const FLOAT_TOLERANCE: f64 = 1e-6;

/// Top-level fields common to both robots, read first to pick the robot.
#[derive(Deserialize)]
struct Probe {
    robot: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AtronFile {
    name: String,
    #[allow(dead_code)]
    robot: String,
    source: Option<String>,
    lattice_unit_m: Option<f64>,
    origin_m: Option<[f64; 3]>,
    modules: Vec<AtronRecord>,
    connections: Vec<(String, i64, String, i64)>,
    derivation: Option<String>,
    note: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AtronRecord {
    name: String,
    id: Option<u32>,
    ussr_name: Option<String>,
    position: [i64; 3],
    orientation: Option<String>,
    base: Option<String>,
    spin: Option<i64>,
    joint: i64,
    axis: Option<[i64; 3]>,
    connector_offsets: Option<Vec<[i64; 3]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MtranFile {
    name: String,
    #[allow(dead_code)]
    robot: String,
    source: Option<String>,
    lattice_unit_m: Option<f64>,
    origin_m: Option<[f64; 3]>,
    modules: Vec<MtranRecord>,
    connections: Vec<(String, i64, String, i64)>,
    derivation: Option<String>,
    note: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MtranRecord {
    name: String,
    id: Option<u32>,
    ussr_name: Option<String>,
    position: [f64; 3],
    orientation: String,
    joints_deg: [i64; 2],
    joint_axis: Option<[f64; 3]>,
    connector_normals: Option<Vec<[f64; 3]>>,
    connector_positions_m: Option<Vec<[f64; 3]>>,
}

// The file format's entry points live beside the format, so that the configuration types do
// not depend on it.
impl Configuration {
    /// Parses and validates a configuration in the data-file format (see the crate README).
    pub fn from_json_str(text: &str) -> Result<Configuration, ConfigError> {
        parse_configuration(text)
    }

    /// Writes the configuration in the same format, including the redundant fields.
    pub fn to_json_string(&self) -> String {
        write_configuration(self)
    }
}

/// Parses either robot's file.
fn parse_configuration(text: &str) -> Result<Configuration, ConfigError> {
    not_an_object(text)?;
    let probe: Probe = deserialize(text)?;
    match probe.robot.as_deref() {
        Some("ATRON") => parse_atron(deserialize(text)?).map(Configuration::Atron),
        Some("MTRAN") => parse_mtran(deserialize(text)?).map(Configuration::Mtran),
        Some(other) => Err(ConfigError::new(
            "robot",
            format!("unknown robot \"{other}\"; expected \"ATRON\" or \"MTRAN\""),
        )),
        None => Err(ConfigError::new(
            "robot",
            "missing field; expected \"ATRON\" or \"MTRAN\"",
        )),
    }
}

/// A file that does not start as a JSON object is not a configuration at all (a program given
/// as `--from`, say): said as such, where JSON's own message would be "expected value".
fn not_an_object(text: &str) -> Result<(), ConfigError> {
    let Some((offset, found)) = text.char_indices().find(|(_, c)| !c.is_whitespace()) else {
        return Err(ConfigError::new(
            "document",
            "the file is empty; expected a configuration (a JSON object)",
        ));
    };
    if found == '{' {
        return Ok(());
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    let program = text[offset..].starts_with("robot") || text.contains("sequence ");
    let hint = if program {
        "; this looks like a DynaRole program (.dr), not a configuration (.json)"
    } else {
        ""
    };
    Err(ConfigError::new(
        "document",
        format!(
            "expected a configuration (a JSON object, starting with `{{`), found `{}` at line \
             {line}, column {column}{hint}",
            found.escape_debug()
        ),
    ))
}

/// Deserializes the whole text, tracking the field path of any error and rejecting trailing
/// characters.
fn deserialize<T: DeserializeOwned>(text: &str) -> Result<T, ConfigError> {
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

fn parse_atron(file: AtronFile) -> Result<AtronConfiguration, ConfigError> {
    let metadata = metadata(
        file.name,
        file.source,
        (file.lattice_unit_m, LATTICE_UNIT_M),
        file.origin_m,
        (file.derivation, file.note),
    )?;
    let modules = file
        .modules
        .into_iter()
        .enumerate()
        .map(|(i, record)| atron_module(i, record))
        .collect::<Result<Vec<_>, _>>()?;
    let connections = connections(&file.connections, CONNECTOR_COUNT)?;
    AtronConfiguration::new(metadata, modules, &connections)
}

/// Builds one ATRON module and checks its redundant fields against the model.
/// Largest module ID: the runtime's `dr_hal_id` is 16 bits and 65,535 means "no ID".
pub const MAX_MODULE_ID: u32 = 65_534;

/// A module ID the runtime can hold, or an error naming `modules[i].id`.
fn check_id(i: usize, id: Option<u32>) -> Result<Option<u32>, ConfigError> {
    match id {
        Some(id) if id > MAX_MODULE_ID => Err(ConfigError::new(
            format!("modules[{i}].id"),
            format!("expected 0 to {MAX_MODULE_ID} (IDs are 16 bits on the modules, 65535 means none), found {id}"),
        )),
        _ => Ok(id),
    }
}

fn atron_module(i: usize, record: AtronRecord) -> Result<AtronModule, ConfigError> {
    let at = |field: &str| format!("modules[{i}].{field}");
    let id = check_id(i, record.id)?;
    let orientation = atron_orientation(i, &record)?;
    let joint_units = u16::try_from(record.joint)
        .ok()
        .filter(|j| is_joint_position(*j))
        .ok_or_else(|| {
            ConfigError::new(
                at("joint"),
                format!("joint {} is not one of 0, 108, 216, 324", record.joint),
            )
        })?;
    let position = integer_vector(record.position).ok_or_else(|| {
        ConfigError::new(
            at("position"),
            format!("coordinates must be within +-{MAX_COORDINATE}"),
        )
    })?;
    if let Some(axis) = record.axis {
        let expected = orientation.axis();
        if axis != expected.map(i64::from) {
            return Err(ConfigError::new(
                at("axis"),
                format!(
                    "{axis:?} does not match orientation {orientation}, whose axis is {expected:?}"
                ),
            ));
        }
    }
    if let Some(offsets) = &record.connector_offsets {
        check_offsets(i, offsets, orientation, joint_units)?;
    }
    Ok(AtronModule {
        name: record.name,
        id,
        ussr_name: record.ussr_name,
        position,
        orientation,
        joint_units,
    })
}

/// The orientation from `orientation`, or from `base` and `spin` when it is absent; when both
/// are given they must agree.
fn atron_orientation(i: usize, record: &AtronRecord) -> Result<Orientation, ConfigError> {
    let at = |field: &str| format!("modules[{i}].{field}");
    let base = match &record.base {
        Some(name) => Some(OrientationBase::from_name(name).ok_or_else(|| {
            ConfigError::new(
                at("base"),
                format!("unknown base \"{name}\"; expected one of NS, SN, EW, WE, UD, DU"),
            )
        })?),
        None => None,
    };
    let spin = match record.spin {
        Some(spin) => Some(u8::try_from(spin).ok().filter(|s| *s < 4).ok_or_else(|| {
            ConfigError::new(at("spin"), format!("spin {spin} is not 0, 1, 2 or 3"))
        })?),
        None => None,
    };
    let Some(name) = &record.orientation else {
        return match (base, spin) {
            (Some(base), Some(spin)) => Ok(Orientation::from_base_spin(base, spin)),
            _ => Err(ConfigError::new(
                at("orientation"),
                "missing; give orientation, or both base and spin",
            )),
        };
    };
    let orientation =
        Orientation::parse(name).map_err(|message| ConfigError::new(at("orientation"), message))?;
    if let Some(base) = base {
        if base != orientation.base() {
            return Err(ConfigError::new(
                at("base"),
                format!(
                    "\"{}\" does not match orientation {name}, whose base is {}",
                    base.name(),
                    orientation.base().name()
                ),
            ));
        }
    }
    if let Some(spin) = spin {
        if spin != orientation.spin() {
            return Err(ConfigError::new(
                at("spin"),
                format!(
                    "{spin} does not match orientation {name}, whose spin is {}",
                    orientation.spin()
                ),
            ));
        }
    }
    Ok(orientation)
}

fn check_offsets(
    i: usize,
    offsets: &[[i64; 3]],
    orientation: Orientation,
    joint_units: u16,
) -> Result<(), ConfigError> {
    if offsets.len() != usize::from(CONNECTOR_COUNT) {
        return Err(ConfigError::new(
            format!("modules[{i}].connector_offsets"),
            format!("{} entries; expected 8 (connectors 0-7)", offsets.len()),
        ));
    }
    for (c, given) in (0..CONNECTOR_COUNT).zip(offsets) {
        let expected = orientation.connector_offset(joint_units, c);
        if expected.map(|e| e.map(i64::from)) != Some(*given) {
            return Err(ConfigError::new(
                format!("modules[{i}].connector_offsets[{c}]"),
                format!(
                    "{given:?} does not match the model's {:?} for orientation {orientation} at \
                     joint {joint_units}",
                    expected.unwrap_or_default()
                ),
            ));
        }
    }
    Ok(())
}

/// An in-bounds integer vector.
fn integer_vector(v: [i64; 3]) -> Option<Vec3> {
    let mut out = [0i32; 3];
    for (o, x) in out.iter_mut().zip(v) {
        *o = i32::try_from(x).ok()?;
    }
    within_bounds(out).then_some(out)
}

fn parse_mtran(file: MtranFile) -> Result<MtranConfiguration, ConfigError> {
    let metadata = metadata(
        file.name,
        file.source,
        (file.lattice_unit_m, MTRAN_LATTICE_UNIT_M),
        file.origin_m,
        (file.derivation, file.note),
    )?;
    let modules = file
        .modules
        .into_iter()
        .enumerate()
        .map(|(i, record)| mtran_module(i, record))
        .collect::<Result<Vec<_>, _>>()?;
    let connections = connections(&file.connections, MTRAN_CONNECTOR_COUNT)?;
    MtranConfiguration::new(metadata, modules, &connections)
}

/// Builds one M-TRAN module and checks its redundant fields.
fn mtran_module(i: usize, record: MtranRecord) -> Result<MtranModule, ConfigError> {
    let at = |field: &str| format!("modules[{i}].{field}");
    let orientation = MtranOrientation::parse(&record.orientation)
        .map_err(|message| ConfigError::new(at("orientation"), message))?;
    let centre_quarter_pitch = half_integer_vector(record.position).ok_or_else(|| {
        ConfigError::new(
            at("position"),
            format!(
                "coordinates must be whole or half numbers within +-{}",
                MAX_COORDINATE / 2
            ),
        )
    })?;
    let id = check_id(i, record.id)?;
    let mut joints_deg = [0i16; 2];
    for (j, (out, angle)) in joints_deg.iter_mut().zip(record.joints_deg).enumerate() {
        *out = i16::try_from(angle).map_err(|_| {
            ConfigError::new(
                format!("modules[{i}].joints_deg[{j}]"),
                format!("joint angle {angle} is outside -90..90"),
            )
        })?;
    }
    let module = MtranModule {
        name: record.name,
        id,
        ussr_name: record.ussr_name,
        centre_quarter_pitch,
        orientation,
        joints_deg,
    };
    if let Some(axis) = record.joint_axis {
        check_float_vector(&at("joint_axis"), axis, module.joint_axis().map(f64::from))?;
    }
    if let Some(normals) = &record.connector_normals {
        let expected = module
            .straight_connector_normals()
            .map(|n| n.map(f64::from));
        check_float_list(&at("connector_normals"), normals, &expected)?;
    }
    if let Some(positions) = &record.connector_positions_m {
        let expected = module.straight_connector_positions_m();
        check_float_list(&at("connector_positions_m"), positions, &expected)?;
    }
    Ok(module)
}

/// A vector of whole or half numbers, doubled into integers.
fn half_integer_vector(v: [f64; 3]) -> Option<Vec3> {
    let mut out = [0i32; 3];
    for (o, x) in out.iter_mut().zip(v) {
        let doubled = 2.0 * x;
        if !doubled.is_finite() || (doubled - doubled.round()).abs() > 1e-9 {
            return None;
        }
        if doubled.abs() > f64::from(MAX_COORDINATE) {
            return None;
        }
        // Finite, integral and within bounds, so the conversion is exact.
        *o = doubled.round() as i32;
    }
    Some(out)
}

fn check_float_vector(path: &str, given: [f64; 3], expected: [f64; 3]) -> Result<(), ConfigError> {
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

fn check_float_list(
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

/// Writes a configuration: top-level fields one per line, one module and one connection per
/// line, like the data files.
fn write_configuration(config: &Configuration) -> String {
    let (robot, unit, modules, connections) = match config {
        Configuration::Atron(c) => (
            "ATRON",
            LATTICE_UNIT_M,
            c.modules().iter().map(atron_value).collect::<Vec<_>>(),
            c.named_connections(),
        ),
        Configuration::Mtran(c) => (
            "MTRAN",
            MTRAN_LATTICE_UNIT_M,
            c.modules().iter().map(mtran_value).collect::<Vec<_>>(),
            c.named_connections(),
        ),
    };
    let meta = config.metadata();
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
    fields.push(format!("\"modules\": {}", list(&modules)));
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

/// A JSON array with one element per line.
fn list(items: &[String]) -> String {
    if items.is_empty() {
        return "[]".to_string();
    }
    let lines: Vec<String> = items.iter().map(|v| format!("    {v}")).collect();
    format!("[\n{}\n  ]", lines.join(",\n"))
}

/// One-line JSON with a space after each comma and colon, as in the data files (serde_json's
/// compact form has none).
fn compact(value: &Value) -> String {
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
fn object(entries: Vec<(&str, Option<Value>)>) -> String {
    let fields: Vec<String> = entries
        .into_iter()
        .filter_map(|(key, value)| value.map(|v| format!("{}: {}", json!(key), compact(&v))))
        .collect();
    format!("{{{}}}", fields.join(", "))
}

fn atron_value(m: &AtronModule) -> String {
    let offsets: Vec<Vec3> = (0..CONNECTOR_COUNT)
        .filter_map(|c| m.connector_offset(c))
        .collect();
    object(vec![
        ("name", Some(json!(m.name))),
        ("id", m.id.map(|id| json!(id))),
        ("ussr_name", m.ussr_name.as_ref().map(|n| json!(n))),
        ("position", Some(json!(m.position))),
        ("orientation", Some(json!(m.orientation.name()))),
        ("base", Some(json!(m.orientation.base().name()))),
        ("spin", Some(json!(m.orientation.spin()))),
        ("joint", Some(json!(m.joint_units))),
        ("axis", Some(json!(m.orientation.axis()))),
        ("connector_offsets", Some(json!(offsets))),
    ])
}

fn mtran_value(m: &MtranModule) -> String {
    // Whole numbers are written as integers, like the data files.
    let position: Vec<Value> = m
        .centre_quarter_pitch
        .iter()
        .map(|c| {
            if c % 2 == 0 {
                json!(c / 2)
            } else {
                json!(f64::from(*c) / 2.0)
            }
        })
        .collect();
    let normals = m.straight_connector_normals().map(|n| n.map(f64::from));
    object(vec![
        ("name", Some(json!(m.name))),
        ("id", m.id.map(|id| json!(id))),
        ("ussr_name", m.ussr_name.as_ref().map(|n| json!(n))),
        ("position", Some(json!(position))),
        ("orientation", Some(json!(m.orientation.name()))),
        ("joints_deg", Some(json!(m.joints_deg))),
        ("joint_axis", Some(json!(m.joint_axis().map(f64::from)))),
        ("connector_normals", Some(json!(normals))),
        (
            "connector_positions_m",
            Some(json!(m.straight_connector_positions_m())),
        ),
    ])
}
