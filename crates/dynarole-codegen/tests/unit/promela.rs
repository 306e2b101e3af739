//! Unit tests of `src/promela.rs`, kept beside the integration tests
//! because they read the robots' example files.

use super::*;
use test_support::{line, lowered};

/// protocol.md's `A; B & C; D;` (a sequential and a parallel unit for the paper switch).
fn ir() -> Ir {
    lowered(
        include_str!("../../../../robots/atron/examples/verify/a_bc_d.dr"),
        "a_bc_d",
    )
}

/// Every part of every template file is written by some model (none is dead text).
#[test]
fn every_template_part_is_used() {
    let (ir, topology) = (ir(), line(&[0, 1, 2, 3, 4]));
    let graph = liveness_graph(&ir, &topology);
    let options = |protocol, late| test_support::options("a_bc_d", protocol, late);
    template::RENDERED.with(|r| r.borrow_mut().clear());
    let full = generate_promela(&ir, &topology, &options(Protocol::Lattice, 1));
    let paper = generate_promela(&ir, &topology, &options(Protocol::Paper, 1));
    let comp = options(Protocol::Lattice, 0);
    let compositional = generate_compositional(&ir, &topology, &comp, 0, &graph);
    assert!(full.is_ok() && paper.is_ok() && compositional.is_ok());
    let rendered = template::RENDERED.with(|r| r.borrow().clone());
    for file in [
        &HAL,
        &lattice::LATTICE,
        &paper::PAPER,
        &compositional::COMPOSITIONAL,
    ] {
        for (part, _, _) in file.parts() {
            assert!(
                rendered.contains(&(file.path, part)),
                "{} part {part} is never written",
                file.path
            );
        }
    }
}
