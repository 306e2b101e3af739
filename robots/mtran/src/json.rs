//! The M-TRAN data file: its module records, read and validated field by field (every error
//! naming its field path), and written back with the redundant fields; what every robot's file
//! shares is `file_format.rs`.

use crate::module::{
    MtranConfiguration, MtranModule, MtranOrientation, MTRAN_CONNECTOR_COUNT, MTRAN_LATTICE_UNIT_M,
};
use dynarole_world::common::ConfigError;
use dynarole_world::file_format::{
    check_float_list, check_float_vector, check_id, object, read_document, write_document,
};
use dynarole_world::geometry::{Vec3, MAX_COORDINATE};
use serde::Deserialize;
use serde_json::{json, Value};

/// Reads a configuration file of this robot (its `robot` field already checked).
pub(crate) fn read(text: &str) -> Result<MtranConfiguration, ConfigError> {
    let (metadata, modules, connections) = read_document::<MtranRecord, _>(
        text,
        MTRAN_LATTICE_UNIT_M,
        MTRAN_CONNECTOR_COUNT,
        mtran_module,
    )?;
    MtranConfiguration::new(metadata, modules, &connections)
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

pub(crate) fn mtran_value(m: &MtranModule) -> String {
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

impl MtranConfiguration {
    /// Writes the configuration in the data-file format, including the redundant fields.
    pub fn to_json_string(&self) -> String {
        let modules: Vec<String> = self.modules().iter().map(mtran_value).collect();
        let connections = self.named_connections();
        write_document(
            "MTRAN",
            MTRAN_LATTICE_UNIT_M,
            &modules,
            &connections,
            self.metadata(),
        )
    }
}
