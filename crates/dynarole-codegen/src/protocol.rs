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
    /// The model checker has its transcription (`promela/NAME.rs`).
    pub modelled: bool,
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
        settings: &[Setting::Epochs, Setting::NoNv, Setting::Dissemination],
        modelled: true,
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
        modelled: true,
    },
    ProtocolInfo {
        protocol: Protocol::Token,
        name: "token",
        help: "The token-passing baseline the paper replaced: one token, handed from module to module along chains of latched modules (its routes are computed on the configuration given with --from)",
        description: "token baseline",
        shape: Shape::Nested,
        runtime: &runtime::TOKEN,
        header: "dr_token.h",
        source: "dr_token.c",
        program_type: "dr_token_program_t",
        settings: &[Setting::TokenRetries],
        modelled: false,
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
            .filter(|p| p.info().modelled)
            .map(Protocol::name)
            .collect();
        format!("the {} protocols", names.join(" and "))
    }

    /// The protocols `setting` applies to, by name ("lattice"), for messages.
    pub fn taking(setting: Setting) -> Vec<&'static str> {
        Protocol::ALL
            .into_iter()
            .filter(|p| p.takes(setting))
            .map(Protocol::name)
            .collect()
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
