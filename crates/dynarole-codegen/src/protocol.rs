//! The protocol table: every protocol the back-ends generate, with its names, description,
//! runtime files, the sequences it can run and the options that apply to it; the options'
//! own values (paper merge, dissemination, token retries); and the protocol variants that
//! campaigns compare (`lattice-fixed`, `token-32`...). The command line, campaign files,
//! the model checker and the back-ends all name and parse protocols here.

use crate::choice::{self, Choice, UnknownName};
use crate::runtime;
use dynarole_core::driver::Shape;
use std::fmt;
use std::str::FromStr;

/// A protocol that shares the sequence's progress between the modules.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Protocol {
    Lattice,
    Paper,
    /// The token-passing baseline the paper replaced (runtime/token/).
    Token,
}

/// An option of `CompileOptions` that means something for some protocols only.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    /// `merge`: which of the paper's merge functions.
    Merge,
    /// `single_step_handover` and `restart_pending`: the paper protocol's variants.
    PaperVariants,
    /// `epochs`: runs of the whole sequence.
    Epochs,
    /// `no_nv`: surviving resets without non-volatile storage.
    NoNv,
    /// `dissemination`: how the state is broadcast.
    Dissemination,
    /// `token_retries` and `routes`: the token's hand-overs.
    TokenRetries,
    /// `on_failure` and `retries`: what a module does when one of its operations fails.
    OnFailure,
}

impl Setting {
    /// Why a protocol that does not take this setting has no use for it, for the usage error
    /// a flag of it gets ("the paper protocol has its own fixed broadcast period").
    pub fn without_it(self) -> &'static str {
        match self {
            Setting::Merge => "has no merge function to choose",
            Setting::PaperVariants => "has no such variant",
            Setting::Epochs => "runs the sequence once",
            Setting::NoNv => "has no such variant",
            Setting::Dissemination => "has its own fixed broadcast period",
            Setting::TokenRetries => "hands no token over",
            Setting::OnFailure => "re-issues a failed operation until it succeeds",
        }
    }
}

/// What the tools know of one protocol. A new protocol is one entry here (and its runtime in
/// `runtime/`, its tables in a module of this crate called from `c::generate_c`).
#[derive(Debug)]
pub struct ProtocolInfo {
    pub protocol: Protocol,
    /// The name on the command line, in reports and in campaign files.
    pub name: &'static str,
    /// One line for the command line's help.
    pub help: &'static str,
    /// The protocol in words, in reports and model headers ("lattice protocol").
    pub description: &'static str,
    /// What its code can run of a sequence: the paper's runs flat sequences only.
    pub shape: Shape,
    /// The runtime files a compiled directory carries besides `runtime::COMMON`.
    pub runtime: &'static [(&'static str, &'static str)],
    /// The runtime's header the program includes, and its source the Makefile builds.
    pub header: &'static str,
    pub source: &'static str,
    /// The C type of `dr_program`.
    pub program_type: &'static str,
    /// The options of `CompileOptions` that apply to it.
    pub settings: &'static [Setting],
    /// How its code runs the statements of a `&` group: what `parallelise` may write for it.
    pub groups: GroupRun,
    /// Its code needs hand-over routes computed on the start configuration
    /// (`CompileOptions::routes`, `dynarole_replay::token_routes`): a compile needs `--from`.
    pub needs_routes: bool,
    /// Its state packet's payload: the runtime's own constant for its fixed part and what
    /// grows with the sequence (the one source of the wire size both the C and the compiler
    /// use).
    pub payload: Payload,
    /// What the model checker has of it (`promela/NAME.rs`), or `None`: not modelled.
    pub model: Option<Modelled>,
}

/// How a protocol's code runs the statements of one `&` group.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroupRun {
    /// At the same time, a module's own statements too (the lattice runtime starts them as
    /// one batch).
    Overlapping,
    /// At the same time on different modules; a module's own statements one after the other.
    OnePerModule,
    /// One statement at a time in source order: a parallel form gains nothing.
    OneAtATime,
}

/// The payload of a protocol's state packet: a fixed part, named by a `#define` of the
/// protocol's runtime header (read from the header text the compiler embeds), plus a part
/// that grows with the sequence.
#[derive(Clone, Copy, Debug)]
pub struct Payload {
    /// The `#define` in [`ProtocolInfo::header`] that gives the fixed bytes.
    pub fixed: &'static str,
    pub grows: Growth,
}

/// What part of a payload grows with the sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Growth {
    /// One bit per statement of the window (`DR_CONF_WINDOW / 8` bytes).
    WindowBits,
    /// One byte per pending slot (`DR_CONF_MAX_PENDING`).
    PendingSlots,
    /// Nothing: the payload has one size.
    Nothing,
}

/// What the model checker has of a protocol.
#[derive(Clone, Copy, Debug)]
pub struct Modelled {
    /// A compositional model (one module concrete, the others abstract) for robots too large
    /// for the full one; it models NV storage and one run.
    pub compositional: bool,
    /// The deliberately broken variants that show the checker catches each guarantee's loss.
    pub broken_variants: bool,
}

/// Every protocol, in the order the command line lists them (the default first). Entry `i`
/// is the protocol whose discriminant is `i` (checked at compile time below).
pub static PROTOCOLS: [ProtocolInfo; 3] = [
    ProtocolInfo {
        protocol: Protocol::Lattice,
        name: "lattice",
        help: "dynarole's protocol: shared state as a join-semilattice; runs every sequence the language accepts (default)",
        description: "lattice protocol",
        shape: Shape::Nested,
        runtime: &runtime::LATTICE,
        header: "dr_lattice.h",
        source: "dr_lattice.c",
        program_type: "dr_program_t",
        settings: &[
            Setting::Epochs,
            Setting::NoNv,
            Setting::Dissemination,
            Setting::OnFailure,
        ],
        groups: GroupRun::Overlapping,
        needs_routes: false,
        payload: Payload {
            fixed: "DR_LATTICE_PAYLOAD_FIXED",
            grows: Growth::WindowBits,
        },
        model: Some(Modelled {
            compositional: true,
            broken_variants: true,
        }),
    },
    ProtocolInfo {
        protocol: Protocol::Paper,
        name: "paper",
        help: "The paper's protocol, faithfully, for reproduction and comparison (one pending set, no nested blocks)",
        description: "paper protocol",
        shape: Shape::Flat,
        runtime: &runtime::PAPER,
        header: "dr_paper.h",
        source: "dr_paper.c",
        program_type: "dr_paper_program_t",
        settings: &[Setting::Merge, Setting::PaperVariants],
        groups: GroupRun::OnePerModule,
        needs_routes: false,
        payload: Payload {
            fixed: "DR_PAPER_PAYLOAD_FIXED",
            grows: Growth::PendingSlots,
        },
        model: Some(Modelled {
            compositional: false,
            broken_variants: false,
        }),
    },
    ProtocolInfo {
        protocol: Protocol::Token,
        name: "token",
        help: "The token-passing baseline the paper replaced: one token, handed from module to module along chains of latched modules (its routes are computed on the configuration given with --from)",
        description: "token baseline",
        shape: Shape::NestedInTurn,
        runtime: &runtime::TOKEN,
        header: "dr_token.h",
        source: "dr_token.c",
        program_type: "dr_token_program_t",
        settings: &[Setting::TokenRetries],
        groups: GroupRun::OneAtATime,
        needs_routes: true,
        // The largest packet, a safe token's hand-over (acknowledgements are shorter).
        payload: Payload {
            fixed: "DR_TOKEN_SAFE_PAYLOAD",
            grows: Growth::Nothing,
        },
        model: None,
    },
];

const _: () = {
    assert!(Protocol::ALL.len() == PROTOCOLS.len());
    let mut i = 0;
    while i < PROTOCOLS.len() {
        assert!(PROTOCOLS[i].protocol as usize == i && Protocol::ALL[i] as usize == i);
        i += 1;
    }
};

impl Protocol {
    /// Every protocol, in the table's order.
    pub const ALL: [Protocol; 3] = [Protocol::Lattice, Protocol::Paper, Protocol::Token];

    /// The protocol's entry in [`PROTOCOLS`].
    pub fn info(self) -> &'static ProtocolInfo {
        &PROTOCOLS[self as usize]
    }

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// What the protocol's code can run of a sequence: the paper's runs flat ones only.
    pub fn shape(self) -> Shape {
        self.info().shape
    }

    /// Whether `setting` means something for this protocol.
    pub fn takes(self, setting: Setting) -> bool {
        self.info().settings.contains(&setting)
    }

    /// The protocols the model checker models, in words: "the lattice and paper protocols".
    pub fn modelled_in_words() -> String {
        let names: Vec<&str> = Protocol::ALL
            .into_iter()
            .filter(|p| p.info().model.is_some())
            .map(Protocol::name)
            .collect();
        format!("the {} protocols", names.join(" and "))
    }

    /// What the model checker has of this protocol, or the message that says it has nothing
    /// ("the model checker models the lattice and paper protocols, not the token baseline").
    pub fn model(self) -> Result<Modelled, String> {
        self.info().model.ok_or_else(|| {
            format!(
                "the model checker models {}, not the {}",
                Protocol::modelled_in_words(),
                self.info().description
            )
        })
    }

    /// Its code needs hand-over routes computed on the start configuration.
    pub fn needs_routes(self) -> bool {
        self.info().needs_routes
    }

    /// How its code runs a `&` group.
    pub fn groups(self) -> GroupRun {
        self.info().groups
    }

    /// The protocols `setting` applies to, by name ("lattice"), for messages.
    pub fn taking(setting: Setting) -> Vec<&'static str> {
        Protocol::names_where(|info| info.settings.contains(&setting))
    }

    /// The names of the protocols whose entry satisfies `test`, in the table's order, for
    /// messages ("the compositional model is for the lattice protocol").
    pub fn names_where(test: impl Fn(&ProtocolInfo) -> bool) -> Vec<&'static str> {
        PROTOCOLS
            .iter()
            .filter(|info| test(info))
            .map(|info| info.name)
            .collect()
    }

    /// Whether the model checker has a compositional model of it.
    pub fn has_compositional_model(self) -> bool {
        self.info().model.is_some_and(|m| m.compositional)
    }

    /// The protocols with a compositional model, in words for messages ("lattice").
    pub fn with_compositional_model() -> String {
        Protocol::names_where(|p| p.model.is_some_and(|m| m.compositional)).join(" and ")
    }
}

impl Choice for Protocol {
    const WHAT: &'static str = "protocol";
    const ALL: &'static [Protocol] = &Protocol::ALL;
    fn name(self) -> &'static str {
        self.info().name
    }
    fn help(self) -> &'static str {
        self.info().help
    }
}

/// The three versions of the paper's merge (protocol notes, e.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PaperMerge {
    /// Fig. 3 as printed: `p > s_other and p in P_other`.
    Printed,
    /// The Java runtime of the experiments: `p > s_other or p in P_other`.
    Java,
    /// The later C port, which Fig. 4 needs: `p >= s_other or p in P_other`.
    #[default]
    CPort,
}

impl PaperMerge {
    /// The runtime's constant for `dr_module_t.merge` (runtime/paper/dr_paper.h).
    pub fn c_macro(self) -> &'static str {
        match self {
            PaperMerge::Printed => "DR_MERGE_PRINTED",
            PaperMerge::Java => "DR_MERGE_JAVA",
            PaperMerge::CPort => "DR_MERGE_C_PORT",
        }
    }
}

impl Choice for PaperMerge {
    const WHAT: &'static str = "merge";
    const ALL: &'static [PaperMerge] = &[PaperMerge::Printed, PaperMerge::Java, PaperMerge::CPort];
    fn name(self) -> &'static str {
        match self {
            PaperMerge::Printed => "printed",
            PaperMerge::Java => "java",
            PaperMerge::CPort => "c-port",
        }
    }
    fn help(self) -> &'static str {
        match self {
            PaperMerge::Printed => "Fig. 3 as printed (`>` and `and`)",
            PaperMerge::Java => "The Java runtime of the original experiments (`>` and `or`)",
            PaperMerge::CPort => {
                "The later C port, which the text and Fig. 4 need (`>=` and `or`; default)"
            }
        }
    }
}

/// How the lattice protocol disseminates its state (`DR_CONF_LATTICE_DISSEMINATION`,
/// runtime/dr_conf.h). The paper and token protocols have their own fixed period.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Dissemination {
    /// Trickle-like: news at once, then an interval that doubles while nothing is new.
    #[default]
    Adaptive,
    /// A broadcast every period for the whole run (the behaviour before adaptive existed).
    Fixed,
}

impl Dissemination {
    /// Every mode, in the order the command line lists them.
    pub const ALL: [Dissemination; 2] = [Dissemination::Adaptive, Dissemination::Fixed];

    /// The name used on the command line, in campaign files and in reports.
    pub fn name(self) -> &'static str {
        Choice::name(self)
    }

    /// The value of `DR_CONF_LATTICE_DISSEMINATION` in the generated configuration.
    pub fn c_macro(self) -> &'static str {
        match self {
            Dissemination::Adaptive => "DR_DISSEMINATION_ADAPTIVE",
            Dissemination::Fixed => "DR_DISSEMINATION_FIXED",
        }
    }
}

impl Choice for Dissemination {
    const WHAT: &'static str = "dissemination";
    const ALL: &'static [Dissemination] = &Dissemination::ALL;
    fn name(self) -> &'static str {
        match self {
            Dissemination::Adaptive => "adaptive",
            Dissemination::Fixed => "fixed",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Dissemination::Adaptive => {
                "News at once, then an interval that doubles while nothing is new (default)"
            }
            Dissemination::Fixed => "A broadcast every 100 ms for the whole run",
        }
    }
}

/// What a lattice module does when an operation of its fails (`DR_CONF_ON_FAILURE`,
/// runtime/dr_conf.h): the HAL reports it (a connector that did not latch, a joint that
/// stalled). The paper and token protocols re-issue a failed operation until it succeeds.
/// The default is the runtime's ([`default_failure_policy`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OnFailure {
    /// The module stops at the first failure: it starts nothing more and says so.
    Stop,
    /// The failed operation is issued again, at most `retries` times; then the module stops.
    Retry,
}

impl OnFailure {
    /// Every policy, in the order the command line lists them.
    pub const ALL: [OnFailure; 2] = [OnFailure::Stop, OnFailure::Retry];

    /// The value of `DR_CONF_ON_FAILURE` in the generated configuration.
    pub fn c_macro(self) -> &'static str {
        match self {
            OnFailure::Stop => "DR_ON_FAILURE_STOP",
            OnFailure::Retry => "DR_ON_FAILURE_RETRY",
        }
    }
}

impl Choice for OnFailure {
    const WHAT: &'static str = "failure policy";
    const ALL: &'static [OnFailure] = &OnFailure::ALL;
    fn name(self) -> &'static str {
        match self {
            OnFailure::Stop => "stop",
            OnFailure::Retry => "retry",
        }
    }
    fn help(self) -> &'static str {
        match self {
            OnFailure::Stop => "Stop where the robot is at the first failed operation",
            OnFailure::Retry => {
                "Issue a failed operation again, --retries times, then stop (default)"
            }
        }
    }
}

/// The most `--retries` may be (`DR_CONF_RETRIES` stays below the runtime's gave-up mark).
pub const MAX_RETRIES: u8 = 100;

/// How the token baseline's hand-over messages are made reliable (the original experiments'
/// variants).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TokenRetries {
    /// Each hop sends once, unacknowledged.
    Plain,
    /// Acknowledged hop by hop, tried at most this many times (at least 1).
    Tries(u16),
    /// Acknowledged hop by hop, tried until acknowledged.
    Unlimited,
}

impl TokenRetries {
    /// The name used on the command line, in reports and campaign files: `plain`, `32`,
    /// `unlimited`.
    pub fn name(self) -> String {
        match self {
            TokenRetries::Plain => "plain".into(),
            TokenRetries::Tries(n) => n.to_string(),
            TokenRetries::Unlimited => "unlimited".into(),
        }
    }
}

/// `plain`, `unlimited` or a number of tries per hop from 1.
impl FromStr for TokenRetries {
    type Err = String;
    fn from_str(text: &str) -> Result<TokenRetries, String> {
        match text {
            "plain" => Ok(TokenRetries::Plain),
            "unlimited" => Ok(TokenRetries::Unlimited),
            n => match n.parse::<u16>() {
                Ok(tries) if tries >= 1 => Ok(TokenRetries::Tries(tries)),
                _ => Err(format!(
                    "expected `plain`, `unlimited` or a number of tries from 1 to 65535, found `{n}`"
                )),
            },
        }
    }
}

/// A protocol with the option that sets its variants apart, as campaigns compare them: the
/// lattice protocol with each dissemination, the token baseline with each of the original
/// experiments' retries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Variant {
    Lattice,
    LatticeFixed,
    Paper,
    TokenPlain,
    Token32,
    Token128,
    TokenUnlimited,
}

/// One variant: the variant, its name, and the options it sets (protocol, dissemination,
/// token retries). Options a variant does not set keep `CompileOptions::default()`'s values.
type VariantEntry = (Variant, &'static str, Protocol, Dissemination, TokenRetries);

/// The variants, in `Variant`'s order (checked at compile time below).
#[rustfmt::skip]
static VARIANTS: [VariantEntry; 7] = {
    use Dissemination::{Adaptive, Fixed};
    use Protocol::{Lattice, Paper, Token};
    use TokenRetries::{Plain, Tries, Unlimited};
    [
        (Variant::Lattice,        "lattice",         Lattice, Adaptive, Tries(32)),
        (Variant::LatticeFixed,   "lattice-fixed",   Lattice, Fixed,    Tries(32)),
        (Variant::Paper,          "paper",           Paper,   Adaptive, Tries(32)),
        (Variant::TokenPlain,     "token-plain",     Token,   Adaptive, Plain),
        (Variant::Token32,        "token-32",        Token,   Adaptive, Tries(32)),
        (Variant::Token128,       "token-128",       Token,   Adaptive, Tries(128)),
        (Variant::TokenUnlimited, "token-unlimited", Token,   Adaptive, Unlimited),
    ]
};

const _: () = {
    let all = <Variant as Choice>::ALL;
    assert!(all.len() == VARIANTS.len());
    let mut i = 0;
    while i < VARIANTS.len() {
        assert!(VARIANTS[i].0 as usize == i && all[i] as usize == i);
        i += 1;
    }
};

impl Variant {
    fn entry(self) -> &'static VariantEntry {
        &VARIANTS[self as usize]
    }

    pub fn protocol(self) -> Protocol {
        self.entry().2
    }

    pub fn dissemination(self) -> Dissemination {
        self.entry().3
    }

    pub fn token_retries(self) -> TokenRetries {
        self.entry().4
    }

    /// The name used in campaign files and their results.
    pub fn name(self) -> &'static str {
        self.entry().1
    }
}

impl Choice for Variant {
    const WHAT: &'static str = "protocol";
    const ALL: &'static [Variant] = &[
        Variant::Lattice,
        Variant::LatticeFixed,
        Variant::Paper,
        Variant::TokenPlain,
        Variant::Token32,
        Variant::Token128,
        Variant::TokenUnlimited,
    ];
    fn name(self) -> &'static str {
        self.entry().1
    }
}

/// `FromStr` and `Display` through the table, for each set of names.
macro_rules! by_name {
    ($($t:ty),*) => {$(
        impl FromStr for $t {
            type Err = UnknownName;
            fn from_str(text: &str) -> Result<$t, UnknownName> {
                choice::parse(text)
            }
        }
        impl fmt::Display for $t {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(Choice::name(*self))
            }
        }
    )*};
}

by_name!(Protocol, PaperMerge, Dissemination, Variant);

/// The runtime's default failure policy and retries (`DR_CONF_ON_FAILURE` and
/// `DR_CONF_RETRIES` of runtime/dr_conf.h, the one place they are decided): what a program
/// compiled without `--on-failure` and `--retries` does, and so the flags' defaults. The file
/// is embedded at build time and the tests compile with it: this cannot fail at run time.
pub fn default_failure_policy() -> (OnFailure, u8) {
    let policy = runtime::conf_text("DR_CONF_ON_FAILURE")
        .and_then(|text| OnFailure::ALL.into_iter().find(|p| p.c_macro() == text))
        .expect("runtime/dr_conf.h defines DR_CONF_ON_FAILURE as a policy");
    let retries = runtime::conf_text("DR_CONF_RETRIES")
        .and_then(|text| text.parse::<u8>().ok())
        .expect("runtime/dr_conf.h defines DR_CONF_RETRIES as a byte");
    (policy, retries)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every name parses back to its value, for every set.
    fn round_trip<T: Choice + fmt::Debug + FromStr<Err = UnknownName> + fmt::Display>() {
        let names = choice::names::<T>();
        assert_eq!(names.len(), T::ALL.len());
        for &value in T::ALL {
            assert_eq!(value.name().parse::<T>(), Ok(value), "{value:?}");
            assert_eq!(value.to_string(), value.name());
            assert_eq!(names.iter().filter(|n| **n == value.name()).count(), 1);
        }
    }

    #[test]
    fn every_name_round_trips() {
        round_trip::<Protocol>();
        round_trip::<PaperMerge>();
        round_trip::<Dissemination>();
        round_trip::<Variant>();
        for protocol in Protocol::ALL {
            assert_eq!(protocol.info().protocol, protocol);
        }
    }

    #[test]
    fn an_unknown_name_lists_the_names_and_the_closest() {
        let error = "lattise".parse::<Protocol>().expect_err("unknown");
        assert_eq!(
            error.to_string(),
            "unknown protocol `lattise`, expected one of `lattice`, `paper`, `token`"
        );
        assert_eq!(error.hint().as_deref(), Some("did you mean `lattice`?"));
        let error = "trickle".parse::<Dissemination>().expect_err("unknown");
        assert_eq!(
            error.to_string(),
            "unknown dissemination `trickle`, expected `adaptive` or `fixed`"
        );
        assert_eq!(error.hint(), None);
        assert!("token-7".parse::<Variant>().is_err());
        assert!("Lattice".parse::<Protocol>().is_err());
    }

    /// Campaign variants name the back-end's own modes: `lattice-fixed` is the lattice protocol
    /// with the dissemination named `fixed`, `token-N` the token with N tries.
    #[test]
    fn variants_are_named_after_their_options() {
        for &v in <Variant as Choice>::ALL {
            let expected = match (v.protocol(), v.dissemination()) {
                (Protocol::Lattice, Dissemination::Adaptive) => "lattice".to_string(),
                (Protocol::Lattice, d) => format!("lattice-{}", d.name()),
                (Protocol::Paper, _) => "paper".to_string(),
                (Protocol::Token, _) => format!("token-{}", v.token_retries().name()),
            };
            assert_eq!(v.name(), expected);
        }
    }

    #[test]
    fn token_retries_parse() {
        assert_eq!("plain".parse(), Ok(TokenRetries::Plain));
        assert_eq!("unlimited".parse(), Ok(TokenRetries::Unlimited));
        assert_eq!("128".parse(), Ok(TokenRetries::Tries(128)));
        for bad in ["0", "-1", "70000", "many"] {
            assert!(bad.parse::<TokenRetries>().is_err(), "{bad}");
        }
        for r in [
            TokenRetries::Plain,
            TokenRetries::Tries(7),
            TokenRetries::Unlimited,
        ] {
            assert_eq!(r.name().parse(), Ok(r));
        }
    }

    #[test]
    fn settings_name_their_protocols() {
        assert_eq!(Protocol::taking(Setting::Dissemination), ["lattice"]);
        assert_eq!(Protocol::taking(Setting::Merge), ["paper"]);
        assert!(Protocol::Token.takes(Setting::TokenRetries));
        assert_eq!(
            Protocol::modelled_in_words(),
            "the lattice and paper protocols"
        );
    }
}
