//! What a compilation is asked for (`CompileOptions`), shared by every back-end, and the
//! helpers the back-ends' modules share; it sits below them so that none imports another's.

use crate::protocol::default_failure_policy;
use crate::protocol::{Dissemination, OnFailure, PaperMerge, Protocol, Setting, TokenRetries};
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
    /// Lattice protocol: what a module does when one of its operations fails.
    pub on_failure: OnFailure,
    /// Lattice protocol, `on_failure` retry: times a failed operation is issued again.
    pub retries: u8,
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
        let (on_failure, retries) = default_failure_policy();
        CompileOptions {
            protocol: Protocol::Lattice,
            merge: PaperMerge::CPort,
            single_step_handover: false,
            restart_pending: false,
            epochs: 1,
            no_nv: false,
            dissemination: Dissemination::Adaptive,
            token_retries: TokenRetries::Tries(32),
            on_failure,
            retries,
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
        for setting in self.protocol.info().settings {
            out.push_str(&self.describe_setting(*setting));
        }
        out
    }

    /// What `setting` adds to [`CompileOptions::describe`] when it is not the default (the
    /// match names every setting, so a new one says here what it shows).
    fn describe_setting(&self, setting: Setting) -> String {
        match setting {
            Setting::NoNv if self.no_nv => " without NV".into(),
            Setting::Merge => format!(", {} merge", self.merge),
            Setting::PaperVariants => {
                let mut out = String::new();
                if self.single_step_handover {
                    out.push_str(", single-step handover");
                }
                if self.restart_pending {
                    out.push_str(", pending restart");
                }
                out
            }
            Setting::OnFailure => match self.on_failure {
                OnFailure::Stop => ", stop on failure".into(),
                OnFailure::Retry if self.retries == default_failure_policy().1 => String::new(),
                OnFailure::Retry => format!(", {} retries", self.retries),
            },
            Setting::NoNv | Setting::Epochs | Setting::Dissemination | Setting::TokenRetries => {
                String::new()
            }
        }
    }

    /// The runs of the sequence its code makes: `epochs` (0: forever) where the protocol
    /// takes it, else one.
    pub fn runs(&self) -> u16 {
        if self.protocol.takes(Setting::Epochs) {
            self.epochs
        } else {
            1
        }
    }

    /// The modules survive resets without NV storage: `no_nv` where the protocol takes it.
    pub fn without_nv(&self) -> bool {
        self.no_nv && self.protocol.takes(Setting::NoNv)
    }

    /// How the state is broadcast, where the protocol lets one choose.
    pub fn chosen_dissemination(&self) -> Option<Dissemination> {
        self.protocol
            .takes(Setting::Dissemination)
            .then_some(self.dissemination)
    }
}

/// The C name of an operation's code (`DR_OP_CONNECTOR_EXTEND`), in the program's header and
/// every table that starts the operation.
pub(crate) fn op_macro(part: &str, op: &str) -> String {
    format!("DR_OP_{}_{}", part.to_uppercase(), op.to_uppercase())
}
