//! The ATRON data file: its module records, read and validated field by field (every error
//! naming its field path), and written back with the redundant fields; what every robot's file
//! shares is `file_format.rs`.

use crate::config::{AtronConfiguration, AtronModule};
use crate::lattice::{
    is_joint_position, Orientation, OrientationBase, CONNECTOR_COUNT, LATTICE_UNIT_M,
};
use dynarole_world::common::ConfigError;
use dynarole_world::file_format::{check_id, object, read_document, write_document};
use dynarole_world::geometry::{within_bounds, Vec3, MAX_COORDINATE};
use serde::Deserialize;
use serde_json::json;

/// Reads a configuration file of this robot (its `robot` field already checked).
pub(crate) fn read(text: &str) -> Result<AtronConfiguration, ConfigError> {
    let (metadata, modules, connections) =
        read_document::<AtronRecord, _>(text, LATTICE_UNIT_M, CONNECTOR_COUNT, atron_module)?;
    AtronConfiguration::new(metadata, modules, &connections)
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

pub(crate) fn atron_value(m: &AtronModule) -> String {
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

impl AtronConfiguration {
    /// Writes the configuration in the data-file format, including the redundant fields.
    pub fn to_json_string(&self) -> String {
        let modules: Vec<String> = self.modules().iter().map(atron_value).collect();
        let connections = self.named_connections();
        write_document(
            "ATRON",
            LATTICE_UNIT_M,
            &modules,
            &connections,
            self.metadata(),
        )
    }
}
