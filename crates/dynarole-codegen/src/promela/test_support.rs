//! What the Promela back-end's tests share, compiled for tests only: its unit tests and
//! `tests/promela.rs` (which includes this file by path). An example's IR, three modules in a
//! line and the model options of one protocol. The back-end's names come from the module
//! above, the `promela` module or the test crate, which both have them in scope.

use super::{CompileOptions, Ir, ModelOptions, Protocol, Topology, TopologyLink, TopologyModule};
use dynarole_core::{analyze, parse};

/// The IR of `sequence` in `source`, an example that checks and fits.
pub fn lowered(source: &str, sequence: &str) -> Ir {
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let plan = program.expand(sequence).expect("the sequence exists");
    program.lower(&[plan]).expect("it fits")
}

/// M0 - M1 - M2 in a line; each link both ways, fair in the stages given.
pub fn line(stages: &[usize]) -> Topology {
    let modules = (0..3u8)
        .map(|k| TopologyModule {
            name: format!("M{k}"),
            address: Some(k),
        })
        .collect();
    let links = [(0, 1), (1, 0), (1, 2), (2, 1)]
        .into_iter()
        .map(|(from, to)| TopologyLink {
            from,
            to,
            fair_stages: stages.to_vec(),
        })
        .collect();
    Topology { modules, links }
}

/// The options of a model named `name` of `protocol`: one reset, `late` late slots, no
/// fault.
pub fn options(name: &str, protocol: Protocol, late: u8) -> ModelOptions {
    ModelOptions {
        compile: CompileOptions {
            protocol,
            name: name.into(),
            ..CompileOptions::default()
        },
        resets: 1,
        reset_modules: Vec::new(),
        late,
        fault: None,
    }
}
