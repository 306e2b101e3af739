//! What a compilation is asked for (`CompileOptions`), shared by every back-end, and the
//! helpers the back-ends' modules share; it sits below them so that none imports another's.

use crate::protocol::{Dissemination, PaperMerge, Protocol, TokenRetries};
use dynarole_core::lower::TokenRoutes;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CompileOptions {
    pub protocol: Protocol,
    pub merge: PaperMerge,
    /// Paper protocol: add pending and transfer in one step.
    pub single_step_handover: bool,
    /// Paper protocol: the Sec. III-C restart of an interrupted pending operation.
    pub restart_pending: bool,
    /// Lattice protocol: runs of the whole sequence before the end; 0 runs forever.
    pub epochs: u16,
    /// Lattice protocol: the hardware has no non-volatile storage; survive resets through the
    /// neighbours instead (a weaker guarantee, see runtime/lattice/README.md).
    pub no_nv: bool,
    /// Lattice protocol: how the state is disseminated (ignored by the other protocols).
    pub dissemination: Dissemination,
    /// Token baseline: how hand-overs are made reliable.
    pub token_retries: TokenRetries,
    /// Token baseline: where each statement runs and its hand-over routes (required by it).
    pub routes: Option<TokenRoutes>,
    /// Name of the compiled sequence(s), for comments.
    pub name: String,
    /// The robot (or swarm) identity every packet carries (`DR_ROBOT_ID`, which a build can
    /// still override at flash time).
    pub robot_id: u16,
    /// The shared key of keyed builds: every packet then carries an authentication tag.
    pub key: Option<[u8; 16]>,
    /// The execution, chosen anew for every launch (`DR_EXECUTION`, which a build can still
    /// override at flash time): packets and NV records of another launch are refused.
    pub execution: u32,
}

impl Default for CompileOptions {
    /// The lattice protocol, one run, NV storage, adaptive dissemination; the paper's C-port merge; the safe token
    /// with 32 tries.
    fn default() -> CompileOptions {
        CompileOptions {
            protocol: Protocol::Lattice,
            merge: PaperMerge::CPort,
            single_step_handover: false,
            restart_pending: false,
            epochs: 1,
            no_nv: false,
            dissemination: Dissemination::Adaptive,
            token_retries: TokenRetries::Tries(32),
            routes: None,
            name: String::new(),
            robot_id: 0,
            key: None,
            execution: 0,
        }
    }
}

impl CompileOptions {
    /// The protocol and the options that change what it does, in words ("paper protocol,
    /// java merge, pending restart"): the one description reports and model headers use.
    pub fn describe(&self) -> String {
        let mut out = self.protocol.info().description.to_string();
        match self.protocol {
            Protocol::Lattice if self.no_nv => out.push_str(" without NV"),
            Protocol::Paper => {
                out.push_str(&format!(", {} merge", self.merge));
                if self.single_step_handover {
                    out.push_str(", single-step handover");
                }
                if self.restart_pending {
                    out.push_str(", pending restart");
                }
            }
            Protocol::Lattice | Protocol::Token => {}
        }
        out
    }
}

/// The C name of an operation's code (`DR_OP_CONNECTOR_EXTEND`), in the program's header and
/// every table that starts the operation.
pub(crate) fn op_macro(part: &str, op: &str) -> String {
    format!("DR_OP_{}_{}", part.to_uppercase(), op.to_uppercase())
}
