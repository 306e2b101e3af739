//! Unit tests of `src/promela/lattice.rs`, kept beside the integration tests
//! because they read the robots' example files.

use super::super::test_support::{line, lowered, options};
use super::LATTICE_BATCH;
use crate::{generate_c, generate_promela, Protocol};

/// The value of `#define name value` in `text`, if it has that line.
fn defined<'t>(text: &'t str, name: &str) -> Option<&'t str> {
    text.lines().find_map(|line| {
        let mut words = line.strip_prefix("#define ")?.split_whitespace();
        (words.next() == Some(name)).then(|| words.next()).flatten()
    })
}

/// The model runs the batches the image is built with: the generated configuration and
/// the model carry the one value (the paper protocol's image has no batch).
#[test]
fn the_model_and_the_image_share_the_batch() {
    let ir = lowered(
        include_str!("../../../../robots/atron/examples/verify/ab_c.dr"),
        "ab_c",
    );
    let registry = dynarole_robots::plugins();
    let robot = registry.get(&ir.robot).expect("a built-in robot");
    let conf = |protocol| {
        let generated = generate_c(&ir, robot, &options("ab_c", protocol, 0).compile);
        let files = generated.expect("generates").files;
        let conf = files
            .into_iter()
            .find(|(name, _)| name == "dr_program_conf.h");
        conf.expect("a configuration header").1
    };
    let batch = LATTICE_BATCH.to_string();
    let lattice = conf(Protocol::Lattice);
    assert_eq!(
        defined(&lattice, "DR_CONF_LATTICE_BATCH"),
        Some(batch.as_str())
    );
    assert_eq!(
        defined(&conf(Protocol::Paper), "DR_CONF_LATTICE_BATCH"),
        None
    );
    let model = generate_promela(
        &ir,
        &line(&[0, 1, 2, 3]),
        &options("ab_c", Protocol::Lattice, 0),
    );
    let model = model.expect("models").text;
    assert_eq!(defined(&model, "BATCH"), Some(batch.as_str()));
}
