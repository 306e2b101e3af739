//! The recording of the first turn of eight2car (paper Fig. 5) on the eight: the latch the
//! retract releases, the motion the world model plans, the poses mid-turn (from
//! `Motion::position_at`), the round trip through the format, and the reader's checks of
//! the fields it follows.

use dynarole_core::{analyze, parse};
use dynarole_recording::{poses_at, Builder, Path, Recording, TraceEvent};
use dynarole_world::Leg;

const SOURCE: &str = "robot atron;\nsequence s {\n    M0.Connector[0].retract();\n    M3.Connector[4].retract();\n    M3.Joint.rotateFromToBy(0, 324, false, 150);\n}\n";
const EIGHT: &str = include_str!("../../../robots/atron/examples/eight.json");
const MOVE_MODULE: &str = include_str!("../../../robots/mtran/examples/move_module.dr");
const SNAKE4: &str = include_str!("../../../robots/mtran/examples/mtran-snake4.json");

fn recording() -> Recording {
    let events = [
        (0.0, 0, TraceEvent::Start, "#0 retract"),
        (2.0, 3, TraceEvent::Start, "#1 retract"),
        (50.0, 0, TraceEvent::Done, "#0 retract"),
        (52.0, 3, TraceEvent::Done, "#1 retract"),
        (100.0, 3, TraceEvent::Start, "#2 turn"),
        (650.0, 3, TraceEvent::Done, "#2 turn"),
    ];
    built(SOURCE, "s", EIGHT, &events, 2000.0)
}

/// A recording of `sequence` of `source` from `start`, fed `events` (time, module, event,
/// detail).
fn built(
    source: &str,
    sequence: &str,
    start: &str,
    events: &[(f64, usize, TraceEvent, &str)],
    end_ms: f64,
) -> Recording {
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let program = program.expect("a program");
    let plan = program.expand(sequence).expect("the sequence");
    let statements: Vec<_> = plan.statements().into_iter().cloned().collect();
    let texts: Vec<String> = statements
        .iter()
        .map(|s| s.describe(&program.robot))
        .collect();
    let start = dynarole_robots::read_configuration(start).expect("the start");
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
    for (time, module, event, detail) in events {
        builder.event(*time, Some(*module), *event, "-", detail);
    }
    builder.finish(end_ms, Vec::new())
}

/// The pivot and angle of a path of one rotation.
fn rotation(path: &Path) -> ([f64; 3], f64) {
    match path.legs.as_slice() {
        [Leg::Rotate {
            pivot, angle_deg, ..
        }] => (*pivot, *angle_deg),
        other => panic!("not one rotation: {other:?}"),
    }
}

#[test]
fn a_turn_moves_the_smaller_side_smoothly_and_ends_where_the_world_does() {
    let r = recording();
    let motion = &r.motions[2];
    let turn = motion.path.as_ref().expect("a turn");
    let (pivot, angle_deg) = rotation(turn);
    assert_eq!(motion.outcome, "done");
    assert_eq!(angle_deg.abs(), 90.0);
    assert_eq!(turn.modules, vec![0, 1], "M0 and M1 on the moving side");
    assert_eq!(
        turn.parts,
        vec![[motion.module, 1]],
        "the turner's south half"
    );
    assert_eq!(
        r.motions[0].released.len(),
        1,
        "the retract released a latch"
    );
    let moving = turn.modules[0];
    let before = poses_at(&r, 100.0).expect("poses")[moving].centre;
    let middle = poses_at(&r, 375.0).expect("poses")[moving].centre;
    let after = poses_at(&r, 650.0).expect("poses")[moving].centre;
    assert_ne!(before, after);
    // Half way through a quarter turn about the pivot: as far from it, between the two.
    let distance = |p: [f64; 3]| {
        ((p[0] - pivot[0]).powi(2) + (p[1] - pivot[1]).powi(2) + (p[2] - pivot[2]).powi(2)).sqrt()
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

/// An event or a marker kind outside the vocabulary is refused, naming its field: the page
/// would have no colour nor meaning for it.
#[test]
fn the_reader_refuses_a_word_outside_the_vocabulary() {
    let mut r = recording();
    r.events[2].event = "frobnicate".into();
    let text = serde_json::to_string(&r).expect("serialises");
    let error = Recording::from_json(&text).expect_err("refused");
    assert!(
        error.starts_with("field `events[2].event`: `frobnicate` is not a trace event (one of "),
        "{error}"
    );
    r.events[2].event = "done".into();
    r.markers.push(dynarole_recording::Marker {
        time_ms: 1.0,
        kind: "glitch".into(),
        modules: vec![0],
        label: "?".into(),
    });
    let text = serde_json::to_string(&r).expect("serialises");
    let error = Recording::from_json(&text).expect_err("refused");
    assert!(
        error.starts_with("field `markers[0].kind`: `glitch`"),
        "{error}"
    );
}

/// M-TRAN: the world model lists moving blocks, the turner's own among them; the recording
/// names each other module once and the turner's moving block as its half, so that every
/// turn ends (fraction 1) exactly where the world model puts the robot after it.
#[test]
fn mtran_turns_move_their_blocks_and_end_where_the_world_does() {
    // The four bends, one after the other, each by its own module (M10..M13 are 0..3).
    let events: Vec<(f64, usize, TraceEvent, String)> = (0u32..4)
        .flat_map(|k| {
            let t = 1000.0 * f64::from(k);
            let m = k as usize;
            [
                (t, m, TraceEvent::Start, format!("#{k} turn")),
                (t + 550.0, m, TraceEvent::Done, format!("#{k} turn")),
            ]
        })
        .collect();
    let events: Vec<_> = events
        .iter()
        .map(|(t, m, e, d)| (*t, *m, *e, d.as_str()))
        .collect();
    let r = built(MOVE_MODULE, "left2right", SNAKE4, &events, 5000.0);
    for motion in &r.motions {
        let turn = motion
            .path
            .as_ref()
            .expect("an M-TRAN joint turn has a motion");
        assert_eq!(rotation(turn).1.abs(), 90.0);
        assert!(!turn.modules.contains(&motion.module), "{turn:?}");
        assert!(turn.modules.windows(2).all(|w| w[0] < w[1]), "{turn:?}");
        assert_eq!(turn.parts.len(), 1, "the turner's moving block: {turn:?}");
        let near_end = poses_at(&r, motion.end_ms - 1e-9).expect("poses");
        let after = poses_at(&r, motion.end_ms).expect("poses");
        let before = poses_at(&r, motion.start_ms).expect("poses");
        let middle = poses_at(&r, (motion.start_ms + motion.end_ms) / 2.0).expect("poses");
        for (m, (a, b)) in near_end.iter().zip(&after).enumerate() {
            let mut points = vec![(a.centre, b.centre)];
            points.extend(
                a.parts
                    .iter()
                    .zip(&b.parts)
                    .map(|(x, y)| (x.centre, y.centre)),
            );
            points.extend(
                a.connectors
                    .iter()
                    .copied()
                    .zip(b.connectors.iter().copied()),
            );
            for (x, y) in points {
                let gap = (0..3).map(|i| (x[i] - y[i]).abs()).fold(0.0, f64::max);
                assert!(
                    gap < 1e-6,
                    "module {m} at the end of {motion:?}: {x:?} vs {y:?}"
                );
            }
        }
        // Mid-turn the turner's moving block is between its places before and after.
        let connectors = |p: &[dynarole_recording::Pose]| p[motion.module].connectors.clone();
        assert_ne!(connectors(&middle), connectors(&before));
        assert_ne!(connectors(&middle), connectors(&after));
    }
}
