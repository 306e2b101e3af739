//! What the generated code of a program's sequences cannot encode for a protocol
//! (`dynarole check --protocol`): the lowering's limits for the protocol's shape and, for the
//! paper's protocol, its state layout; each at the statement that exceeds it.

use crate::Protocol;
use dynarole_core::{driver, Diagnostic, Program};

/// One diagnostic per declared sequence that `protocol`'s code could not run.
pub fn target_limits(program: &Program, protocol: Protocol) -> Vec<Diagnostic> {
    let shape = protocol.shape();
    let mut out = Vec::new();
    for decl in program.file.sequences() {
        let plan = program.expand(&decl.name.name).unwrap_or_default();
        let fits =
            driver::lower(program, std::slice::from_ref(&plan), shape).and_then(
                |ir| match protocol {
                    Protocol::Paper => ir.paper_layout().map(|_| ()).map_err(Diagnostic::from),
                    Protocol::Lattice | Protocol::Token => Ok(()),
                },
            );
        out.extend(fits.err());
    }
    out
}
