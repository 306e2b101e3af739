//! Equality up to rigid motion: any of the 24 lattice rotations plus a lattice-preserving
//! translation gives an equal configuration; a single perturbation is found and named.

mod common;

use common::{load, load_atron};
use dynarole_robot_atron::AtronConfiguration;
use dynarole_world::{compare, compare_with_expected, Configuration, Rotation, Vec3};
use proptest::prelude::*;

const SHAPES: [&str; 3] = ["eight", "car", "snake"];

/// `config` rotated and shifted by `2 * k + parity`, using the `choice`-th parity class that
/// keeps it on the ATRON lattice (only some translations preserve the lattice phase).
fn moved(
    config: &Configuration,
    rotation: usize,
    k: Vec3,
    choice: usize,
) -> Result<Configuration, String> {
    let all = Rotation::all();
    let rotation = *all.get(rotation % 24).ok_or("no rotation")?;
    let valid: Vec<Configuration> = (0..8)
        .filter_map(|bits: i32| {
            let t = [
                2 * k[0] + (bits & 1),
                2 * k[1] + ((bits >> 1) & 1),
                2 * k[2] + ((bits >> 2) & 1),
            ];
            config.transformed(rotation, t).ok()
        })
        .collect();
    if valid.is_empty() {
        return Err("no lattice-preserving translation".to_string());
    }
    Ok(valid[choice % valid.len()].clone())
}

/// Rebuilds an ATRON configuration after editing its modules and connections.
fn rebuild(
    config: &AtronConfiguration,
    edit: impl FnOnce(
        &mut Vec<dynarole_robot_atron::AtronModule>,
        &mut Vec<dynarole_world::NamedConnection>,
    ),
) -> Result<Configuration, String> {
    let mut modules = config.modules().to_vec();
    let mut connections = config.named_connections();
    edit(&mut modules, &mut connections);
    AtronConfiguration::new(config.metadata().clone(), modules, &connections)
        .map(Configuration::new)
        .map_err(|e| e.to_string())
}

proptest! {
    #[test]
    fn rigid_motions_give_equal_configurations(
        shape in 0usize..3, rotation in 0usize..24,
        k in prop::array::uniform3(-6i32..6), choice in 0usize..3,
    ) {
        let original = load(SHAPES[shape]).map_err(TestCaseError::fail)?;
        let other = moved(&original, rotation, k, choice).map_err(TestCaseError::fail)?;
        prop_assert!(compare(&original, &other).is_ok(), "{:?}", compare(&original, &other));
        prop_assert!(compare(&other, &original).is_ok());
    }

    #[test]
    fn a_moved_module_is_found(
        shape in 0usize..3, module in 0usize..7, rotation in 0usize..24,
        k in prop::array::uniform3(-3i32..3),
    ) {
        let original = load_atron(SHAPES[shape]).map_err(TestCaseError::fail)?;
        let name = original.modules()[module].name.clone();
        // Move it far away by an even vector (keeps the lattice phase) and drop its latches.
        let perturbed = rebuild(&original, |modules, connections| {
            let p = modules[module].position;
            modules[module].position = [p[0] + 20, p[1], p[2] + 2];
            connections.retain(|(a, _, b, _)| *a != name && *b != name);
        }).map_err(TestCaseError::fail)?;
        let perturbed = moved(&perturbed, rotation, k, 0).map_err(TestCaseError::fail)?;
        let diff = compare(&Configuration::new(original.clone()), &perturbed);
        let diff = diff.err().ok_or_else(|| TestCaseError::fail("no difference"))?;
        prop_assert_eq!(diff.misplaced.len(), 1, "{}", diff);
        prop_assert_eq!(&diff.misplaced[0].module, &name);
        prop_assert_eq!(diff.matched, original.modules().len() - 1);
        let expected = format!("module {name} misplaced");
        prop_assert!(diff.to_string().contains(&expected));
    }

    #[test]
    fn a_changed_joint_is_found(
        shape in 0usize..3, module in 0usize..7, rotation in 0usize..24,
        k in prop::array::uniform3(-3i32..3),
    ) {
        let original = load_atron(SHAPES[shape]).map_err(TestCaseError::fail)?;
        let name = original.modules()[module].name.clone();
        // Turning the joint moves the north connectors: their latches have to go.
        let perturbed = rebuild(&original, |modules, connections| {
            modules[module].joint_units = (modules[module].joint_units + 108) % 432;
            connections.retain(|(a, ca, b, cb)| !((*a == name && *ca < 4) || (*b == name && *cb < 4)));
        }).map_err(TestCaseError::fail)?;
        let perturbed = moved(&perturbed, rotation, k, 1).map_err(TestCaseError::fail)?;
        let diff = compare(&Configuration::new(original), &perturbed);
        let diff = diff.err().ok_or_else(|| TestCaseError::fail("no difference"))?;
        prop_assert!(diff.misplaced.is_empty(), "{}", diff);
        prop_assert_eq!(diff.joints.len(), 1);
        prop_assert_eq!(&diff.joints[0].module, &name);
        let expected = format!("joint of {name}");
        prop_assert!(diff.to_string().contains(&expected));
    }

    #[test]
    fn a_dropped_connection_is_found(
        shape in 0usize..3, which in 0usize..8, rotation in 0usize..24,
        k in prop::array::uniform3(-3i32..3),
    ) {
        let original = load_atron(SHAPES[shape]).map_err(TestCaseError::fail)?;
        let connections = original.named_connections();
        let dropped = connections[which % connections.len()].clone();
        let perturbed = rebuild(&original, |_, connections| connections.retain(|c| *c != dropped))
            .map_err(TestCaseError::fail)?;
        let perturbed = moved(&perturbed, rotation, k, 2).map_err(TestCaseError::fail)?;
        let diff = compare(&Configuration::new(original), &perturbed);
        let diff = diff.err().ok_or_else(|| TestCaseError::fail("no difference"))?;
        let (a, ca, b, cb) = dropped;
        prop_assert_eq!(diff.missing_connections.clone(), vec![format!("{a}.C{ca}-{b}.C{cb}")]);
        prop_assert!(diff.misplaced.is_empty() && diff.joints.is_empty() && diff.extra_connections.is_empty());
    }
}

#[test]
fn different_module_names_are_listed() -> Result<(), String> {
    let diff = compare(&load("car")?, &load("car-xml")?)
        .err()
        .ok_or("equal?")?;
    assert_eq!(diff.only_in_first.len(), 7);
    assert_eq!(diff.only_in_second.len(), 7);
    let text = diff.to_string();
    assert!(
        text.contains("module M0 in the first configuration only"),
        "{text}"
    );
    Ok(())
}

#[test]
fn eight_and_car_differ_readably() -> Result<(), String> {
    let diff = compare(&load("eight")?, &load("car")?)
        .err()
        .ok_or("equal?")?;
    let text = diff.to_string();
    // M2 and M5 never move in eight2car, so the identity motion matches them.
    assert_eq!(diff.matched, 2);
    let misplaced: Vec<&str> = diff.misplaced.iter().map(|m| m.module.as_str()).collect();
    assert_eq!(misplaced, ["M0", "M1", "M3", "M4", "M6"]);
    assert!(text.contains("module M6 misplaced: first [4, 0, 0] NS_BROKEN, second [2, 1, -1] UD"));
    assert!(
        text.contains("joint of M1: first [0], second [216]"),
        "{text}"
    );
    assert!(
        text.contains("connection M0.C0-M2.C1 in the first configuration only"),
        "{text}"
    );
    Ok(())
}

#[test]
fn a_reached_configuration_is_named_as_reached_and_the_expected_one_as_expected(
) -> Result<(), String> {
    // `replay --expect` once printed the reached pose as "expected" and the expected as
    // "found".
    let (expected, reached) = (load("eight")?, load("car")?);
    let text = compare_with_expected(&reached, &expected)
        .err()
        .ok_or("equal?")?
        .to_string();
    assert!(
        text.contains("module M6 misplaced: expected [4, 0, 0] NS_BROKEN, reached [2, 1, -1] UD"),
        "{text}"
    );
    assert!(
        text.contains("joint of M1: expected [0], reached [216]"),
        "{text}"
    );
    assert!(
        text.contains("connection M0.C0-M2.C1 in the expected configuration only"),
        "{text}"
    );
    assert!(
        text.contains("the expected configuration has 2 module(s) in place"),
        "{text}"
    );
    Ok(())
}

#[test]
fn different_robots_differ() -> Result<(), String> {
    let diff = compare(&load("eight")?, &load("mtran-snake4")?)
        .err()
        .ok_or("equal?")?;
    assert_eq!(
        diff.to_string(),
        "different robots: ATRON (first) and MTRAN (second)"
    );
    Ok(())
}

#[test]
fn mtran_snakes_compare_up_to_rigid_motion() -> Result<(), String> {
    let snake = load("mtran-snake4")?;
    for rotation in Rotation::all() {
        let other = snake
            .transformed(rotation, [3, -1, 7])
            .map_err(|e| e.to_string())?;
        compare(&snake, &other).map_err(|d| d.to_string())?;
    }
    Ok(())
}
