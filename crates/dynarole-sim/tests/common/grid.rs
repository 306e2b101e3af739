//! The scale benchmark's structure, shared with the memory test: a flat ATRON grid of N
//! modules generated in memory (`benches/scale.rs` says how it is laid out).
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::fmt::Write;

/// The one statement: M0 (the corner, NS_BROKEN, latched only on connector 4, in its south
/// hemisphere) turns its joint a quarter; nothing is attached to the turning half.
pub const SOURCE: &str = "robot atron;\n\
    sequence spread {\n    M0.Joint.rotateFromToBy(0, 108, true, 150);\n}\n";

/// The connections of a NS_BROKEN module at (x, z): its male connector, the EW neighbour's
/// offset (dx, dz), and the EW module's female connector (`eight.json`).
const LATCHES: [(u8, i64, i64, u8); 4] =
    [(0, 1, -1, 1), (2, -1, -1, 5), (4, 1, 1, 3), (6, -1, 1, 7)];

/// One module of the generated structure.
pub struct Site {
    pub name: String,
    pub id: Option<u32>,
    pub x: i64,
    pub z: i64,
}

/// The data-file JSON of a flat structure on `sites` (modules and their latches).
pub fn structure_json(name: &str, sites: &[Site]) -> String {
    let at: BTreeMap<(i64, i64), &str> = sites
        .iter()
        .map(|s| ((s.x, s.z), s.name.as_str()))
        .collect();
    let mut out = String::with_capacity(sites.len() * 160);
    let _ = write!(
        out,
        "{{\"name\": \"{name}\", \"robot\": \"ATRON\", \"lattice_unit_m\": 0.08, \"modules\": ["
    );
    for (k, s) in sites.iter().enumerate() {
        let separator = if k == 0 { "" } else { "," };
        let id = s.id.map(|i| format!("\"id\": {i}, ")).unwrap_or_default();
        let orientation = if s.x.rem_euclid(2) == 0 {
            "NS_BROKEN"
        } else {
            "EW"
        };
        let _ = write!(
            out,
            "{separator}\n{{\"name\": \"{}\", {id}\"position\": [{}, 0, {}], \"orientation\": \"{orientation}\", \"joint\": 0}}",
            s.name, s.x, s.z
        );
    }
    out.push_str("\n], \"connections\": [");
    let mut first = true;
    for s in sites.iter().filter(|s| s.x.rem_euclid(2) == 0) {
        for (male, dx, dz, female) in LATCHES {
            if let Some(other) = at.get(&(s.x + dx, s.z + dz)) {
                let separator = if first { "" } else { "," };
                first = false;
                let _ = write!(
                    out,
                    "{separator}\n[\"{}\", {male}, \"{other}\", {female}]",
                    s.name
                );
            }
        }
    }
    out.push_str("\n]}\n");
    out
}

/// `n` sites row by row from the corner (0, 0), which is `M0` (ID 0); no other ID.
pub fn square(n: usize) -> Vec<Site> {
    let side = ((2 * n) as f64).sqrt().ceil() as i64;
    let mut sites = Vec::with_capacity(n);
    'rows: for z in 0.. {
        for x in (z % 2..side).step_by(2) {
            if sites.len() == n {
                break 'rows;
            }
            let (name, id) = if (x, z) == (0, 0) {
                ("M0".to_string(), Some(0))
            } else {
                (format!("s{x}_{z}"), None)
            };
            sites.push(Site { name, id, x, z });
        }
    }
    sites
}
