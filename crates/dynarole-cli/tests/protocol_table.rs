//! The protocol table is the one place a protocol's properties are decided, checked on the
//! tree: no source outside it compares a protocol with one variant (`== Protocol::Token`) or
//! with a protocol's name (`== "token"`), tests that fall through silently for a new protocol.
//! A `match` naming every variant is allowed: the compiler makes a new protocol answer it.

mod common;

use common::tree::{tree_files, workspace};

/// The file that holds the table (and so may compare with its variants).
const TABLE: &str = "crates/dynarole-codegen/src/protocol.rs";

/// Every `.rs` file under each crate's `src/` and `benches/` (tests may name the protocol
/// they test), as (path from the workspace, text).
fn sources() -> Vec<(String, String)> {
    let crates = tree_files(&workspace().join("crates"), &|name| name.ends_with(".rs"));
    (crates.into_iter())
        .filter(|(path, _)| path.contains("/src/") || path.contains("/benches/"))
        .collect()
}

/// The line without its `//` comment (a `//` inside a string is rare enough in the patterns
/// looked for here not to matter).
fn code(line: &str) -> &str {
    line.find("//").map_or(line, |at| &line[..at])
}

/// The places in `text` that compare a protocol with one of its variants or names, as
/// (line number, line).
fn comparisons(text: &str, names: &[&str]) -> Vec<(usize, String)> {
    let compares = |code: &str| {
        let squeezed: String = code.split_whitespace().collect::<Vec<_>>().join("");
        let variant = ["==", "!="].iter().any(|op| {
            squeezed.contains(&format!("{op}Protocol::"))
                || squeezed.contains(&format!("{op}dynarole_codegen::Protocol::"))
                || squeezed.contains(&format!("{op}crate::Protocol::"))
                || ["Lattice", "Paper", "Token"]
                    .iter()
                    .any(|v| squeezed.contains(&format!("Protocol::{v}{op}")))
        });
        let name = names.iter().any(|n| {
            squeezed.contains(&format!("==\"{n}\"")) || squeezed.contains(&format!("!=\"{n}\""))
        });
        variant || name
    };
    (text.lines().enumerate())
        .filter(|(_, line)| compares(code(line)))
        .map(|(k, line)| (k + 1, line.trim().to_string()))
        .collect()
}

#[test]
fn no_source_compares_a_protocol_with_one_variant() {
    let names: Vec<&str> = dynarole_codegen::PROTOCOLS.iter().map(|p| p.name).collect();
    let mut found = Vec::new();
    for (path, text) in sources().iter().filter(|(path, _)| path != TABLE) {
        for (line, code) in comparisons(text, &names) {
            found.push(format!("{path}:{line}: {code}"));
        }
    }
    assert!(
        found.is_empty(),
        "decide these in the protocol table ({TABLE}) or with a `match` naming every \
         protocol:\n{}",
        found.join("\n")
    );
}

#[test]
fn a_comparison_is_found_and_a_match_is_not() {
    let names = ["token"];
    let text = "if options.protocol != Protocol::Token {\n\
                let x = protocol == dynarole_codegen::Protocol::Lattice;\n\
                if p.name == \"token\" {}\n\
                // a comment: protocol == Protocol::Paper\n\
                match protocol { Protocol::Paper => 1, Protocol::Lattice | Protocol::Token => 2 }\n\
                if protocol.needs_routes() {}\n";
    let found: Vec<usize> = comparisons(text, &names).iter().map(|(l, _)| *l).collect();
    assert_eq!(found, [1, 2, 3]);
}
