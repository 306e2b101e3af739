//! Every acceptance rule of the ATRON world on small configurations: what is rejected, what is
//! only reported, and which side of a joint moves.

mod common;

use common::load_atron;
use dynarole_robot_atron::{AtronConfiguration, AtronModule, Orientation, World};
use dynarole_world::{Metadata, OpError, Rotation, Vec3, Warning};

/// A module at `position` whose axis is `axis`, spun so that the connector facing `toward`
/// (a neighbour site) has the wanted gender; the 24 frames are searched.
fn module_facing(name: &str, position: Vec3, axis: Vec3, toward: Vec3, male: bool) -> AtronModule {
    let offset = [
        toward[0] - position[0],
        toward[1] - position[1],
        toward[2] - position[2],
    ];
    let orientation = Rotation::all()
        .into_iter()
        .map(Orientation::from_frame)
        .filter(|o| o.axis() == axis)
        .find(|o| {
            (0..8u8).any(|c| o.connector_offset(0, c) == Some(offset) && (c % 2 == 0) == male)
        })
        .unwrap_or_else(|| Orientation::from_frame(Rotation::IDENTITY));
    AtronModule {
        name: name.to_string(),
        id: None,
        ussr_name: None,
        position,
        orientation,
        joint_units: 0,
    }
}

/// The connector of `module` that faces site `toward`.
fn connector_toward(module: &AtronModule, toward: Vec3) -> u8 {
    let offset = [
        toward[0] - module.position[0],
        toward[1] - module.position[1],
        toward[2] - module.position[2],
    ];
    (0..8u8)
        .find(|c| module.connector_offset(*c) == Some(offset))
        .unwrap_or(99)
}

/// Builds a configuration, latching each listed pair through the connectors facing each other.
fn build(modules: Vec<AtronModule>, pairs: &[(usize, usize)]) -> Result<World, String> {
    let connections: Vec<_> = pairs
        .iter()
        .map(|(a, b)| {
            let (ma, mb) = (&modules[*a], &modules[*b]);
            (
                ma.name.clone(),
                connector_toward(ma, mb.position),
                mb.name.clone(),
                connector_toward(mb, ma.position),
            )
        })
        .collect();
    AtronConfiguration::new(Metadata::default(), modules, &connections)
        .map(World::new)
        .map_err(|e| e.to_string())
}

#[test]
fn extend_onto_nothing_is_an_error() -> Result<(), String> {
    let mut world = World::new(load_atron("rotation-chain-1")?);
    let before = world.clone();
    match world.extend("M0", 0) {
        Err(OpError::NothingToLatchOnto { port, reason }) => {
            assert_eq!(port, "M0.C0");
            assert!(reason.contains("empty"), "{reason}");
        }
        other => return Err(format!("expected NothingToLatchOnto, got {other:?}")),
    }
    assert_eq!(world, before);
    Ok(())
}

#[test]
fn extend_onto_a_facing_male_is_an_error() -> Result<(), String> {
    // Two unlatched neighbours whose facing connectors are both male.
    let a = module_facing("A", [0, 0, 0], [0, 0, 1], [1, 0, 1], true);
    let b = module_facing("B", [1, 0, 1], [1, 0, 0], [0, 0, 0], true);
    let mut world = build(vec![a.clone(), b], &[])?;
    let err = world.extend("A", connector_toward(&a, [1, 0, 1]));
    match err {
        Err(OpError::NothingToLatchOnto { reason, .. }) => {
            assert!(reason.contains("male"), "{reason}")
        }
        other => return Err(format!("expected NothingToLatchOnto, got {other:?}")),
    }
    Ok(())
}

#[test]
fn extend_latches_onto_a_facing_female() -> Result<(), String> {
    let a = module_facing("A", [0, 0, 0], [0, 0, 1], [1, 0, 1], true);
    let b = module_facing("B", [1, 0, 1], [1, 0, 0], [0, 0, 0], false);
    let mut world = build(vec![a.clone(), b], &[])?;
    let c = connector_toward(&a, [1, 0, 1]);
    let outcome = world.extend("A", c).map_err(|e| e.to_string())?;
    assert!(outcome.warnings.is_empty());
    assert_eq!(world.configuration().latches().len(), 1);
    // Extending again is a reported no-op.
    let again = world.extend("A", c).map_err(|e| e.to_string())?;
    assert!(matches!(
        again.warnings.as_slice(),
        [Warning::AlreadyLatched { .. }]
    ));
    assert_eq!(world.configuration().latches().len(), 1);
    Ok(())
}

#[test]
fn extend_of_a_female_connector_is_an_error() -> Result<(), String> {
    let mut world = World::new(load_atron("eight")?);
    let err = world.extend("M2", 1);
    assert!(
        matches!(
            err,
            Err(OpError::FemaleConnector {
                action: "extend",
                ..
            })
        ),
        "{err:?}"
    );
    Ok(())
}

#[test]
fn retract_of_a_female_connector_is_an_error() -> Result<(), String> {
    let mut world = World::new(load_atron("eight")?);
    let before = world.clone();
    let err = world.retract("M2", 1);
    match &err {
        Err(e @ OpError::FemaleConnector { port, action }) => {
            assert_eq!((port.as_str(), *action), ("M2.C1", "retract"));
            assert!(e.to_string().contains("female"));
        }
        other => return Err(format!("expected FemaleConnector, got {other:?}")),
    }
    assert_eq!(world, before);
    Ok(())
}

#[test]
fn retract_with_nothing_latched_is_reported() -> Result<(), String> {
    let mut world = World::new(load_atron("eight")?);
    let outcome = world.retract("M0", 2).map_err(|e| e.to_string())?;
    assert!(
        matches!(outcome.warnings.as_slice(), [Warning::NothingLatched { port }] if port == "M0.C2")
    );
    Ok(())
}

#[test]
fn retract_that_splits_the_robot_is_reported() -> Result<(), String> {
    let mut world = World::new(load_atron("rotation-chain-5")?);
    let outcome = world.retract("M1", 2).map_err(|e| e.to_string())?;
    match outcome.warnings.as_slice() {
        [Warning::Split { first, second }] => {
            assert_eq!(first, &["M0", "M1"]);
            assert_eq!(second, &["M2", "M3", "M4"]);
        }
        other => return Err(format!("expected a split warning, got {other:?}")),
    }
    // Retracting a latch inside a loop does not split anything.
    let mut eight = World::new(load_atron("eight")?);
    let outcome = eight.retract("M0", 0).map_err(|e| e.to_string())?;
    assert!(outcome.warnings.is_empty());
    Ok(())
}

#[test]
fn rotate_from_the_wrong_angle_is_an_error() -> Result<(), String> {
    let mut world = World::new(load_atron("rotation-chain-5")?);
    let err = world.rotate("M2", 108, 216, true);
    assert!(
        matches!(
            err,
            Err(OpError::WrongStartAngle {
                from: 108,
                actual: 0,
                ..
            })
        ),
        "{err:?}"
    );
    let err = world.rotate("M2", 0, 100, true);
    assert!(
        matches!(err, Err(OpError::InvalidAngle { angle: 100, .. })),
        "{err:?}"
    );
    let err = world.rotate("M9", 0, 108, true);
    assert!(matches!(err, Err(OpError::UnknownModule { .. })), "{err:?}");
    Ok(())
}

#[test]
fn rotate_inside_a_loop_is_an_error() -> Result<(), String> {
    // The left half of the eight: a ring of four modules.
    let eight = load_atron("eight")?;
    let ring: Vec<AtronModule> = eight.modules()[..4].to_vec();
    let connections = [
        ("M0".to_string(), 0, "M2".to_string(), 1),
        ("M0".to_string(), 4, "M1".to_string(), 3),
        ("M3".to_string(), 6, "M1".to_string(), 7),
        ("M3".to_string(), 2, "M2".to_string(), 5),
    ];
    let config = AtronConfiguration::new(Metadata::default(), ring, &connections)
        .map_err(|e| e.to_string())?;
    let mut world = World::new(config);
    let before = world.clone();
    let err = world.rotate("M0", 0, 108, true);
    match &err {
        Err(e @ OpError::JointLocked { module, .. }) => {
            assert_eq!(module, "M0");
            assert!(e.to_string().contains("loop"));
        }
        other => return Err(format!("expected JointLocked, got {other:?}")),
    }
    assert_eq!(world, before);
    // Releasing one latch of the ring frees the joint.
    world.retract("M0", 0).map_err(|e| e.to_string())?;
    world
        .rotate("M0", 0, 108, true)
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// Pivot P (NS at the origin) with a two-module arm A-A2 on its north hemisphere, a two-module
/// anchor on its south hemisphere (a tie, so the north side turns) and an unattached module O
/// at (1, 2, -1). Turning the north side by +90 deg about z carries A2 from (2, 1, -1) through
/// O's site 36.9 deg into the turn, although both end poses are clear.
fn sweep_world() -> Result<World, String> {
    let p = module_facing("P", [0, 0, 0], [0, 0, 1], [1, 0, -1], true);
    let a = module_facing("A", [1, 0, -1], [1, 0, 0], [0, 0, 0], false);
    let a2 = module_facing("A2", [2, 1, -1], [0, 1, 0], [1, 0, -1], false);
    let south = p.connector_offset(4).unwrap_or_default();
    let b = module_facing("B", south, [1, 0, 0], [0, 0, 0], false);
    let b2_site = [south[0] + 1, south[1] + 1, south[2]];
    let b2 = module_facing("B2", b2_site, [0, 1, 0], south, false);
    let o = module_facing("O", [1, 2, -1], [1, 0, 0], [2, 1, -1], true);
    let world = build(vec![p, a, a2, b, b2, o], &[(0, 1), (1, 2), (0, 3), (3, 4)])?;
    // The latch between A and A2 needs a male and a female side: check it exists.
    assert_eq!(world.configuration().latches().len(), 4);
    Ok(world)
}

#[test]
fn rotate_that_sweeps_through_a_module_is_an_error() -> Result<(), String> {
    let mut world = sweep_world()?;
    let before = world.clone();
    // Decreasing the joint turns the north side by +90 deg about the axis (+z).
    let err = world.rotate("P", 0, 324, false);
    match &err {
        Err(OpError::SweepCollision {
            moving,
            still,
            distance,
            angle_deg,
            ..
        }) => {
            assert_eq!((moving.as_str(), still.as_str()), ("A2", "O"));
            assert!(*distance < 1e-9, "{distance}");
            assert!((angle_deg - 36.87).abs() < 0.01, "{angle_deg}");
        }
        other => return Err(format!("expected SweepCollision, got {other:?}")),
    }
    assert_eq!(world, before);
    // The other way round is clear.
    let outcome = world.rotate("P", 0, 108, true).map_err(|e| e.to_string())?;
    assert_eq!(outcome.moved, ["A", "A2"]);
    Ok(())
}

#[test]
fn the_larger_side_stays_and_a_tie_moves_the_north_side() -> Result<(), String> {
    // Chain M0..M9: M2 holds M0-M1 on its north hemisphere (connector 1) and M3..M9 on its
    // south one (connector 5): the north side, the smaller, moves.
    let mut world = World::new(load_atron("rotation-chain-10")?);
    let outcome = world
        .rotate("M2", 0, 108, true)
        .map_err(|e| e.to_string())?;
    assert_eq!(outcome.moved, ["M0", "M1"]);
    // M6: M0..M5 north, M7..M9 south: the south side moves, with M6's own south frame.
    let before = world.configuration().modules()[6].orientation;
    let outcome = world
        .rotate("M6", 0, 108, true)
        .map_err(|e| e.to_string())?;
    assert_eq!(outcome.moved, ["M6", "M7", "M8", "M9"]);
    assert_ne!(world.configuration().modules()[6].orientation, before);
    // A tie (M2 of the five-module chain: two modules each side): the north side moves.
    let mut world = World::new(load_atron("rotation-chain-5")?);
    let outcome = world
        .rotate("M2", 0, 216, true)
        .map_err(|e| e.to_string())?;
    assert_eq!(outcome.moved, ["M0", "M1"]);
    // M1 holds both neighbours on its north hemisphere: only its south hemisphere turns,
    // which changes its frame and nothing else.
    let outcome = world
        .rotate("M1", 0, 108, true)
        .map_err(|e| e.to_string())?;
    assert_eq!(outcome.moved, ["M1"]);
    Ok(())
}

#[test]
fn a_three_quarter_turn_equals_three_quarter_turns() -> Result<(), String> {
    let start = World::new(load_atron("rotation-chain-5")?);
    let mut once = start.clone();
    once.rotate("M2", 0, 108, false)
        .map_err(|e| e.to_string())?;
    let mut stepwise = start.clone();
    for (from, to) in [(0, 324), (324, 216), (216, 108)] {
        stepwise
            .rotate("M2", from, to, false)
            .map_err(|e| e.to_string())?;
    }
    assert_eq!(once, stepwise);
    assert_eq!(once.configuration().modules()[2].joint_units, 108);
    assert_ne!(once, start);
    Ok(())
}

#[test]
fn queries_for_the_network_simulator() -> Result<(), String> {
    use dynarole_world::Port;
    let eight = load_atron("eight")?;
    let m0 = eight.module_index("M0").ok_or("no M0")?;
    let m2 = eight.module_index_by_id(2).ok_or("no id 2")?;
    let port = Port {
        module: m0,
        connector: 0,
    };
    assert_eq!(
        eight.facing(port),
        Some(Port {
            module: m2,
            connector: 1
        })
    );
    assert!(eight.is_latched(port));
    assert_eq!(
        eight.latched_to(Port {
            module: m2,
            connector: 1
        }),
        Some(port)
    );
    // M0.C2 faces an empty site.
    assert_eq!(
        eight.facing(Port {
            module: m0,
            connector: 2
        }),
        None
    );
    let names: Vec<&str> = eight.modules().iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["M0", "M1", "M2", "M3", "M4", "M5", "M6"]);
    Ok(())
}
