//! RoFI's old text format read into configurations: a single configuration, a plan with the
//! planner's trailer, both spellings of an edge, comments and line endings, and an error at the
//! right line and column for each rule a file can break.

use dynarole_robot_rofi::{
    read_old_format, Connector, Dock, OldFormatError, Orientation, Plan, RofiConfiguration, Side,
};
use proptest::prelude::*;

/// Three modules in a chain: 1 to 2 by names, 2 to 3 by numbers.
const CHAIN: &str = "\
M 1 0 0 0
M 2 -15.5 90 180
M 3 45 -90 -30
E 1 B -Z N -Z A 2
E 2 1 2 1 0 0 3
";

fn read(text: &str) -> Plan {
    match read_old_format(text) {
        Ok(plan) => plan,
        Err(error) => panic!("{text:?} should read, but: {error}"),
    }
}

fn refuse(text: &str) -> OldFormatError {
    match read_old_format(text) {
        Ok(plan) => panic!("{text:?} should be refused, but read {plan:?}"),
        Err(error) => error,
    }
}

/// Checks an error's place and that its message names what was expected.
fn assert_error(error: &OldFormatError, line: usize, column: usize, words: &[&str]) {
    assert_eq!((error.line, error.column), (line, column), "{error}");
    for word in words {
        assert!(error.message.contains(word), "{word:?} not in: {error}");
    }
}

fn only(plan: &Plan) -> &RofiConfiguration {
    assert_eq!(plan.configurations.len(), 1, "{plan:?}");
    &plan.configurations[0].1
}

#[test]
fn a_file_without_c_is_one_configuration() {
    let plan = read(CHAIN);
    assert_eq!(plan.configurations[0].0, 1);
    let config = only(&plan);
    assert_eq!(config.len(), 3);
    let two = config.module(2).expect("module 2");
    assert_eq!((two.alpha, two.beta, two.gamma), (-15.5, 90.0, 180.0));
    assert_eq!(config.connections().len(), 2);

    let first = config
        .connection_at((1, Connector::new(Side::B, Dock::MinusZ)))
        .expect("an edge at 1 B -Z");
    assert_eq!(first.orientation, Orientation::North);
    assert_eq!(first.to, (2, Connector::new(Side::A, Dock::MinusZ)));

    let second = config
        .connection_at((3, Connector::new(Side::A, Dock::PlusX)))
        .expect("an edge at 3 A +X");
    assert_eq!(second.orientation, Orientation::East);
    assert_eq!(second.to, (2, Connector::new(Side::B, Dock::MinusZ)));
}

#[test]
fn a_plan_of_three_configurations_with_the_planner_trailer() {
    let text = "\
C
M 1 0 0 0
M 2 0 0 0
E 1 A +X S -X B 2
C
M 1 10 0 0
M 2 0 0 0
E 1 A +X S -X B 2
C
M 1 20 0 0
M 2 0 0 90
E 1 A +X S -X B 2

length 3
queue 17
# planner statistics end here
cfgs 42
";
    let plan = read(text);
    let lines: Vec<usize> = plan.configurations.iter().map(|(line, _)| *line).collect();
    assert_eq!(lines, [1, 5, 9]);
    let alphas: Vec<f64> = plan
        .configurations
        .iter()
        .map(|(_, config)| config.module(1).expect("module 1").alpha)
        .collect();
    assert_eq!(alphas, [0.0, 10.0, 20.0]);
    for (_, config) in &plan.configurations {
        assert_eq!(config.connections().len(), 1);
    }
}

#[test]
fn names_and_numbers_give_the_same_edge_from_either_end() {
    let modules = "M 20001 0 0 0\nM 10102 0 0 0\n";
    let by_names = read(&format!("{modules}E 20001 A +X E -Z B 10102\n"));
    let by_numbers = read(&format!("{modules}E 20001 0 0 1 2 1 10102\n"));
    assert_eq!(by_names, by_numbers);

    let from_higher = read(&format!("{modules}E 10102 B -Z E +X A 20001\n"));
    let here = (20001, Connector::new(Side::A, Dock::PlusX));
    let there = (10102, Connector::new(Side::B, Dock::MinusZ));
    for plan in [&by_names, &from_higher] {
        let edge = only(plan).connection_at(here).expect("an edge");
        assert_eq!((edge.to, edge.orientation), (there, Orientation::East));
    }
}

#[test]
fn every_orientation_and_dock_number_reads() {
    let orientations = ["N", "E", "S", "W"];
    for (number, name) in orientations.iter().enumerate() {
        let text = |ori: &str| format!("M 1 0 0 0\nM 2 0 0 0\nE 1 A -X {ori} +X B 2\n");
        let by_name = read(&text(name));
        assert_eq!(by_name, read(&text(&number.to_string())));
        let edge = only(&by_name).connections()[0];
        assert_eq!(edge.orientation, Orientation::ALL[number]);
    }
}

#[test]
fn comments_blank_lines_tabs_and_crlf_are_ignored() {
    let text = "# two modules\r\n\r\nM 1\t0  0 0\r\n   \t\r\n  #indented comment\r\n\
                M 2 0 0 0 \r\nE 1 A -Z N -Z B 2\r\n# end";
    let plain = "M 1 0 0 0\nM 2 0 0 0\nE 1 A -Z N -Z B 2\n";
    assert_eq!(read(text), read(plain));
}

#[test]
fn angles_may_have_exponents_and_gamma_is_circular() {
    let config = read("M 7 1e-05 -2.5E1 540\n").configurations.remove(0).1;
    let module = config.module(7).expect("module 7");
    assert_eq!(
        (module.alpha, module.beta, module.gamma),
        (1e-5, -25.0, 180.0)
    );
}

#[test]
fn an_unknown_line_type_is_refused() {
    let error = refuse("M 1 0 0 0\n  X 1 2\n");
    assert_error(&error, 2, 3, &["expected a line", "`X`"]);
}

#[test]
fn a_missing_field_is_reported_where_it_should_be() {
    let error = refuse("M 1 0 0\n");
    assert_error(&error, 1, 8, &["missing gamma", "an angle in degrees"]);
    let error = refuse("M 1 0 0 0\nM 2 0 0 0\nE 1 A -Z N -Z B\n");
    assert_error(&error, 3, 16, &["missing second module id", "a module id"]);
}

#[test]
fn an_extra_field_is_refused() {
    let error = refuse("M 1 0 0 0 0\n");
    assert_error(&error, 1, 11, &["expected the end of the line", "`0`"]);
    let error = refuse("C extra\nM 1 0 0 0\n");
    assert_error(
        &error,
        1,
        3,
        &["expected the end of the line after `C`", "`extra`"],
    );
}

#[test]
fn each_field_that_does_not_parse_says_what_was_expected() {
    let modules = "M 1 0 0 0\nM 2 0 0 0\n";
    let cases = [
        ("M x 0 0 0\n", 1, 3, "a module id"),
        ("M -1 0 0 0\n", 1, 3, "a module id"),
        ("M 4294967296 0 0 0\n", 1, 3, "a module id"),
        ("M 1 ten 0 0\n", 1, 5, "an angle in degrees"),
        ("M 1 0 nan 0\n", 1, 7, "an angle in degrees"),
        ("M 1 0 0 1e\n", 1, 9, "an angle in degrees"),
        (
            &format!("{modules}E 1 C -Z N -Z B 2\n"),
            3,
            5,
            "a side: A, B, 0 or 1",
        ),
        (
            &format!("{modules}E 1 A +Y N -Z B 2\n"),
            3,
            7,
            "a dock: +X, -X, -Z, 0, 1 or 2",
        ),
        (
            &format!("{modules}E 1 A -Z 4 -Z B 2\n"),
            3,
            10,
            "an orientation: N, E, S, W",
        ),
        (&format!("{modules}E 1 A -Z N 3 B 2\n"), 3, 12, "a dock"),
        (&format!("{modules}E 1 A -Z N -Z 2 2\n"), 3, 15, "a side"),
        (
            &format!("{modules}E 1 A -Z N -Z B +2\n"),
            3,
            17,
            "a module id",
        ),
        (&format!("{modules}length many\n"), 3, 8, "a whole number"),
    ];
    for (text, line, column, expected) in cases {
        let error = refuse(text);
        assert_error(&error, line, column, &[expected]);
    }
}

#[test]
fn columns_count_characters_not_bytes() {
    let error = refuse("M 1 0 0 0\nM 2 0 0 0\nE 1 A -Z N -Z Bé 2\n# é\n");
    assert_error(&error, 3, 15, &["a side", "`Bé`"]);
    let error = refuse("M 1 0 é\n");
    assert_error(&error, 1, 8, &["missing gamma"]);
    let error = refuse("M ééé\t0 0 0 x\n");
    assert_error(&error, 1, 13, &["after gamma", "`x`"]);
}

#[test]
fn an_edge_to_an_undeclared_module_is_refused() {
    let error = refuse("M 1 0 0 0\nE 1 A -Z N -Z B 2\nM 2 0 0 0\n");
    assert_error(
        &error,
        2,
        17,
        &["module 2 is not declared", "expected an `M` line"],
    );
    let error = refuse("M 2 0 0 0\nE 1 A -Z N -Z B 2\n");
    assert_error(&error, 2, 3, &["module 1 is not declared"]);
}

#[test]
fn a_module_of_an_earlier_configuration_is_not_declared_in_the_next() {
    let error = refuse("C\nM 1 0 0 0\nM 2 0 0 0\nC\nM 1 0 0 0\nE 1 A -Z N -Z B 2\n");
    assert_error(&error, 6, 17, &["module 2 is not declared"]);
}

#[test]
fn a_connector_used_twice_is_refused() {
    let modules = "M 1 0 0 0\nM 2 0 0 0\nM 3 0 0 0\n";
    let error = refuse(&format!("{modules}E 1 A -Z N -Z B 2\nE 1 A -Z N +X A 3\n"));
    assert_error(
        &error,
        5,
        3,
        &["already connected", "expected each connector"],
    );
    let error = refuse(&format!("{modules}E 1 A -Z N -Z B 2\nE 3 A +X N -Z B 2\n"));
    assert_error(
        &error,
        5,
        12,
        &["already connected", "expected each connector"],
    );
    // The same edge written once from each end also uses its connectors twice.
    let error = refuse(&format!("{modules}E 1 A -Z N -Z B 2\nE 2 B -Z N -Z A 1\n"));
    assert_error(&error, 5, 3, &["already connected"]);
}

#[test]
fn a_connector_connected_to_itself_is_refused() {
    let error = refuse("M 1 0 0 0\nE 1 A -Z N -Z A 1\n");
    assert_error(
        &error,
        2,
        3,
        &["connected to itself", "two different connectors"],
    );
}

#[test]
fn a_module_declared_twice_is_refused() {
    let error = refuse("M 1 0 0 0\nM 2 0 0 0\n# again\nM  1 5 5 5\n");
    assert_error(
        &error,
        4,
        4,
        &["declared twice", "expected each module id once"],
    );
}

#[test]
fn alpha_or_beta_out_of_range_is_refused_at_its_field() {
    let error = refuse("M 1 90.5 0 0\n");
    assert_error(&error, 1, 5, &["alpha", "-90..90"]);
    let error = refuse("M 1 0 -91 0\n");
    assert_error(&error, 1, 7, &["beta", "-90..90"]);
    let error = refuse("M 1 0 0 1e999\n");
    assert_error(&error, 1, 9, &["gamma", "a finite angle"]);
}

#[test]
fn an_empty_c_block_is_refused_at_its_c() {
    let error = refuse("C\nM 1 0 0 0\n\nC\n# nothing\nC\nM 1 0 0 0\n");
    assert_error(&error, 4, 1, &["expected at least one `M"]);
    let error = refuse("C\nM 1 0 0 0\nC\n");
    assert_error(&error, 3, 1, &["expected at least one `M"]);
    let error = refuse("C\nM 1 0 0 0\nC\nlength 1\n");
    assert_error(&error, 3, 1, &["expected at least one `M"]);
}

#[test]
fn a_file_without_modules_is_refused() {
    for text in ["", "\n\n", "# only a comment\r\n", "length 0\n"] {
        let error = refuse(text);
        assert_error(&error, 1, 1, &["expected at least one `M", "no module"]);
    }
}

#[test]
fn lines_before_the_first_c_are_refused() {
    let error = refuse("# fine\nM 1 0 0 0\nC\nM 1 0 0 0\n");
    assert_error(&error, 2, 1, &["expected `C` before"]);
    let error = refuse("\n  length 3\nC\nM 1 0 0 0\n");
    assert_error(&error, 2, 3, &["expected `C` before"]);
}

#[test]
fn only_the_trailer_may_follow_the_trailer() {
    let error = refuse("C\nM 1 0 0 0\nlength 1\n\nM 2 0 0 0\n");
    assert_error(&error, 5, 1, &["after the trailer", "a module"]);
    let error = refuse("C\nM 1 0 0 0\ncfgs 1\nC\nM 2 0 0 0\n");
    assert_error(&error, 4, 1, &["after the trailer", "a configuration"]);
    let error = refuse("M 1 0 0 0\nqueue 1\n E 1 A -Z N -Z B 1\n");
    assert_error(&error, 3, 2, &["after the trailer", "an edge"]);
}

#[test]
fn an_error_displays_its_place() {
    let error = refuse("M 1 0 0\n");
    assert!(
        error.to_string().starts_with("line 1, column 8: "),
        "{error}"
    );
}

proptest! {
    #[test]
    fn arbitrary_text_never_panics_and_errors_stay_in_the_file(text in any::<String>()) {
        check_any(&text)?;
    }

    #[test]
    fn format_like_text_never_panics_and_errors_stay_in_the_file(
        text in "([CMEl#0-9AB+XZ\\-NSW. \t\r\n]|length|queue|cfgs|é){0,200}"
    ) {
        check_any(&text)?;
    }
}

fn check_any(text: &str) -> Result<(), TestCaseError> {
    let lines = text.split('\n').count();
    if let Err(error) = read_old_format(text) {
        prop_assert!(
            (1..=lines + 1).contains(&error.line),
            "{error} in {lines} lines"
        );
        prop_assert!(error.column >= 1, "{error}");
        prop_assert!(!error.message.is_empty());
    }
    Ok(())
}
