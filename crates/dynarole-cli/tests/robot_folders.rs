//! A robot is one folder: outside `robots/`, the registry crate (`crates/dynarole-robots`),
//! tests, benchmarks, docs and examples, no source file (Rust, C, JavaScript) names a robot
//! kind of the registry, so that adding a robot touches its folder and one line of the
//! registry only (docs/robots.md).

mod common;

use common::tree::{tree_files, workspace};

/// Folders whose files may name robots: the robots' own folders, the registry, and what only
/// describes or exercises the tool (`tests/`, `benches/`, `examples/`, `docs/`, fuzz corpora).
const MAY_NAME_ROBOTS: [&str; 8] = [
    "robots/",
    "crates/dynarole-robots/",
    "/tests/",
    "/benches/",
    "examples/",
    // A crate's examples (a robot from outside the tree) name their own robot.
    "/examples/",
    "docs/",
    "fuzz/corpus/",
];

/// The spellings of every built-in robot kind looked for, lower case and without hyphens
/// (`M-TRAN` is `mtran`): its plugin name and its data files' `robot` value.
fn robot_words() -> Vec<String> {
    let mut words: Vec<String> = dynarole_robots::BUILT_IN
        .iter()
        .flat_map(|k| [k.name(), k.file_tag()])
        .map(|w| w.to_lowercase().replace('-', ""))
        .collect();
    words.sort();
    words.dedup();
    words
}

/// Whether `line` names `word` (lower case) as a word of its own: not inside a longer
/// identifier or word (`patron` is no robot), an underscore or a dot being a boundary.
fn names(line: &str, word: &str) -> bool {
    let line = line.to_lowercase().replace('-', "");
    let bytes = line.as_bytes();
    line.match_indices(word).any(|(at, _)| {
        let before = at.checked_sub(1).map(|i| bytes[i]);
        let after = bytes.get(at + word.len()).copied();
        let boundary = |c: Option<u8>| c.is_none_or(|c| !c.is_ascii_alphanumeric());
        boundary(before) && boundary(after)
    })
}

/// The part of a Rust file before its unit tests (`#[cfg(test)]`), which are tests.
fn before_unit_tests(text: &str) -> &str {
    text.find("#[cfg(test)]").map_or(text, |at| &text[..at])
}

/// Every `path:line: text` of a source file outside [`MAY_NAME_ROBOTS`] that names one of
/// `words`.
fn robot_names_outside_folders(files: &[(String, String)], words: &[String]) -> Vec<String> {
    let mut problems = Vec::new();
    for (path, text) in files {
        let exempt = MAY_NAME_ROBOTS.iter().any(|f| {
            if f.starts_with('/') {
                path.contains(f)
            } else {
                path.starts_with(f)
            }
        });
        if exempt || path.starts_with("out/") {
            continue;
        }
        let text = if path.ends_with(".rs") {
            before_unit_tests(text)
        } else {
            text
        };
        for (n, line) in text.lines().enumerate() {
            if words.iter().any(|w| names(line, w)) {
                problems.push(format!("{path}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    problems
}

#[test]
fn no_source_outside_the_robot_folders_names_a_robot() {
    let words = robot_words();
    assert!(words.len() >= 2, "the registry's robots: {words:?}");
    let files = tree_files(&workspace(), &|name| {
        [".rs", ".js", ".c", ".h"].iter().any(|e| name.ends_with(e))
    });
    assert!(
        files
            .iter()
            .any(|(p, _)| p == "crates/dynarole-world/src/lib.rs"),
        "the tree's sources are found"
    );
    let problems = robot_names_outside_folders(&files, &words);
    assert!(
        problems.is_empty(),
        "a robot named outside its folder (move the knowledge into robots/NAME/, or ask the \
         robot API for it):\n{}",
        problems.join("\n")
    );
}

#[test]
fn a_robot_name_is_found_as_a_word_and_only_outside_tests() {
    let words = vec!["atron".to_string(), "mtran".to_string()];
    let file = |path: &str, text: &str| (path.to_string(), text.to_string());
    let files = [
        file("crates/x/src/a.rs", "// the ATRON board\nfn f() {}\n"),
        file("crates/x/src/b.rs", "// a patron of the arts\n"),
        file(
            "crates/x/src/c.rs",
            "fn f() {}\n#[cfg(test)]\nmod t { \"robot atron;\" }\n",
        ),
        file("crates/x/tests/d.rs", "robot atron;\n"),
        file("robots/atron/src/lib.rs", "\"atron\"\n"),
        file("crates/x/web/src/e.js", "if (robot === 'M-TRAN') {}\n"),
    ];
    let problems = robot_names_outside_folders(&files, &words);
    assert_eq!(
        problems,
        [
            "crates/x/src/a.rs:1: // the ATRON board",
            "crates/x/web/src/e.js:1: if (robot === 'M-TRAN') {}"
        ]
    );
}
