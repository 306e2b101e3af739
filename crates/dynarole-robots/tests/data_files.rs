//! Loading the data files, writing them back, and the errors (with field paths) for every kind
//! of invalid input.

mod common;

use common::{load, text, FILES};
use proptest::prelude::*;
use serde_json::{json, Value};

#[test]
fn every_data_file_loads() -> Result<(), String> {
    for (name, _) in FILES {
        let config = load(name)?;
        let expected = ["mtran", "cubes"]
            .into_iter()
            .find(|robot| name.starts_with(robot))
            .unwrap_or("atron");
        assert_eq!(config.kind().name(), expected, "{name}");
        assert_eq!(config.metadata().name, name);
    }
    let chain = load("rotation-chain-20")?;
    assert_eq!(
        chain
            .downcast_ref::<dynarole_robot_atron::AtronConfiguration>()
            .map(|c| c.modules().len()),
        Some(20)
    );
    assert_eq!(
        chain
            .downcast_ref::<dynarole_robot_atron::AtronConfiguration>()
            .map(|c| c.latches().len()),
        Some(19)
    );
    Ok(())
}

#[test]
fn writing_and_reading_back_gives_the_same_configuration() -> Result<(), String> {
    for (name, _) in FILES {
        let config = load(name)?;
        let written = config.to_json_string();
        let again =
            dynarole_robots::read_configuration(&written).map_err(|e| format!("{name}: {e}"))?;
        assert_eq!(again, config, "{name}");
        assert_eq!(again.to_json_string(), written, "{name}");
    }
    Ok(())
}

/// Numbers compared with a tolerance (the M-TRAN metres are sums of floats).
fn same_json(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => (x - y).abs() < 1e-9,
            _ => false,
        },
        (Value::Array(x), Value::Array(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(p, q)| same_json(p, q))
        }
        _ => a == b,
    }
}

#[test]
fn written_fields_agree_with_the_data_files() -> Result<(), String> {
    for (name, original) in FILES {
        let original: Value = serde_json::from_str(original).map_err(|e| e.to_string())?;
        let written: Value =
            serde_json::from_str(&load(name)?.to_json_string()).map_err(|e| e.to_string())?;
        let (Some(ours), Some(theirs)) = (
            written["modules"].as_array(),
            original["modules"].as_array(),
        ) else {
            return Err(format!("{name}: no modules"));
        };
        for (o, t) in ours.iter().zip(theirs) {
            let Some(fields) = t.as_object() else {
                return Err(format!("{name}: module is not an object"));
            };
            for (key, value) in fields {
                assert!(
                    same_json(&o[key], value),
                    "{name} {key}: {} vs {value}",
                    o[key]
                );
            }
        }
        for key in [
            "name",
            "robot",
            "source",
            "lattice_unit_m",
            "origin_m",
            "derivation",
        ] {
            assert_eq!(written.get(key), original.get(key), "{name} {key}");
        }
    }
    Ok(())
}

/// An edit of a valid file, the error path it must produce and a fragment of the message.
type Case = (Box<dyn FnOnce(&mut Value)>, &'static str, &'static str);

/// eight.json with `edit` applied, parsed; the error's path and message.
fn error_after(edit: impl FnOnce(&mut Value)) -> Result<(String, String), String> {
    let mut value: Value = serde_json::from_str(text("eight")?).map_err(|e| e.to_string())?;
    edit(&mut value);
    match dynarole_robots::read_configuration(&value.to_string()) {
        Ok(_) => Err("the edited file was accepted".to_string()),
        Err(e) => Ok((e.path, e.message)),
    }
}

fn mtran_error_after(edit: impl FnOnce(&mut Value)) -> Result<(String, String), String> {
    let mut value: Value =
        serde_json::from_str(text("mtran-snake4")?).map_err(|e| e.to_string())?;
    edit(&mut value);
    match dynarole_robots::read_configuration(&value.to_string()) {
        Ok(_) => Err("the edited file was accepted".to_string()),
        Err(e) => Ok((e.path, e.message)),
    }
}

#[test]
fn unknown_orientation_names_the_field_and_the_choices() -> Result<(), String> {
    let mut value: Value = serde_json::from_str(text("eight")?).map_err(|e| e.to_string())?;
    value["modules"][3]["orientation"] = json!("NX");
    let err = dynarole_robots::read_configuration(&value.to_string())
        .err()
        .ok_or("accepted")?;
    assert_eq!(
        err.to_string(),
        "modules[3].orientation: unknown orientation \"NX\"; expected one of NS, SN, EW, WE, \
         UD, DU, NS_BROKEN or BASE@k"
    );
    let (path, message) = error_after(|v| v["modules"][3]["orientation"] = json!("NX"))?;
    assert_eq!(path, "modules[3].orientation");
    assert_eq!(
        message,
        "unknown orientation \"NX\"; expected one of NS, SN, EW, WE, UD, DU, NS_BROKEN or BASE@k"
    );
    Ok(())
}

#[test]
fn module_field_errors() -> Result<(), String> {
    let cases: Vec<Case> = vec![
        (
            Box::new(|v| v["modules"][1]["joint"] = json!(100)),
            "modules[1].joint",
            "0, 108",
        ),
        (
            Box::new(|v| v["modules"][2]["name"] = json!("M1")),
            "modules[2].name",
            "duplicate",
        ),
        (
            Box::new(|v| v["modules"][2]["id"] = json!(1)),
            "modules[2].id",
            "duplicate",
        ),
        (
            Box::new(|v| v["modules"][1]["axis"] = json!([0, 1, 0])),
            "modules[1].axis",
            "EW",
        ),
        (
            Box::new(|v| v["modules"][1]["connector_offsets"][3] = json!([0, 0, 0])),
            "modules[1].connector_offsets[3]",
            "does not match",
        ),
        (
            Box::new(|v| v["modules"][0]["base"] = json!("SN")),
            "modules[0].base",
            "NS_BROKEN",
        ),
        (
            Box::new(|v| v["modules"][0]["spin"] = json!(1)),
            "modules[0].spin",
            "spin is 2",
        ),
        (
            Box::new(|v| v["modules"][0]["spin"] = json!(7)),
            "modules[0].spin",
            "7",
        ),
        (
            Box::new(|v| v["modules"][4]["position"] = json!([3, "x", 1])),
            "modules[4].position[1]",
            "invalid type",
        ),
        (
            Box::new(|v| v["modules"][4]["postion"] = json!([3, 0, 1])),
            "modules[4].postion",
            "unknown field",
        ),
        (
            Box::new(|v| v["lattice_unit_m"] = json!(0.1)),
            "lattice_unit_m",
            "0.08",
        ),
        (
            Box::new(|v| v["robot"] = json!("KILOBOT")),
            "robot",
            "ATRON",
        ),
        (
            Box::new(|v| {
                if let Some(m) = v["modules"][5].as_object_mut() {
                    m.remove("orientation");
                    m.remove("base");
                }
            }),
            "modules[5].orientation",
            "missing",
        ),
    ];
    for (edit, path, fragment) in cases {
        let (got_path, message) = error_after(edit)?;
        assert_eq!(got_path, path, "{message}");
        assert!(message.contains(fragment), "{path}: {message}");
    }
    Ok(())
}

#[test]
fn base_and_spin_alone_are_enough() -> Result<(), String> {
    let mut value: Value = serde_json::from_str(text("car")?).map_err(|e| e.to_string())?;
    if let Some(m) = value["modules"][1].as_object_mut() {
        m.remove("orientation");
    }
    let config =
        dynarole_robots::read_configuration(&value.to_string()).map_err(|e| e.to_string())?;
    assert_eq!(Some(config), load("car").ok());
    Ok(())
}

#[test]
fn lattice_errors() -> Result<(), String> {
    // A hole site (all coordinates + c odd).
    let (path, message) = error_after(|v| {
        v["modules"][6]["position"] = json!([5, 1, 0]);
        v["connections"] = json!([]);
    })?;
    assert_eq!(path, "modules[6].position");
    assert!(message.contains("lattice phase"), "{message}");
    // A legal site, but for a module with another axis.
    let (path, _) = error_after(|v| {
        v["modules"][6]["position"] = json!([5, 0, 1]);
        v["connections"] = json!([]);
    })?;
    assert_eq!(path, "modules[6].position");
    // Two modules on one site.
    let (path, message) = error_after(|v| {
        v["modules"][6]["position"] = json!([2, 0, 0]);
        v["connections"] = json!([]);
    })?;
    assert_eq!(path, "modules[6].position");
    assert!(message.contains("occupied by modules[3]"), "{message}");
    Ok(())
}

#[test]
fn connection_errors() -> Result<(), String> {
    let cases: Vec<(Value, &str, &str)> = vec![
        (
            json!(["M9", 0, "M2", 1]),
            "connections[0][0]",
            "unknown module",
        ),
        (json!(["M0", 9, "M2", 1]), "connections[0][1]", "0-7"),
        (json!(["M0", 0, "M2", -1]), "connections[0][3]", "0-7"),
        (json!(["M0", 0, "M1", 2]), "connections[0]", "both male"),
        (json!(["M0", 1, "M2", 1]), "connections[0]", "both female"),
        (json!(["M0", 0, "M1", 3]), "connections[0]", "do not face"),
        (
            json!(["M0", 4, "M1", 3]),
            "connections[1][1]",
            "already used",
        ),
        (json!(["M0", 0]), "connections[0]", "invalid length"),
    ];
    for (first, path, fragment) in cases {
        let (got_path, message) = error_after(|v| v["connections"][0] = first.clone())?;
        assert_eq!(got_path, path, "{first}: {message}");
        assert!(message.contains(fragment), "{first}: {message}");
    }
    Ok(())
}

#[test]
fn syntax_errors_do_not_panic_and_say_where() -> Result<(), String> {
    for bad in [
        "",
        "{",
        "[]",
        "{\"robot\": \"ATRON\"}",
        "{} trailing",
        "null",
    ] {
        let err = dynarole_robots::read_configuration(bad);
        assert!(err.is_err(), "{bad:?} accepted");
    }
    let err = dynarole_robots::read_configuration("{\"name\": \"x\", \"robot\": \"ATRON\", }");
    assert!(err.is_err_and(|e| e.message.contains("line 1")));
    Ok(())
}

#[test]
fn mtran_errors() -> Result<(), String> {
    let cases: Vec<Case> = vec![
        (
            Box::new(|v| v["modules"][1]["joints_deg"] = json!([45, 0])),
            "modules[1].joints_deg[0]",
            "-90, 0 and 90",
        ),
        (
            Box::new(|v| v["modules"][1]["orientation"] = json!("ORI7")),
            "modules[1].orientation",
            "ORI2",
        ),
        (
            Box::new(|v| v["modules"][1]["joint_axis"] = json!([0.0, 1.0, 0.0])),
            "modules[1].joint_axis",
            "does not match",
        ),
        (
            Box::new(|v| v["modules"][2]["connector_normals"][4] = json!([0.0, 0.0, -1.0])),
            "modules[2].connector_normals[4]",
            "does not match",
        ),
        (
            Box::new(|v| v["modules"][2]["connector_positions_m"][0] = json!([-0.06, 0.0, 0.0])),
            "modules[2].connector_positions_m[0]",
            "does not match",
        ),
        (
            Box::new(|v| v["modules"][2]["position"] = json!([2.25, 0, 0])),
            "modules[2].position",
            "half",
        ),
        (
            Box::new(|v| v["modules"][2]["position"] = json!([3, 0, 0])),
            "modules[2].position",
            "overlaps",
        ),
        (
            Box::new(|v| v["connections"][0] = json!(["T11", 3, "T10", 3])),
            "connections[0]",
            "male (0-2)",
        ),
        (
            Box::new(|v| v["connections"][0] = json!(["T11", 1, "T10", 4])),
            "connections[0]",
            "do not face",
        ),
        (
            Box::new(|v| v["lattice_unit_m"] = json!(0.08)),
            "lattice_unit_m",
            "0.07",
        ),
    ];
    for (edit, path, fragment) in cases {
        let (got_path, message) = mtran_error_after(edit)?;
        assert_eq!(got_path, path, "{message}");
        assert!(message.contains(fragment), "{path}: {message}");
    }
    Ok(())
}

proptest! {
    /// Arbitrary damage to a valid file gives an error or a configuration, never a panic.
    #[test]
    fn damaged_files_never_panic(cut in 0usize..2400, insert in "[\\[\\]{}\",:0-9a-zA-Z-]{0,3}") {
        let original = text("eight").unwrap_or_default();
        let cut = cut.min(original.len());
        if original.is_char_boundary(cut) {
            let damaged = format!("{}{}{}", &original[..cut], insert, &original[(cut + 1).min(original.len())..]);
            let _ = dynarole_robots::read_configuration(&damaged);
        }
    }
}

#[test]
fn module_ids_beyond_16_bits_are_refused_not_clamped() -> Result<(), String> {
    let (path, message) = error_after(|v| v["modules"][2]["id"] = json!(70000))?;
    assert_eq!(path, "modules[2].id");
    assert!(message.contains("expected 0 to 65534"), "{message}");
    let (path, _) = mtran_error_after(|v| v["modules"][0]["id"] = json!(65535))?;
    assert_eq!(path, "modules[0].id");
    Ok(())
}
