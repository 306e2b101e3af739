//! The program driver: robot lookup, diagnostics in order, sequence selection and lowering.

use dynarole_core::driver::{self, SelectError, Shape};
use dynarole_core::lower::LimitError;
use dynarole_core::{parse, Diagnostic, DiagnosticKind, RobotApi, Span};

const SNAKEBOT: &str = include_str!("../../dynarole-cli/tests/golden/snakebot.robot.toml");

const TWO: &str = "robot atron;
sequence first { M0.Connector[0].retract(); }
sequence second { { M1.Connector[0].retract(); M2.Connector[0].retract(); } & first; }
";

fn snakebot() -> RobotApi {
    RobotApi::from_toml(SNAKEBOT).expect("the snakebot plugin parses")
}

#[test]
fn the_plugin_beside_the_source_is_asked_for_an_unknown_robot_only() {
    let parsed =
        parse("robot snakebot;\nsequence s { M2.Hinge.bend(45); M2.Gripper[$FRONT].close(); }\n");
    let mut asked = Vec::new();
    let registry = driver::registry(
        dynarole_robots::plugins(),
        driver::robot_name(&parsed.file),
        [],
        |file| {
            asked.push(file.to_string());
            Ok::<_, ()>(Some(snakebot()))
        },
    )
    .expect("the lookup does not fail");
    assert_eq!(asked, ["snakebot.robot.toml"]);
    let checked = driver::check(&parsed, &registry);
    assert!(checked.is_ok(), "{:?}", checked.err());

    let registry = driver::registry(
        dynarole_robots::plugins(),
        Some("snakebot"),
        [snakebot()],
        |_| Err("a robot given as a plugin is not looked up again"),
    );
    assert!(registry.is_ok());
    let registry = driver::registry(dynarole_robots::plugins(), Some("atron"), [], |_| {
        Err("a built-in robot is known")
    });
    assert!(registry.is_ok());
}

#[test]
fn a_failing_lookup_is_the_callers_error() {
    let failed = driver::registry(dynarole_robots::plugins(), Some("nosuchbot"), [], |file| {
        Err(format!("cannot read {file}"))
    });
    assert_eq!(
        failed.err(),
        Some("cannot read nosuchbot.robot.toml".to_string())
    );
}

#[test]
fn check_returns_syntax_and_checking_errors_in_source_order() {
    let parsed = parse(
        "robot atron;\nsequence s { M0.Nope[0].x(); }\nsequence t { M0.Connector[0].retract() }\n",
    );
    let registry = driver::registry(dynarole_robots::plugins(), None, [], |_| Ok::<_, ()>(None))
        .expect("no lookup");
    let errors = driver::check(&parsed, &registry).expect_err("the file has errors");
    assert!(errors.len() >= 2, "{errors:?}");
    assert!(
        errors.windows(2).all(|w| w[0].span <= w[1].span),
        "{errors:?}"
    );
}

#[test]
fn the_first_sequence_is_the_default_and_an_unknown_one_gets_a_suggestion() {
    let parsed = parse(TWO);
    let program = driver::check(&parsed, &dynarole_robots::plugins()).expect("TWO checks");
    assert_eq!(
        driver::select_sequences(&program, &[]),
        Ok(vec!["first".to_string()])
    );
    let wanted = ["second".to_string(), "frist".to_string()];
    let error = driver::select_sequences(&program, &wanted).expect_err("frist is unknown");
    assert!(
        matches!(error, SelectError::Unknown { index: 1, .. }),
        "{error:?}"
    );
    assert_eq!(
        error.message("two.dr"),
        "no sequence `frist` in two.dr; did you mean `first`? sequences in two.dr: first, second"
    );
    let plans = driver::plans(&program, &wanted[..1]).expect("second expands");
    assert_eq!(plans.len(), 1);
}

#[test]
fn a_file_without_sequences_has_nothing_to_run() {
    let parsed = parse("robot atron;\n");
    let program =
        driver::check(&parsed, &dynarole_robots::plugins()).expect("an empty program checks");
    let error = driver::select_sequences(&program, &[]).expect_err("nothing to run");
    assert_eq!(error, SelectError::NoSequence);
    assert!(error
        .message("e.dr")
        .starts_with("e.dr declares no sequence"));
}

#[test]
fn a_flat_protocol_refuses_nested_blocks_that_a_nested_one_lowers() {
    let parsed = parse(TWO);
    let program = driver::check(&parsed, &dynarole_robots::plugins()).expect("TWO checks");
    let plans = driver::plans(&program, &["second".to_string()]).expect("second expands");
    assert!(driver::lower(&program, &plans, Shape::Nested).is_ok());
    let refused = driver::lower(&program, &plans, Shape::Flat).expect_err("nested block");
    assert!(
        matches!(
            refused.kind,
            DiagnosticKind::NotSupportedByPaperProtocol { .. }
        ),
        "{refused:?}"
    );
    let at = usize::try_from(refused.span.start).expect("a span fits usize");
    assert!(TWO[at..].starts_with("{ M1"), "{refused:?}");
}

#[test]
fn a_limit_error_is_a_target_limit_at_its_span() {
    let span = Span::new(3, 9);
    let d = Diagnostic::from(LimitError {
        message: "too many".into(),
        span,
    });
    assert_eq!(d.span, span);
    assert_eq!(
        d.kind,
        DiagnosticKind::TargetLimit {
            message: "too many".into()
        }
    );
}
