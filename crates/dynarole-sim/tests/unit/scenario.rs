//! Unit tests of `src/scenario.rs`, kept beside the integration tests
//! because they read the robots' example files.

use super::*;

/// Every stepping is read by its name, and written back as it.
#[test]
fn stepping_names_round_trip() {
    for &stepping in <Stepping as Choice>::ALL {
        let text = format!("stepping = \"{}\"\n", stepping.name());
        let scenario = Scenario::from_toml_str(&text).expect("a known name");
        assert_eq!(scenario.stepping, stepping);
        let written = serde_json::to_value(&scenario).expect("serialises");
        assert_eq!(written["stepping"], stepping.name());
    }
}

/// A timeout above the limit is refused at its field, naming the limit; the limit itself
/// is accepted.
#[test]
fn the_timeout_has_an_upper_limit() {
    let at_limit = format!("timeout_ms = {MAX_TIMEOUT_MS}\n");
    assert!(Scenario::from_toml_str(&at_limit).is_ok());
    let text = "timeout_ms = 1000000000000\n";
    let error = Scenario::from_toml_str(text).expect_err("too long");
    assert_eq!(error.field, "timeout_ms");
    assert!(
        error.message.contains("more than 1000000000 ms"),
        "{}",
        error.message
    );
    assert_eq!(error.span, Some(13..26));
}

#[test]
fn an_unknown_stepping_is_an_error_at_its_value() {
    let text = "stepping = \"tick\"\n";
    let error = Scenario::from_toml_str(text).expect_err("unknown");
    assert_eq!(
        error.message,
        "unknown stepping `tick`, expected `fixed` or `tickless`"
    );
    assert_eq!(error.span, Some(11..17));
    assert_eq!(error.hint.as_deref(), Some("did you mean `tickless`?"));
}

fn built_in(name: &str) -> RobotApi {
    dynarole_robots::plugins()
        .get(name)
        .cloned()
        .expect("a built-in robot")
}

/// ATRON's presets (and M-TRAN's, for now the same) are the simulator's two joint models
/// of before, number for number: `ussr` (550 ms + 310 ms per further quarter) and
/// `realistic` (1500 ms per quarter + 600 ms to settle), extend 3 s and retract 2 s.
#[test]
fn atrons_timing_presets_are_the_former_joint_models() {
    for robot in ["atron", "mtran"] {
        let api = built_in(robot);
        let named = |name: &str| {
            let timing = Timing {
                preset: PresetName::named(name),
                ..Timing::default()
            };
            timing.durations(&api).expect("a preset of the robot")
        };
        // The robot has no moves: its presets leave `move_ms` out (0, never used).
        let ussr = Durations {
            move_ms: 0,
            ..USSR_TIMING
        };
        assert_eq!(named("ussr"), ussr, "{robot}");
        assert_eq!(default_durations(&api), ussr, "{robot}: ussr first");
        let realistic = named("realistic");
        assert_eq!((realistic.extend_ms, realistic.retract_ms), (3000, 2000));
        for quarters in 0..=4 {
            let before = if quarters == 0 {
                0
            } else {
                1500 * quarters + 600
            };
            assert_eq!(realistic.turn_ms(quarters), before, "{robot}: {quarters}");
            let before = if quarters == 0 {
                0
            } else {
                550 + 310 * (quarters - 1)
            };
            assert_eq!(USSR_TIMING.turn_ms(quarters), before, "{quarters}");
        }
    }
}

/// A plugin without `[[timing]]` runs the built-in `ussr`, the only name it has.
#[test]
fn a_robot_without_timing_presets_runs_the_built_in_ussr() {
    let api = RobotApi::from_toml("name = \"bare\"\n").expect("a plugin");
    assert_eq!(Timing::default().durations(&api), Ok(USSR_TIMING));
    let ussr = Scenario::from_toml_str("[timing]\npreset = \"ussr\"\n").expect("reads");
    assert_eq!(ussr.timing.durations(&api), Ok(USSR_TIMING));
    let other = Scenario::from_toml_str("[timing]\npreset = \"realistic\"\n").expect("reads");
    let error = other.timing.durations(&api).expect_err("not this robot's");
    assert_eq!(error.field, "timing.preset");
    assert_eq!(
        error.message,
        "unknown timing preset `realistic`; robot `bare` has `ussr`"
    );
}

/// `joint`, the field's former name, still reads; the overrides are optional and written
/// only when given.
#[test]
fn the_former_joint_field_reads_as_the_preset() {
    let old = Scenario::from_toml_str("[timing]\njoint = \"realistic\"\n").expect("reads");
    assert_eq!(old.timing.preset, PresetName::named("realistic"));
    assert_eq!(old.timing.extend_ms, None);
    let written = serde_json::to_value(&old.timing).expect("serialises");
    assert_eq!(
        written,
        serde_json::json!({ "preset": "realistic", "variation": 0.0 })
    );
    let long = Scenario::from_toml_str("[timing]\nretract_ms = 1000000001\n");
    assert_eq!(long.expect_err("too long").field, "timing.retract_ms");
}
