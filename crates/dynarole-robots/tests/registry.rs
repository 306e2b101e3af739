//! The registry lists every robot kind once, and each one's plugin loads into the front end's
//! registry under the kind's name, in the registry's order.

#[test]
fn every_kind_has_a_plugin_of_its_name() {
    let robots = dynarole_robots::robots();
    let plugins = dynarole_robots::plugins_of(&robots).expect("every plugin loads");
    let names: Vec<String> = robots.names().iter().map(|n| n.to_string()).collect();
    assert_eq!(plugins.names(), names);
    let mut unique = names.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), names.len(), "a kind listed twice: {names:?}");
}

#[test]
fn an_unknown_robot_field_names_every_known_one() {
    let error = dynarole_robots::read_configuration(r#"{"robot": "NOPE"}"#).expect_err("unknown");
    assert_eq!(error.path, "robot");
    let tags = dynarole_robots::BUILT_IN.map(|k| format!("\"{}\"", k.file_tag()));
    for tag in tags {
        assert!(error.message.contains(&tag), "{}", error.message);
    }
}
