//! RofiWorld JSON read into configurations: one world and a plan of worlds, connector names
//! and numbers alike, and an error naming the field for each rule a file can break.

use dynarole_robot_rofi::{read_rofiworld, validate, Connector, Dock, Orientation, Side};

const TWO: &str = r#"{
  "modules": [
    {"id": 1, "type": "universal", "alpha": 0, "beta": 0, "gamma": 0},
    {"id": 2, "type": "universal", "alpha": 0, "beta": 0, "gamma": 90}
  ],
  "moduleJoints": [
    {"orientation": "North", "from": {"id": 1, "connector": "B-Z"}, "to": {"id": 2, "connector": 2}}
  ],
  "spaceJoints": [
    {"point": [0, 0, 0], "to": {"id": 1, "component": 6}, "joint": {"type": "rigid", "sourceToDestination": "identity"}}
  ]
}"#;

#[test]
fn one_world_reads_into_one_valid_configuration() {
    let worlds = read_rofiworld(TWO).expect("a world");
    assert_eq!(worlds.len(), 1);
    let config = &worlds[0];
    assert_eq!(config.len(), 2);
    let c = config.connections()[0];
    assert_eq!(c.from, (1, Connector::new(Side::B, Dock::MinusZ)));
    assert_eq!(c.to, (2, Connector::new(Side::A, Dock::MinusZ)));
    assert_eq!(c.orientation, Orientation::North);
    let poses = validate(config).expect("valid");
    let far = poses.centre((2, Side::B)).expect("a shoe");
    assert!((far.z - 3.0).abs() < 1e-9, "{far}");
}

#[test]
fn a_plan_is_an_array_of_worlds_and_gamma_is_circular() {
    let turned = TWO.replace(r#""gamma": 90"#, r#""gamma": 450"#);
    let text = format!("[{TWO}, {turned}]");
    let worlds = read_rofiworld(&text).expect("a plan");
    assert_eq!(worlds.len(), 2);
    let gamma = |i: usize| worlds[i].module(2).expect("module 2").gamma;
    assert_eq!(gamma(0), 90.0);
    assert_eq!(gamma(1), 90.0);
}

fn error_of(text: &str) -> String {
    match read_rofiworld(text) {
        Ok(_) => panic!("accepted: {text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn each_broken_rule_names_its_field() {
    let cases = [
        (
            TWO.replace(r#""B-Z""#, r#""B+Y""#),
            "moduleJoints[0].from.connector",
            "expected a connector",
        ),
        (
            TWO.replace(r#""connector": 2"#, r#""connector": 6"#),
            "moduleJoints[0].to.connector",
            "0 to 5",
        ),
        (
            TWO.replace("North", "Up"),
            "moduleJoints[0].orientation",
            "expected an orientation",
        ),
        (
            TWO.replace(
                r#""alpha": 0, "beta": 0, "gamma": 90"#,
                r#""alpha": 120, "beta": 0, "gamma": 90"#,
            ),
            "modules[1]",
            "outside -90..90",
        ),
        (
            TWO.replace(
                r#""type": "universal", "alpha": 0, "beta": 0, "gamma": 90"#,
                r#""type": "pad", "alpha": 0, "beta": 0, "gamma": 90"#,
            ),
            "modules[1].type",
            "only universal modules",
        ),
        (
            // A pad as RoFI writes it: no angles, a size.
            TWO.replace(
                r#""type": "universal", "alpha": 0, "beta": 0, "gamma": 90"#,
                r#""type": "pad", "width": 6, "height": 3"#,
            ),
            "modules[1].type",
            "pads and other module kinds are not modelled",
        ),
        (
            TWO.replace(
                r#""alpha": 0, "beta": 0, "gamma": 90"#,
                r#""alpha": 0, "beta": 0"#,
            ),
            "modules[1].gamma",
            "missing field `gamma`",
        ),
        (
            TWO.replace(r#""id": 2, "connector""#, r#""id": 9, "connector""#),
            "moduleJoints[0]",
            "module 9 is not declared",
        ),
        (
            TWO.replace(
                r#""to": {"id": 1, "component""#,
                r#""to": {"id": 4, "component""#,
            ),
            "spaceJoints[0].to.id",
            "no module 4",
        ),
        (
            TWO.replace(
                r#""alpha": 0, "beta": 0, "gamma": 0}"#,
                r#""alpha": "zero", "beta": 0, "gamma": 0}"#,
            ),
            "modules[0].alpha",
            "expected f64",
        ),
        ("[1]".to_string(), "[0]", "expected a RofiWorld object"),
    ];
    for (text, path, expected) in cases {
        let error = error_of(&text);
        assert!(error.contains(path), "{error}: not at `{path}`");
        assert!(
            error.contains(expected),
            "{error}: does not say `{expected}`"
        );
    }
    let plan = format!("[{TWO}, {}]", TWO.replace("North", "Up"));
    assert!(
        error_of(&plan).contains("[1].moduleJoints[0].orientation"),
        "{}",
        error_of(&plan)
    );
}

#[test]
fn text_that_is_not_json_names_its_line_and_column() {
    let error = error_of("{\n  \"modules\": [,]\n}");
    assert!(error.starts_with("line 2, column"), "{error}");
}
