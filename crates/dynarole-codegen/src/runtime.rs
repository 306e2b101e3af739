//! The runtime sources, embedded so that a compiled directory is self-contained.

/// Files every protocol needs.
pub const COMMON: [(&str, &str); 4] = [
    ("dr_conf.h", include_str!("../../../runtime/dr_conf.h")),
    ("dr_hal.h", include_str!("../../../runtime/dr_hal.h")),
    ("dr_packet.h", include_str!("../../../runtime/dr_packet.h")),
    ("dr_packet.c", include_str!("../../../runtime/dr_packet.c")),
];

pub const LATTICE: [(&str, &str); 2] = [
    (
        "dr_lattice.h",
        include_str!("../../../runtime/lattice/dr_lattice.h"),
    ),
    (
        "dr_lattice.c",
        include_str!("../../../runtime/lattice/dr_lattice.c"),
    ),
];

pub const PAPER: [(&str, &str); 2] = [
    (
        "dr_paper.h",
        include_str!("../../../runtime/paper/dr_paper.h"),
    ),
    (
        "dr_paper.c",
        include_str!("../../../runtime/paper/dr_paper.c"),
    ),
];
