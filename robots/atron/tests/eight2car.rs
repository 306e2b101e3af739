//! Replays the paper's Fig. 5 (eight2car) on the eight and checks that it yields the car, and
//! that the automatically reversed sequence brings the car back to the eight.

mod common;

use common::{load, load_atron, reverse, Statement};
use dynarole_robot_atron::{World, KIND, MIN_SWEEP_DISTANCE_LATTICE};
use dynarole_world::{compare, Configuration, RobotKind};
use Statement::{Extend, Retract, Rotate};

/// Fig. 5, corrected for OCR (MO = M0, `$CONNECTOR 4` = `$CONNECTOR_4`), as parallel groups.
fn eight2car() -> Vec<Vec<Statement>> {
    vec![
        vec![Retract("M0", 0), Retract("M3", 4)],
        vec![Rotate("M3", 0, 324, false)],
        vec![Rotate("M4", 0, 108, true)],
        vec![
            Extend("M4", 0),
            Rotate("M1", 0, 324, false),
            Retract("M6", 2),
        ],
        vec![Rotate("M4", 108, 216, true), Rotate("M6", 0, 108, true)],
        vec![Extend("M0", 0)],
        vec![Retract("M6", 6)],
        vec![Rotate("M0", 0, 324, false), Rotate("M1", 324, 0, true)],
        vec![Rotate("M0", 324, 0, true)],
        vec![Extend("M5", 0), Extend("M2", 4), Extend("M1", 4)],
        vec![Retract("M4", 0)],
        vec![Retract("M3", 6)],
        vec![Rotate("M1", 0, 108, true), Rotate("M3", 324, 0, true)],
        vec![Extend("M1", 6)],
        vec![Retract("M3", 0), Retract("M3", 2)],
        vec![Rotate("M1", 108, 216, true)],
    ]
}

/// Runs the groups, requiring every statement to succeed without any warning (every extend
/// meets a facing female, every retract releases a latch, no split), re-validating the
/// configuration after each statement. Returns the world and the closest sweep approach.
fn replay(start: World, groups: &[Vec<Statement>]) -> Result<(World, f64), String> {
    let mut world = start;
    let mut closest = f64::INFINITY;
    for (g, group) in groups.iter().enumerate() {
        for statement in group {
            let outcome = statement
                .run(&mut world)
                .map_err(|e| format!("group {g}: {statement:?}: {e}"))?;
            if !outcome.warnings.is_empty() {
                return Err(format!("group {g}: {statement:?}: {:?}", outcome.warnings));
            }
            if let Some(d) = outcome.closest_approach {
                closest = closest.min(d);
            }
            let text = Configuration::new(world.configuration().clone()).to_json_string();
            KIND.read_configuration(&text)
                .map_err(|e| format!("group {g}: {statement:?} left an invalid world: {e}"))?;
        }
    }
    Ok((world, closest))
}

#[test]
fn the_closest_approaches_are_where_atron_md_says() -> Result<(), String> {
    // M6 passing M5 during M0's 324->0 turn, and M3 passing M5 during M1's final turn.
    let mut world = World::new(load_atron("eight")?);
    let mut tight = Vec::new();
    for group in eight2car() {
        for statement in group {
            let outcome = statement.run(&mut world).map_err(|e| e.to_string())?;
            if outcome.closest_approach.is_some_and(|d| d < 1.3) {
                tight.push(statement);
            }
        }
    }
    assert_eq!(
        tight,
        [Rotate("M0", 324, 0, true), Rotate("M1", 108, 216, true)]
    );
    Ok(())
}

#[test]
fn fig5_has_25_statements() {
    assert_eq!(eight2car().iter().map(Vec::len).sum::<usize>(), 25);
}

#[test]
fn eight2car_yields_the_car_and_its_reverse_the_eight() -> Result<(), String> {
    let eight = load_atron("eight")?;
    let car = load("car")?;
    let (world, closest) = replay(World::new(eight.clone()), &eight2car())?;
    let reached = Configuration::new(world.configuration().clone());
    compare(&reached, &car).map_err(|d| d.to_string())?;
    // The data file was made with the same "larger side stays" rule: identical poses.
    let car_atron = load_atron("car")?;
    assert_eq!(world.configuration().modules(), car_atron.modules());
    assert_eq!(world.configuration().latches(), car_atron.latches());
    assert!(closest >= MIN_SWEEP_DISTANCE_LATTICE);
    assert!((closest - 1.236).abs() < 1e-3, "closest approach {closest}");

    let (back, _) = replay(world, &reverse(&eight2car()))?;
    // Exactly the eight, not only up to rigid motion: M2 and M5 never move.
    assert_eq!(back.configuration().modules(), eight.modules());
    assert_eq!(back.configuration().latches(), eight.latches());
    let back = Configuration::new(back.configuration().clone());
    compare(&back, &Configuration::new(eight)).map_err(|d| d.to_string())?;
    Ok(())
}
