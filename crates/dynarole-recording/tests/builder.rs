//! The recording of the first turn of eight2car (paper Fig. 5) on the eight: the latch the
//! retract releases, the motion the world model plans, the poses mid-turn (from
//! `TurnMotion::position_at`), the round trip through the format, and the reader's checks of
//! the fields it follows.

use dynarole_core::{analyze, parse, RobotRegistry};
use dynarole_recording::{poses_at, Builder, Recording};
use dynarole_world::Configuration;

const SOURCE: &str = "robot atron;\nsequence s {\n    M0.Connector[0].retract();\n    M3.Connector[4].retract();\n    M3.Joint.rotateFromToBy(0, 324, false, 150);\n}\n";
const EIGHT: &str = include_str!("../../../examples/atron/eight.json");

fn recording() -> Recording {
    let parsed = parse(SOURCE);
    let (program, diagnostics) = analyze(&parsed.file, &RobotRegistry::builtin());
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let program = program.expect("a program");
    let plan = program.expand("s").expect("sequence s");
    let statements: Vec<_> = plan.statements().into_iter().cloned().collect();
    let texts: Vec<String> = statements
        .iter()
        .map(|s| s.describe(&program.robot))
        .collect();
    let start = Configuration::from_json_str(EIGHT).expect("the eight");
    let mut builder = Builder::new(
        "replay",
        "t",
        &start,
        &program.robot,
        &statements,
        &texts,
        None,
    )
    .expect("builder");
    builder.event(0.0, Some(0), "start", "-", "#0 retract");
    builder.event(2.0, Some(3), "start", "-", "#1 retract");
    builder.event(50.0, Some(0), "done", "-", "#0 retract");
    builder.event(52.0, Some(3), "done", "-", "#1 retract");
    builder.event(100.0, Some(3), "start", "-", "#2 turn");
    builder.event(650.0, Some(3), "done", "-", "#2 turn");
    builder.finish(2000.0, Vec::new())
}

#[test]
fn a_turn_moves_the_smaller_side_smoothly_and_ends_where_the_world_does() {
    let r = recording();
    let motion = &r.motions[2];
    let turn = motion.turn.as_ref().expect("a turn");
    assert_eq!(motion.outcome, "done");
    assert_eq!(turn.angle_deg.abs(), 90.0);
    assert_eq!(turn.moving, vec![0, 1], "M0 and M1 on the moving side");
    assert_eq!(
        r.motions[0].released.len(),
        1,
        "the retract released a latch"
    );
    let moving = turn.moving[0];
    let before = poses_at(&r, 100.0).expect("poses")[moving].centre;
    let middle = poses_at(&r, 375.0).expect("poses")[moving].centre;
    let after = poses_at(&r, 650.0).expect("poses")[moving].centre;
    assert_ne!(before, after);
    // Half way through a quarter turn about the pivot: as far from it, between the two.
    let distance = |p: [f64; 3]| {
        ((p[0] - turn.pivot[0]).powi(2)
            + (p[1] - turn.pivot[1]).powi(2)
            + (p[2] - turn.pivot[2]).powi(2))
        .sqrt()
    };
    assert!((distance(middle) - distance(before)).abs() < 1e-9);
    assert!(middle != before && middle != after);
    // What the page reads back is what was written.
    let text = serde_json::to_string(&r).expect("serialises");
    let back = Recording::from_json(&text).expect("reads back");
    assert_eq!(back, r);
}

#[test]
fn the_reader_names_the_field_that_points_nowhere() {
    let mut r = recording();
    r.motions[0].module = 7;
    let text = serde_json::to_string(&r).expect("serialises");
    let error = Recording::from_json(&text).expect_err("refused");
    assert!(error.contains("motions[0]"), "{error}");
    r.motions[0].module = 1;
    r.keyframes.clear();
    let text = serde_json::to_string(&r).expect("serialises");
    assert!(Recording::from_json(&text)
        .expect_err("refused")
        .contains("keyframes"));
}
