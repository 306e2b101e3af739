//! The paper's Sec. V-B experiment on the M-TRAN model: the end module of a straight
//! four-module snake is moved to the other end using only connect/disconnect of male
//! connectors and 90-degree joint moves within -90..90, and the automatically reversed
//! sequence moves it back.

use dynarole_robot_mtran::{MtranJoint, MtranWorld};
use dynarole_world::{compare, Configuration, OpError, RobotKind, Warning};
use serde_json::{json, Value};
use MtranJoint::North;

/// One M-TRAN API call.
#[derive(Clone, Copy, Debug)]
enum Statement {
    Connect(&'static str, u8),
    Disconnect(&'static str, u8),
    /// module, joint, from, to, positive direction
    Rotate(&'static str, MtranJoint, i16, i16, bool),
}
use Statement::{Connect, Disconnect, Rotate};

impl Statement {
    fn reversed(self) -> Statement {
        match self {
            Connect(m, c) => Disconnect(m, c),
            Disconnect(m, c) => Connect(m, c),
            Rotate(m, j, f, t, d) => Rotate(m, j, t, f, !d),
        }
    }
}

/// The snake closes into a ring (3 x 3 blocks, every north joint at +90), T10's free male end
/// connector latches onto T13's free female end, T11 lets go of T10, and the ring opens again
/// at the new gap. Each turn moves the smaller side, so the arm that swings is never long.
fn move_end_module() -> Vec<Statement> {
    vec![
        Rotate("T10", North, 0, 90, true),
        Rotate("T11", North, 0, 90, true),
        Rotate("T12", North, 0, 90, true),
        Rotate("T13", North, 0, 90, true),
        Connect("T10", 0),
        Disconnect("T11", 0),
        Rotate("T10", North, 90, 0, false),
        Rotate("T11", North, 90, 0, false),
        Rotate("T12", North, 90, 0, false),
        Rotate("T13", North, 90, 0, false),
    ]
}

fn run(world: &mut MtranWorld, statement: Statement) -> Result<Vec<Warning>, OpError> {
    let outcome = match statement {
        Connect(m, c) => world.connect(m, c)?,
        Disconnect(m, c) => world.disconnect(m, c)?,
        Rotate(m, j, f, t, d) => world.rotate(m, j, f, t, d)?,
    };
    // No block ever passes closer to another than face-to-face neighbours sit.
    if let Some(d) = outcome.closest_approach {
        assert!(d >= 1.0 - 1e-9, "{statement:?}: closest approach {d}");
    }
    Ok(outcome.warnings)
}

/// Runs a sequence that must raise no error and no warning, re-validating after each step.
fn replay(world: &mut MtranWorld, sequence: &[Statement]) -> Result<(), String> {
    for (i, statement) in sequence.iter().enumerate() {
        let warnings =
            run(world, *statement).map_err(|e| format!("step {i} {statement:?}: {e}"))?;
        if !warnings.is_empty() {
            return Err(format!("step {i} {statement:?}: {warnings:?}"));
        }
        let text = Configuration::new(world.configuration().clone()).to_json_string();
        dynarole_robot_mtran::KIND
            .read_configuration(&text)
            .map_err(|e| format!("step {i}: invalid: {e}"))?;
    }
    Ok(())
}

/// The straight snake T11-T12-T13-T10 (T10 moved to the far end).
fn expected_result() -> Result<Configuration, String> {
    let mut value: Value =
        serde_json::from_str(text("mtran-snake4")?).map_err(|e| e.to_string())?;
    for (i, x) in [(0, 6), (1, 0), (2, 2), (3, 4)] {
        value["modules"][i]["position"] = json!([x, 0, 0]);
    }
    value["connections"] = json!([
        ["T12", 0, "T11", 3],
        ["T13", 0, "T12", 3],
        ["T10", 0, "T13", 3]
    ]);
    dynarole_robot_mtran::KIND
        .read_configuration(&value.to_string())
        .map_err(|e| e.to_string())
}

fn start() -> Result<MtranWorld, String> {
    let config = load("mtran-snake4")?;
    let snake = config
        .downcast_ref::<dynarole_robot_mtran::MtranConfiguration>()
        .ok_or("not M-TRAN")?
        .clone();
    Ok(MtranWorld::new(snake))
}

#[test]
fn the_end_module_moves_to_the_other_end_and_back() -> Result<(), String> {
    let mut world = start()?;
    replay(&mut world, &move_end_module())?;
    let reached = Configuration::new(world.configuration().clone());
    compare(&reached, &expected_result()?).map_err(|d| d.to_string())?;

    let reverse: Vec<Statement> = move_end_module()
        .iter()
        .rev()
        .map(|s| s.reversed())
        .collect();
    replay(&mut world, &reverse)?;
    let back = Configuration::new(world.configuration().clone());
    compare(&back, &load("mtran-snake4")?).map_err(|d| d.to_string())?;
    // Exactly, not only up to rigid motion.
    assert_eq!(
        Some(world.configuration()),
        load("mtran-snake4")?.downcast_ref::<dynarole_robot_mtran::MtranConfiguration>()
    );
    Ok(())
}

#[test]
fn the_ring_closes_with_the_end_connectors_facing() -> Result<(), String> {
    let mut world = start()?;
    replay(&mut world, &move_end_module()[..4])?;
    let config = world.configuration();
    let t10 = config.module_index("T10").ok_or("no T10")?;
    let t13 = config.module_index("T13").ok_or("no T13")?;
    let facing = config.facing(dynarole_world::Port {
        module: t10,
        connector: 0,
    });
    assert_eq!(
        facing,
        Some(dynarole_world::Port {
            module: t13,
            connector: 3
        })
    );
    Ok(())
}

#[test]
fn mtran_rejections() -> Result<(), String> {
    let mut world = start()?;
    // Female connectors are not commanded.
    assert!(matches!(
        world.connect("T10", 3),
        Err(OpError::FemaleConnector { .. })
    ));
    assert!(matches!(
        world.disconnect("T10", 4),
        Err(OpError::FemaleConnector { .. })
    ));
    // Nothing faces T10's end connector 0 in the straight snake.
    assert!(matches!(
        world.connect("T10", 0),
        Err(OpError::NothingToLatchOnto { .. })
    ));
    // Already connected / nothing connected are reported.
    let warnings = run(&mut world, Connect("T11", 0)).map_err(|e| e.to_string())?;
    assert!(matches!(
        warnings.as_slice(),
        [Warning::AlreadyLatched { .. }]
    ));
    let warnings = run(&mut world, Disconnect("T10", 1)).map_err(|e| e.to_string())?;
    assert!(matches!(
        warnings.as_slice(),
        [Warning::NothingLatched { .. }]
    ));
    // Angles: wrong start, out of range, not a lattice step, direction against the range.
    let rotate = |w: &mut MtranWorld, f, t, d| w.rotate("T11", North, f, t, d);
    assert!(matches!(
        rotate(&mut world, 90, 0, false),
        Err(OpError::WrongStartAngle { .. })
    ));
    assert!(matches!(
        rotate(&mut world, 0, 180, true),
        Err(OpError::InvalidAngle { .. })
    ));
    assert!(matches!(
        rotate(&mut world, 0, 45, true),
        Err(OpError::InvalidAngle { .. })
    ));
    assert!(matches!(
        rotate(&mut world, 0, 90, false),
        Err(OpError::InvalidAngle { .. })
    ));
    // The most negative angle has no absolute value: refused, never a panic.
    assert!(matches!(
        rotate(&mut world, 0, i16::MIN, false),
        Err(OpError::InvalidAngle { .. })
    ));
    // Fold the snake into a U at T11 (legal: T12 lies beside T10), then turn T12 inwards:
    // T12's south block would swing onto T10's south block.
    let fold = [
        Rotate("T11", North, 0, 90, true),
        Rotate("T11", MtranJoint::South, 0, 90, true),
    ];
    replay(&mut world, &fold)?;
    let before = world.clone();
    let err = world.rotate("T12", North, 0, 90, true);
    match err {
        Err(OpError::SweepCollision {
            moving,
            still,
            distance,
            ..
        }) => {
            assert_eq!((moving.as_str(), still.as_str()), ("T12", "T10"));
            assert!(distance < 0.5, "{distance}");
        }
        other => return Err(format!("expected a sweep collision, got {other:?}")),
    }
    assert_eq!(world, before);
    // Disconnecting the middle splits the snake.
    let warnings = run(&mut world, Disconnect("T12", 0)).map_err(|e| e.to_string())?;
    assert!(matches!(warnings.as_slice(), [Warning::Split { .. }]));
    Ok(())
}

#[test]
fn a_closed_ring_cannot_turn() -> Result<(), String> {
    let mut world = start()?;
    replay(&mut world, &move_end_module()[..5])?;
    let err = world.rotate("T12", North, 90, 0, false);
    assert!(matches!(err, Err(OpError::JointLocked { .. })), "{err:?}");
    Ok(())
}

/// The text of one of this robot's examples.
fn text(name: &str) -> Result<&'static str, String> {
    match name {
        "mtran-snake4" => Ok(include_str!("../examples/mtran-snake4.json")),
        "mtran-snake4-moved" => Ok(include_str!("../examples/mtran-snake4-moved.json")),
        other => Err(format!("no data file {other}")),
    }
}

/// One of this robot's examples, read by its own kind.
fn load(name: &str) -> Result<Configuration, String> {
    (dynarole_robot_mtran::KIND.read_configuration(text(name)?)).map_err(|e| format!("{name}: {e}"))
}
