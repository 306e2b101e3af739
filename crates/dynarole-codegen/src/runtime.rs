//! The runtime sources, embedded so that a compiled directory is self-contained.

/// Files every protocol needs.
pub const COMMON: [(&str, &str); 8] = [
    ("dr_conf.h", include_str!("../../../runtime/dr_conf.h")),
    ("dr_hal.h", include_str!("../../../runtime/dr_hal.h")),
    ("dr_module.h", include_str!("../../../runtime/dr_module.h")),
    ("dr_packet.h", include_str!("../../../runtime/dr_packet.h")),
    ("dr_packet.c", include_str!("../../../runtime/dr_packet.c")),
    ("dr_text.h", include_str!("../../../runtime/dr_text.h")),
    ("dr_text.c", include_str!("../../../runtime/dr_text.c")),
    ("dr_mcu.mk", include_str!("../../../runtime/dr_mcu.mk")),
];

/// `runtime/dr_warn.mk`, the one definition of the C language and warning flags. It is not
/// copied into a compiled directory: its flags are written into the generated Makefile
/// (`c::makefile`), so that the directory's bytes, and with them the program fingerprint, stay
/// what they were when the Makefile spelled them itself.
const DR_WARN_MK: &str = include_str!("../../../runtime/dr_warn.mk");

/// The flags of `DR_WARN = ...` in `runtime/dr_warn.mk`, in their order: what every C build of
/// dynarole compiles with (the runtime's Makefiles include the file, the generated Makefile
/// gets these words, the simulator passes them to `cc`).
pub fn warning_flags() -> Vec<&'static str> {
    const NAME: &str = "DR_WARN =";
    let flags: Vec<&'static str> = DR_WARN_MK
        .lines()
        .find_map(|line| line.strip_prefix(NAME))
        .map(|value| value.split_whitespace().collect())
        .unwrap_or_default();
    // The file is embedded at build time and a test reads it: this cannot fail at run time.
    assert!(
        !flags.is_empty() && flags.iter().all(|f| f.starts_with('-')),
        "runtime/dr_warn.mk defines DR_WARN as one line of flags"
    );
    flags
}

/// How long after a synchronous group of `members` is ready the lattice runtime starts it, in
/// ms: `DR_CONF_SYNC_DELAY_MS` plus `DR_CONF_SYNC_DELAY_PER_MEMBER_MS` for each member after
/// the first, the defaults of the embedded `runtime/dr_conf.h` (their one definition), so that
/// the critical path waits for the countdown as the modules do.
pub fn synchronous_delay_ms(members: usize) -> u64 {
    let base = conf_default("DR_CONF_SYNC_DELAY_MS");
    let per_member = conf_default("DR_CONF_SYNC_DELAY_PER_MEMBER_MS");
    base.saturating_add(per_member.saturating_mul(members.saturating_sub(1) as u64))
}

/// The number a `#define NAME N` of `runtime/dr_conf.h` gives.
fn conf_default(name: &str) -> u64 {
    let value = conf_text(name).and_then(|text| text.parse::<u64>().ok());
    // The file is embedded at build time and a test reads it: this cannot fail at run time.
    assert!(
        value.is_some(),
        "runtime/dr_conf.h defines {name} as a number"
    );
    value.unwrap_or_default()
}

/// What `#define NAME ...` of the embedded `runtime/dr_conf.h` defines `NAME` as, trimmed.
pub(crate) fn conf_text(name: &str) -> Option<&'static str> {
    COMMON[0]
        .1
        .lines()
        .filter_map(|line| line.trim().strip_prefix("#define "))
        .find_map(|rest| {
            let (key, value) = rest.split_once(char::is_whitespace)?;
            (key == name).then(|| value.trim())
        })
}

/// The lattice protocol. The describe file is for traces (host, simulator); the MCU build in
/// the generated Makefile leaves it out, with dr_text.c. The dissemination policies are
/// headers that dr_lattice.c includes (dr_dissemination.h), both copied: the configuration
/// header chooses one.
pub const LATTICE: [(&str, &str); 6] = [
    (
        "dr_lattice.h",
        include_str!("../../../runtime/lattice/dr_lattice.h"),
    ),
    (
        "dr_dissemination.h",
        include_str!("../../../runtime/lattice/dr_dissemination.h"),
    ),
    (
        "dr_dissemination_adaptive.h",
        include_str!("../../../runtime/lattice/dr_dissemination_adaptive.h"),
    ),
    (
        "dr_dissemination_fixed.h",
        include_str!("../../../runtime/lattice/dr_dissemination_fixed.h"),
    ),
    (
        "dr_lattice.c",
        include_str!("../../../runtime/lattice/dr_lattice.c"),
    ),
    (
        "dr_lattice_describe.c",
        include_str!("../../../runtime/lattice/dr_lattice_describe.c"),
    ),
];

/// The paper's protocol (describe file as above).
pub const PAPER: [(&str, &str); 3] = [
    (
        "dr_paper.h",
        include_str!("../../../runtime/paper/dr_paper.h"),
    ),
    (
        "dr_paper.c",
        include_str!("../../../runtime/paper/dr_paper.c"),
    ),
    (
        "dr_paper_describe.c",
        include_str!("../../../runtime/paper/dr_paper_describe.c"),
    ),
];

/// The token-passing baseline (describe file as above).
pub const TOKEN: [(&str, &str); 3] = [
    (
        "dr_token.h",
        include_str!("../../../runtime/token/dr_token.h"),
    ),
    (
        "dr_token.c",
        include_str!("../../../runtime/token/dr_token.c"),
    ),
    (
        "dr_token_describe.c",
        include_str!("../../../runtime/token/dr_token_describe.c"),
    ),
];
