//! The layering ARCHITECTURE.md promises, checked on the tree: no import circle among the
//! top-level modules of any crate (read from the `crate::` and `super::` paths of its
//! sources), no crate depending on one after it in ARCHITECTURE.md's dependency order (from
//! `cargo metadata`), `compile` not linking the simulator, no two C files of `runtime/` calling
//! each other (from the functions each defines and the names each uses), no Makefile or
//! Rust file but `runtime/dr_warn.mk` spelling a warning flag, and trace events named only
//! through their vocabulary (`dynarole_recording::TraceEvent`).

mod common;

use common::tree::{metadata, sources, tree_files, workspace};
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

/// Circles that other changes are removing, as (crate, the modules of the circle). A circle
/// found must lie inside one of these; an entry that no longer matches a circle fails too, so
/// the list only shrinks.
const KNOWN_CIRCLES: &[(&str, &[&str])] = &[];

/// The CLI's modules on the path of `dynarole compile` (every target).
const COMPILE_MODULES: &[&str] = &["compile", "model"];

// ---------------------------------------------------------------------------------------
// Module graph of one crate.

/// One token of Rust source with comments, strings and characters removed.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Tok {
    Ident(String),
    PathSep,
    Open,
    Close,
    Comma,
    Other(char),
}

/// The tokens that matter for paths: identifiers, `::`, braces and commas.
fn tokens(text: &str) -> Vec<Tok> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            i = skip_block_comment(&chars, i);
        } else if c == '"' {
            i = skip_string(&chars, i + 1, 0);
        } else if c == 'r' && matches!(next, Some('"' | '#')) && raw_string_start(&chars, i) {
            let hashes = chars[i + 1..].iter().take_while(|&&h| h == '#').count();
            i = skip_string(&chars, i + 2 + hashes, hashes);
        } else if c == '\'' {
            i = skip_char_or_lifetime(&chars, i);
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(Tok::Ident(chars[start..i].iter().collect()));
        } else {
            out.push(match (c, next) {
                (':', Some(':')) => {
                    i += 1;
                    Tok::PathSep
                }
                ('{', _) => Tok::Open,
                ('}', _) => Tok::Close,
                (',', _) => Tok::Comma,
                _ => Tok::Other(c),
            });
            i += 1;
        }
    }
    out.into_iter()
        .filter(|t| !matches!(t, Tok::Other(c) if c.is_whitespace()))
        .collect()
}

/// Whether `r` at `i` opens a raw string (`r"`, `r#"`), not an identifier starting with r.
fn raw_string_start(chars: &[char], i: usize) -> bool {
    let after_ident = i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_');
    let hashes = chars[i + 1..].iter().take_while(|&&h| h == '#').count();
    !after_ident && chars.get(i + 1 + hashes) == Some(&'"')
}

fn skip_block_comment(chars: &[char], mut i: usize) -> usize {
    let mut depth = 0;
    while i < chars.len() {
        if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
            depth += 1;
            i += 2;
        } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
            depth -= 1;
            i += 2;
            if depth == 0 {
                return i;
            }
        } else {
            i += 1;
        }
    }
    i
}

/// Skips a string whose text starts at `i`, closed by `"` and `hashes` `#` (escapes only in a
/// plain string).
fn skip_string(chars: &[char], mut i: usize, hashes: usize) -> usize {
    while i < chars.len() {
        if hashes == 0 && chars[i] == '\\' {
            i += 2;
            continue;
        }
        if chars[i] == '"' && chars[i + 1..].iter().take_while(|&&h| h == '#').count() >= hashes {
            return i + 1 + hashes;
        }
        i += 1;
    }
    i
}

fn skip_char_or_lifetime(chars: &[char], i: usize) -> usize {
    match (chars.get(i + 1), chars.get(i + 2)) {
        (Some('\\'), _) => {
            // Past the escaped character, to the closing quote (`'\''`, `'\u{1F}'`).
            let mut j = i + 3;
            while j < chars.len() && chars[j] != '\'' {
                j += 1;
            }
            j + 1
        }
        (Some(_), Some('\'')) => i + 3,
        // A lifetime or a label: the name that follows is read as an identifier.
        _ => i + 1,
    }
}

/// The top-level modules `text` (the file of module path `path`, from the crate root) names
/// through `crate::` and `super::` paths, `use` groups included.
fn referenced(path: &[String], text: &str) -> BTreeSet<String> {
    let toks = tokens(text);
    let mut found = BTreeSet::new();
    // Inline modules (`mod tests { ... }`) open inside this file: their name and the brace
    // depth they close at.
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < toks.len() {
        match &toks[i] {
            Tok::Open => depth += 1,
            Tok::Close => {
                depth = depth.saturating_sub(1);
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
            }
            Tok::Ident(word) if word == "mod" => {
                if let (Some(Tok::Ident(name)), Some(Tok::Open)) =
                    (toks.get(i + 1), toks.get(i + 2))
                {
                    inline.push((name.clone(), depth));
                }
            }
            Tok::Ident(word) if word == "crate" || word == "super" => {
                let macro_crate = i > 0 && toks[i - 1] == Tok::Other('$');
                let after_sep = i > 0 && toks[i - 1] == Tok::PathSep;
                if !macro_crate && !after_sep && toks.get(i + 1) == Some(&Tok::PathSep) {
                    let here: Vec<String> = path
                        .iter()
                        .cloned()
                        .chain(inline.iter().map(|(n, _)| n.clone()))
                        .collect();
                    let (base, rest) = path_base(&toks, i, &here);
                    found.extend(targets(&toks, rest, &base));
                }
            }
            _ => {}
        }
        i += 1;
    }
    found
}

/// The module a path starting at `toks[i]` (`crate` or `super`) leaves from, seen from module
/// `here`, and the index of the token after its last `::`.
fn path_base(toks: &[Tok], mut i: usize, here: &[String]) -> (Vec<String>, usize) {
    if toks[i] == Tok::Ident("crate".into()) {
        return (Vec::new(), i + 2);
    }
    let mut base = here.to_vec();
    while toks.get(i) == Some(&Tok::Ident("super".into())) && toks.get(i + 1) == Some(&Tok::PathSep)
    {
        base.pop();
        i += 2;
    }
    (base, i)
}

/// The top-level modules named by the path segment(s) at `toks[i]` below `base`.
fn targets(toks: &[Tok], i: usize, base: &[String]) -> Vec<String> {
    if let Some(top) = base.first() {
        return vec![top.clone()];
    }
    match toks.get(i) {
        Some(Tok::Ident(name)) => vec![name.clone()],
        Some(Tok::Open) => {
            // `crate::{a::X, b}`: the first name of every item of the group.
            let mut names = Vec::new();
            let mut depth = 0;
            let mut at_item_start = true;
            for tok in &toks[i..] {
                match tok {
                    Tok::Open => {
                        depth += 1;
                        if depth == 1 {
                            continue;
                        }
                    }
                    Tok::Close => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    Tok::Comma if depth == 1 => {
                        at_item_start = true;
                        continue;
                    }
                    Tok::Ident(name) if depth == 1 && at_item_start => names.push(name.clone()),
                    _ => {}
                }
                at_item_start = false;
            }
            names
        }
        _ => Vec::new(),
    }
}

/// The module path of a file under `src/` (`a.rs`, `a/mod.rs`: `[a]`; `a/b.rs`: `[a, b]`);
/// the crate root (`lib.rs`, `main.rs`) is the empty path.
fn module_path(relative: &str) -> Vec<String> {
    let trimmed = relative.trim_end_matches(".rs");
    let mut parts: Vec<String> = trimmed.split('/').map(str::to_string).collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    if parts.len() == 1 && (parts[0] == "lib" || parts[0] == "main") {
        parts.clear();
    }
    parts
}

/// The import graph among the top-level modules of a crate whose `src/` holds `files`
/// (relative path, text). The root and `src/bin/` are left out: the root declares the
/// modules, and a binary is not imported.
fn module_graph(files: &[(String, String)]) -> BTreeMap<String, BTreeSet<String>> {
    let paths: Vec<(Vec<String>, &str)> = files
        .iter()
        .filter(|(rel, _)| !rel.starts_with("bin/"))
        .map(|(rel, text)| (module_path(rel), text.as_str()))
        .collect();
    let tops: BTreeSet<String> = paths
        .iter()
        .filter_map(|(p, _)| p.first().cloned())
        .collect();
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (path, text) in &paths {
        let Some(top) = path.first() else { continue };
        let edges = graph.entry(top.clone()).or_default();
        for target in referenced(path, text) {
            if target != *top && tops.contains(&target) {
                edges.insert(target);
            }
        }
    }
    graph
}

/// The strongly connected components of more than one module (Tarjan), each sorted.
fn circles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct Search<'g> {
        graph: &'g BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'g str, usize>,
        low: BTreeMap<&'g str, usize>,
        stack: Vec<&'g str>,
        on_stack: BTreeSet<&'g str>,
        out: Vec<Vec<String>>,
    }
    impl<'g> Search<'g> {
        fn visit(&mut self, v: &'g str) {
            let n = self.index.len();
            self.index.insert(v, n);
            self.low.insert(v, n);
            self.stack.push(v);
            self.on_stack.insert(v);
            let graph = self.graph;
            for w in graph.get(v).into_iter().flatten() {
                let w = w.as_str();
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let low = self.low[v].min(self.low[w]);
                    self.low.insert(v, low);
                } else if self.on_stack.contains(w) {
                    let low = self.low[v].min(self.index[w]);
                    self.low.insert(v, low);
                }
            }
            if self.low[v] == self.index[v] {
                let mut component = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on_stack.remove(w);
                    component.push(w.to_string());
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    self.out.push(component);
                }
            }
        }
    }
    let mut search = Search {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !search.index.contains_key(v.as_str()) {
            search.visit(v);
        }
    }
    search.out.sort();
    search.out
}

/// What is wrong with the circles found per crate, given the known ones.
fn circle_problems(
    found: &BTreeMap<String, Vec<Vec<String>>>,
    known: &[(&str, &[&str])],
) -> Vec<String> {
    let mut problems = Vec::new();
    for (krate, list) in found {
        for circle in list {
            let allowed = known.iter().any(|(k, modules)| {
                k == krate && circle.iter().all(|m| modules.contains(&m.as_str()))
            });
            if !allowed {
                problems.push(format!(
                    "{krate}: import circle among {}",
                    circle.join(", ")
                ));
            }
        }
    }
    for (krate, modules) in known {
        let still = found
            .get(*krate)
            .into_iter()
            .flatten()
            .any(|circle| circle.iter().all(|m| modules.contains(&m.as_str())));
        if !still {
            problems.push(format!(
                "{krate}: the known circle among {} is gone; remove it from KNOWN_CIRCLES",
                modules.join(", ")
            ));
        }
    }
    problems
}

/// Every crate of the tree and its folder: `crates/NAME/`, each robot's `robots/NAME/`
/// (the crate `dynarole-robot-NAME`) and `python/` (the crate `dynarole-python`).
fn crate_dirs() -> Vec<(String, PathBuf)> {
    let mut out = Vec::new();
    for (folder, prefix) in [("crates", ""), ("robots", "dynarole-robot-")] {
        let dirs = std::fs::read_dir(workspace().join(folder)).expect("the crates' folder");
        for path in dirs.flatten().map(|e| e.path()) {
            if path.join("src").is_dir() {
                let name = path
                    .file_name()
                    .expect("name")
                    .to_string_lossy()
                    .into_owned();
                out.push((format!("{prefix}{name}"), path));
            }
        }
    }
    // The Python package's native module is a crate of its own folder.
    out.push(("dynarole-python".to_string(), workspace().join("python")));
    out.sort();
    out
}

// ---------------------------------------------------------------------------------------
// Dependencies between crates.

/// ARCHITECTURE.md's dependency order and its test-only crates.
fn documented_order(architecture: &str) -> (Vec<String>, Vec<String>) {
    let start = architecture
        .find("Dependency order")
        .expect("ARCHITECTURE.md states the dependency order");
    let paragraph = architecture[start..].split("\n\n").next().unwrap_or("");
    let ticked = |text: &str| -> Vec<String> {
        text.split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect()
    };
    let body = paragraph.split_once(':').map_or("", |(_, b)| b);
    match body.split_once('(') {
        Some((order, tests)) if tests.contains("tests only") => (ticked(order), ticked(tests)),
        _ => (ticked(body), Vec::new()),
    }
}

/// Each workspace crate and the workspace crates it depends on (normal and build
/// dependencies; dev-dependencies when `dev`).
fn workspace_dependencies(metadata: &Value, dev: bool) -> BTreeMap<String, BTreeSet<String>> {
    let packages = metadata["packages"].as_array().expect("packages");
    let names: BTreeSet<String> = packages
        .iter()
        .filter_map(|p| p["name"].as_str().map(str::to_string))
        .collect();
    packages
        .iter()
        .filter_map(|p| {
            let deps = p["dependencies"]
                .as_array()?
                .iter()
                .filter(|d| dev || d["kind"].as_str() != Some("dev"))
                .filter_map(|d| d["name"].as_str())
                .filter(|d| names.contains(*d))
                .map(str::to_string)
                .collect();
            Some((p["name"].as_str()?.to_string(), deps))
        })
        .collect()
}

/// Crates placed nowhere in the order, and dependencies on a crate after the dependent.
fn order_problems(
    order: &[String],
    tests_only: &[String],
    deps: &BTreeMap<String, BTreeSet<String>>,
) -> Vec<String> {
    let position = |name: &str| order.iter().position(|o| o == name);
    let mut problems = Vec::new();
    for (krate, needs) in deps {
        if tests_only.contains(krate) {
            continue;
        }
        let Some(at) = position(krate) else {
            problems.push(format!(
                "{krate} is not in ARCHITECTURE.md's dependency order"
            ));
            continue;
        };
        for need in needs {
            match position(need) {
                Some(n) if n < at => {}
                _ => problems.push(format!("{krate} depends on {need}, which is not before it")),
            }
        }
    }
    problems
}

/// The crates `start` links, itself included.
fn closure(deps: &BTreeMap<String, BTreeSet<String>>, start: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut pending = vec![start.to_string()];
    while let Some(k) = pending.pop() {
        if seen.insert(k.clone()) {
            pending.extend(deps.get(&k).into_iter().flatten().cloned());
        }
    }
    seen
}

// ---------------------------------------------------------------------------------------
// The checks on the tree.

#[test]
fn no_import_circle_in_any_crate() {
    let mut found = BTreeMap::new();
    let mut edges = Vec::new();
    for (name, dir) in crate_dirs() {
        let graph = module_graph(&sources(&dir.join("src")));
        let list = circles(&graph);
        for circle in &list {
            for from in circle {
                let to = graph[from].iter().filter(|t| circle.contains(t));
                let to: Vec<&str> = to.map(String::as_str).collect();
                edges.push(format!("  {name}: {from} uses {}", to.join(", ")));
            }
        }
        if !list.is_empty() {
            found.insert(name, list);
        }
    }
    let problems = circle_problems(&found, KNOWN_CIRCLES);
    assert!(
        problems.is_empty(),
        "{}\nthe imports inside the circles:\n{}",
        problems.join("\n"),
        edges.join("\n")
    );
}

#[test]
fn no_crate_depends_on_one_after_it() {
    let architecture =
        std::fs::read_to_string(workspace().join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let (order, tests_only) = documented_order(&architecture);
    let deps = workspace_dependencies(&metadata(), false);
    let problems = order_problems(&order, &tests_only, &deps);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Where the modules `start` of a crate made of `files` reach (through its imports) a crate
/// that links `forbidden`: "FILE names CRATE".
fn links(
    files: &[(String, String)],
    start: &[&str],
    deps: &BTreeMap<String, BTreeSet<String>>,
    forbidden: &str,
) -> Vec<String> {
    let graph = module_graph(files);
    let mut reached = BTreeSet::new();
    let mut pending: Vec<String> = start.iter().map(|m| m.to_string()).collect();
    while let Some(m) = pending.pop() {
        if reached.insert(m.clone()) {
            pending.extend(graph.get(&m).into_iter().flatten().cloned());
        }
    }
    let mut found = BTreeSet::new();
    for (rel, text) in files {
        let top = module_path(rel).first().cloned().unwrap_or_default();
        if !reached.contains(&top) {
            continue;
        }
        for tok in tokens(text) {
            let Tok::Ident(word) = tok else { continue };
            let Some(krate) = word.strip_prefix("dynarole_") else {
                continue;
            };
            let krate = format!("dynarole-{}", krate.replace('_', "-"));
            if closure(deps, &krate).contains(forbidden) {
                found.insert(format!("{rel} names {krate}"));
            }
        }
    }
    found.into_iter().collect()
}

/// `compile` (every target) reaches no module that names the simulator, or a crate that
/// links it.
#[test]
fn compile_does_not_link_the_simulator() {
    let files = sources(&workspace().join("crates/dynarole-cli/src"));
    let deps = workspace_dependencies(&metadata(), false);
    let found = links(&files, COMPILE_MODULES, &deps, "dynarole-sim");
    assert!(
        found.is_empty(),
        "`compile` links dynarole-sim: {}",
        found.join("; ")
    );
    // The check looks at the real modules: `simulate` does link the simulator.
    assert!(!links(&files, &["simulate"], &deps, "dynarole-sim").is_empty());
}

// ---------------------------------------------------------------------------------------
// The checks themselves, on made-up crates.

fn files(list: &[(&str, &str)]) -> Vec<(String, String)> {
    list.iter()
        .map(|(p, t)| (p.to_string(), t.to_string()))
        .collect()
}

#[test]
fn finds_a_circle_through_use_groups_and_super() {
    let crate_files = files(&[
        ("lib.rs", "pub mod a; pub mod b; pub mod c; pub mod d;"),
        ("a.rs", "use crate::{b::Thing, c};"),
        ("b/mod.rs", "mod inner;"),
        ("b/inner.rs", "use super::super::a::Other;"),
        ("c.rs", "// use crate::d;\nconst S: &str = \"crate::d\";"),
        ("d.rs", "use crate::c::X;"),
    ]);
    let graph = module_graph(&crate_files);
    assert_eq!(
        circles(&graph),
        vec![vec!["a".to_string(), "b".to_string()]]
    );
    assert_eq!(
        graph["c"],
        BTreeSet::new(),
        "comments and strings are not imports"
    );
}

#[test]
fn a_test_module_using_super_is_no_circle() {
    let crate_files = files(&[
        (
            "a.rs",
            "pub struct A; #[cfg(test)] mod tests { use super::A; use crate::b::B; }",
        ),
        (
            "b.rs",
            "pub struct B; fn f<'a>(x: &'a str) -> char { let _ = r#\"crate::a\"#; 'x' }",
        ),
    ]);
    let graph = module_graph(&crate_files);
    assert_eq!(graph["a"], BTreeSet::from(["b".to_string()]));
    assert!(circles(&graph).is_empty());
}

#[test]
fn a_new_or_a_vanished_circle_is_a_problem() {
    let found = BTreeMap::from([(
        "k".to_string(),
        vec![vec!["x".to_string(), "y".to_string()]],
    )]);
    assert_eq!(
        circle_problems(&found, &[]),
        vec!["k: import circle among x, y".to_string()]
    );
    assert!(circle_problems(&found, &[("k", &["x", "y", "z"])]).is_empty());
    assert_eq!(
        circle_problems(&BTreeMap::new(), &[("k", &["x", "y"])]).len(),
        1
    );
}

#[test]
fn a_dependency_upwards_is_a_problem() {
    let architecture = "Dependency order (a crate depends only on crates before it): `low`,\n`high` (`fuzz`: tests only).\n\nNext.";
    let (order, tests_only) = documented_order(architecture);
    assert_eq!(order, vec!["low", "high"]);
    assert_eq!(tests_only, vec!["fuzz"]);
    let deps = |pairs: &[(&str, &[&str])]| -> BTreeMap<String, BTreeSet<String>> {
        pairs
            .iter()
            .map(|(k, d)| (k.to_string(), d.iter().map(|s| s.to_string()).collect()))
            .collect()
    };
    let fine = deps(&[("low", &[]), ("high", &["low"]), ("fuzz", &["high"])]);
    assert!(order_problems(&order, &tests_only, &fine).is_empty());
    let upwards = deps(&[("low", &["high"]), ("high", &[]), ("new", &[])]);
    assert_eq!(
        order_problems(&order, &tests_only, &upwards),
        vec![
            "low depends on high, which is not before it".to_string(),
            "new is not in ARCHITECTURE.md's dependency order".to_string()
        ]
    );
}

#[test]
fn a_module_reaching_the_simulator_through_imports_is_found() {
    let crate_files = files(&[
        ("compile.rs", "use crate::load::read;"),
        (
            "load.rs",
            "pub fn read() { dynarole_campaign::read_limited(); }",
        ),
        ("other.rs", "use dynarole_sim::Simulator;"),
    ]);
    let deps: BTreeMap<String, BTreeSet<String>> = BTreeMap::from([
        (
            "dynarole-campaign".to_string(),
            BTreeSet::from(["dynarole-sim".to_string()]),
        ),
        ("dynarole-sim".to_string(), BTreeSet::new()),
    ]);
    assert_eq!(
        links(&crate_files, &["compile"], &deps, "dynarole-sim"),
        vec!["load.rs names dynarole-campaign".to_string()]
    );
    assert!(links(&crate_files, &["load"], &deps, "dynarole-core").is_empty());
}

// ---------------------------------------------------------------------------------------
// The C runtime: no two files that call each other, and one list of warning flags.

/// C source without comments, string and character literals, or preprocessor lines (each
/// replaced by a space): what is left names only what the file's code uses and defines.
fn c_code(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    let mut line_start = true;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('*') {
            i += 2;
            while i < chars.len() && !(chars[i] == '*' && chars.get(i + 1) == Some(&'/')) {
                i += 1;
            }
            i += 2;
            out.push(' ');
        } else if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '"' || c == '\'' {
            i += 1;
            while i < chars.len() && chars[i] != c && chars[i] != '\n' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push(' ');
            line_start = false;
        } else if c == '#' && line_start {
            // A directive, with its `\`-continued lines (a macro body names no definition).
            while i < chars.len() && chars[i] != '\n' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
        } else {
            if c == '\n' {
                line_start = true;
            } else if !c.is_whitespace() {
                line_start = false;
            }
            out.push(c);
            i += 1;
        }
    }
    out
}

fn c_identifiers(code: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in code.char_indices().chain([(code.len(), ' ')]) {
        let ident = c == '_' || c.is_ascii_alphanumeric();
        match (start, ident) {
            (None, true) => start = Some(i),
            (Some(s), false) => {
                if !code[s..].starts_with(|c: char| c.is_ascii_digit()) {
                    out.push((s, &code[s..i]));
                }
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// The functions a C file defines with external linkage: at file scope, a name followed by a
/// parenthesised parameter list and a body, in a declaration that does not say `static`.
fn c_definitions(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut depth = 0usize;
    // Where the current file-scope declaration started.
    let mut start = 0;
    for (i, c) in code.char_indices() {
        match c {
            '{' if depth == 0 => {
                let head = code[start..i].trim_end();
                if let Some(name) = defined_function(head) {
                    out.insert(name);
                }
                depth = 1;
            }
            '{' => depth += 1,
            '}' if depth > 0 => {
                depth -= 1;
                if depth == 0 {
                    start = i + 1;
                }
            }
            ';' if depth == 0 => start = i + 1,
            _ => {}
        }
    }
    out
}

/// The name `head` (a file-scope declaration up to its `{`) defines as a function with external
/// linkage: `... name ( params )` with no `static` and no `=` (an initialiser's braces).
fn defined_function(head: &str) -> Option<String> {
    let params = head.strip_suffix(')')?;
    let open = params.rfind('(')?;
    if params[open + 1..].contains(['(', ')']) {
        return None;
    }
    let before = &head[..open];
    let (_, name) = *c_identifiers(before).last()?;
    let storage = c_identifiers(before);
    if before.contains('=') || storage.iter().any(|(_, w)| *w == "static") {
        return None;
    }
    before.trim_end().ends_with(name).then(|| name.to_string())
}

/// Which C file calls which: an edge from A to B when A names a function that B defines. A
/// function defined in several folders is a port, each build linking one of them (the
/// platforms' `dr_hal.h`, the protocols' `dr_module.h`, each test world's `dr_fake_of`):
/// naming it depends on no file in particular. Two definitions in one folder are not (a copy
/// must not hide a call): each is a file called.
fn c_call_graph(files: &[(String, String)]) -> BTreeMap<String, BTreeSet<String>> {
    let folder = |path: &str| path.rsplit_once('/').map_or("", |(dir, _)| dir).to_string();
    let code: Vec<(String, String)> = files.iter().map(|(p, t)| (p.clone(), c_code(t))).collect();
    let mut definers: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (path, text) in &code {
        for name in c_definitions(text) {
            definers.entry(name).or_default().insert(path.clone());
        }
    }
    definers.retain(|_, owners| {
        let folders: BTreeSet<String> = owners.iter().map(|p| folder(p)).collect();
        folders.len() == 1
    });
    let mut graph = BTreeMap::new();
    for (path, text) in &code {
        let mut to = BTreeSet::new();
        for (_, name) in c_identifiers(text) {
            let owners = definers.get(name).into_iter().flatten();
            // A file's own definition is what its uses of the name mean.
            if !owners.clone().any(|owner| owner == path) {
                to.extend(owners.cloned());
            }
        }
        graph.insert(path.clone(), to);
    }
    graph
}

#[test]
fn no_two_c_files_of_the_runtime_call_each_other() {
    let files = tree_files(&workspace().join("runtime"), &|name| name.ends_with(".c"));
    assert!(
        files.iter().any(|(p, _)| p == "runtime/fuzz/fuzz_hal.c"),
        "the runtime's C files are found"
    );
    let graph = c_call_graph(&files);
    let problems: Vec<String> = circles(&graph)
        .iter()
        .map(|circle| {
            let calls: Vec<String> = circle
                .iter()
                .map(|from| {
                    let to: Vec<&str> = graph[from]
                        .iter()
                        .filter(|t| circle.contains(t))
                        .map(String::as_str)
                        .collect();
                    format!("{from} calls {}", to.join(", "))
                })
                .collect();
            format!("C files calling each other: {}", calls.join("; "))
        })
        .collect();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn a_circle_of_c_files_is_found_and_a_port_is_none() {
    let c_files = files(&[
        (
            "hal.c",
            "#include \"fuzz.h\"\n#define CHECK(x) \\\n    do { fail(\"x\"); } while (0)\n\
             static void sent(void) { packet_check(); }\n\
             unsigned dr_hal_id(void) { return 1u; }\nvoid step(void) { dr_module_step(); }\n",
        ),
        (
            "packet.c",
            "/* hal.c: fail() */\nvoid packet_check(void)\n{\n    fail(\"bad\");\n}\n",
        ),
        (
            "fail.c",
            "static const int table[] = { 1 };\nvoid fail(const char *what) { (void)what; }\n",
        ),
        ("sim/hal.c", "unsigned dr_hal_id(void) { return 2u; }\n"),
        (
            "protocol.c",
            "void dr_module_step(void) { (void)dr_hal_id(); }\n",
        ),
    ]);
    let graph = c_call_graph(&c_files);
    assert_eq!(
        graph["hal.c"],
        BTreeSet::from(["packet.c".to_string(), "protocol.c".to_string()])
    );
    assert_eq!(graph["packet.c"], BTreeSet::from(["fail.c".to_string()]));
    assert_eq!(
        graph["fail.c"],
        BTreeSet::new(),
        "static and initialisers are no functions"
    );
    assert_eq!(
        graph["protocol.c"],
        BTreeSet::new(),
        "dr_hal_id is a port: two folders define it"
    );
    assert!(circles(&graph).is_empty());
    // The old fuzz drivers: the platform checks frames, the checks fail through the platform;
    // a second `fail` beside them does not hide the call.
    let mut circle = c_files.clone();
    circle[0]
        .1
        .push_str("void fail(const char *what) { (void)what; }\n");
    assert_eq!(
        circles(&c_call_graph(&circle)),
        vec![vec!["hal.c".to_string(), "packet.c".to_string()]]
    );
}

/// Where `text` spells a compiler warning flag (`-W` and a letter, after neither a letter nor a
/// digit; not the assembler's, preprocessor's or linker's pass-through `-Wa,` `-Wp,` `-Wl,`),
/// outside comment lines (`#` in a Makefile, `//` in Rust), as line numbers.
fn warning_flags_in(text: &str, comment: &str) -> Vec<usize> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        if line.trim_start().starts_with(comment) {
            continue;
        }
        let bytes = line.as_bytes();
        let spelled = (0..bytes.len().saturating_sub(2)).any(|i| {
            bytes[i] == b'-'
                && bytes[i + 1] == b'W'
                && bytes[i + 2].is_ascii_alphabetic()
                && bytes.get(i + 3) != Some(&b',')
                && (i == 0 || !bytes[i - 1].is_ascii_alphanumeric())
        });
        if spelled {
            out.push(n + 1);
        }
    }
    out
}

#[test]
fn warning_flags_are_spelled_only_in_dr_warn_mk() {
    let root = workspace();
    let makefiles = tree_files(&root, &|name| {
        name == "Makefile" || name.starts_with("Makefile.") || name.ends_with(".mk")
    });
    assert!(
        makefiles.iter().any(|(p, _)| p == "runtime/dr_warn.mk"),
        "runtime/dr_warn.mk is found"
    );
    let rust = tree_files(&root.join("crates"), &|name| name.ends_with(".rs"));
    let mut problems = Vec::new();
    for (files, comment) in [(&makefiles, "#"), (&rust, "//")] {
        for (path, text) in files {
            // dr_warn.mk is the one list; this file names the flags it looks for.
            if path == "runtime/dr_warn.mk" || path.ends_with("dynarole-cli/tests/architecture.rs")
            {
                continue;
            }
            for line in warning_flags_in(text, comment) {
                problems.push(format!(
                    "{path}:{line}: a warning flag outside runtime/dr_warn.mk (include it, or take \
                     dynarole_codegen::warning_flags())"
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn a_warning_flag_is_found_outside_comments() {
    assert_eq!(
        warning_flags_in(
            "# -Wall in a comment\nWARN = -std=c99 -Wall\nLD = -Wl,--gc-sections\n",
            "#"
        ),
        vec![2]
    );
    assert_eq!(
        warning_flags_in(
            "// \"-Wshadow\"\nlet a = [\"-Wshadow\"];\nlet b = \"dynarole-WHAT\";\n",
            "//"
        ),
        vec![2]
    );
}

// ---------------------------------------------------------------------------------------
// Trace events: one vocabulary (`crates/dynarole-recording/src/trace_event.rs`).

/// The functions that write a trace event, as (file, the start of their definition): each
/// takes the vocabulary's enum, so no caller can pass a word.
const EVENT_WRITERS: &[(&str, &str)] = &[
    ("crates/dynarole-sim/src/state.rs", "pub fn log("),
    ("crates/dynarole-sim/src/recorded.rs", "pub fn row("),
    ("crates/dynarole-sim/src/ops.rs", "fn violation("),
    ("crates/dynarole-recording/src/builder.rs", "pub fn event("),
    ("crates/dynarole-recording/src/builder.rs", "fn mark("),
];

/// The calls of the writers' names in Rust source, whose arguments must hold no event word.
const EVENT_CALLS: &[&str] = &[".log(", ".row(", ".violation(", ".event(", ".mark("];

/// The text of a function's parameters: from `head` (which ends with its `(`) to its `)`.
fn parameters<'t>(text: &'t str, head: &str) -> Option<&'t str> {
    let start = text.find(head)? + head.len();
    let end = text[start..].find(')')? + start;
    Some(&text[start..end])
}

/// The string literals (their text) passed to a call starting at each `callee` in `text`,
/// as (line, literal).
fn call_literals(text: &str, callee: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (at, _) in text.match_indices(callee) {
        let line = text[..at].matches('\n').count() + 1;
        let mut depth = 0;
        let mut literal: Option<String> = None;
        let mut escaped = false;
        for c in text[at + callee.len() - 1..].chars() {
            if let Some(l) = literal.as_mut() {
                match (escaped, c) {
                    (false, '\\') => escaped = true,
                    (false, '"') => out.push((line, literal.take().unwrap_or_default())),
                    _ => {
                        escaped = false;
                        l.push(c);
                    }
                }
                continue;
            }
            match c {
                '"' => literal = Some(String::new()),
                '(' => depth += 1,
                ')' => depth -= 1,
                _ => {}
            }
            if depth == 0 {
                break;
            }
        }
    }
    out
}

/// Where a JavaScript source maps an event or a marker kind to a colour by name
/// (`done: '#2ca02c'`, `"reset": "#d62728"`), or keeps one of the old colour tables.
fn js_colour_maps(text: &str, names: &[&str]) -> Vec<usize> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let spaced: String = line.split_whitespace().collect();
        let keyed = names.iter().any(|name| {
            [
                format!("{name}:'#"),
                format!("'{name}':'#"),
                format!("\"{name}\":\"#"),
            ]
            .iter()
            .any(|k| spaced.contains(k.as_str()))
        });
        if keyed || line.contains("KIND_COLOURS") || line.contains("OUTCOME_COLOURS") {
            out.push(n + 1);
        }
    }
    out
}

fn event_words() -> Vec<&'static str> {
    let events = dynarole_recording::EVENTS.iter().map(|e| e.name);
    events
        .chain(dynarole_recording::MARKS.iter().map(|m| m.name))
        .collect()
}

/// Problems of the Rust sources `files` (path from the workspace, text): a writer not taking
/// the enum, or an event word passed to a writer's name.
fn rust_event_problems(files: &[(String, String)], words: &[&str]) -> Vec<String> {
    let mut problems = Vec::new();
    for (file, head) in EVENT_WRITERS {
        let Some((_, text)) = files.iter().find(|(p, _)| p == file) else {
            problems.push(format!("{file}: not found (the writer `{head}` moved?)"));
            continue;
        };
        if !parameters(text, head).is_some_and(|p| p.contains("TraceEvent")) {
            problems.push(format!(
                "{file}: `{head}..)` must take a `TraceEvent`, not a word"
            ));
        }
    }
    for (path, text) in files {
        if path.ends_with("trace_event.rs") || path.contains("/tests/") {
            continue;
        }
        for callee in EVENT_CALLS {
            for (line, literal) in call_literals(text, callee) {
                if words.contains(&literal.as_str()) {
                    problems.push(format!(
                        "{path}:{line}: the event `{literal}` spelled as a word (take \
                         dynarole_recording::TraceEvent)"
                    ));
                }
            }
        }
    }
    problems
}

#[test]
fn trace_events_are_named_only_by_their_vocabulary() {
    let root = workspace();
    let words = event_words();
    let rust = tree_files(&root.join("crates"), &|name| name.ends_with(".rs"));
    let mut problems = rust_event_problems(&rust, &words);
    let js = tree_files(&root.join("crates/dynarole-viewer/web"), &|name| {
        name.ends_with(".js")
    });
    assert!(!js.is_empty(), "the viewer's sources are found");
    for (path, text) in &js {
        for line in js_colour_maps(text, &words) {
            problems.push(format!(
                "{path}:{line}: a colour by event name (take the page's vocabulary, from \
                 dynarole_recording::vocabulary_json)"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn a_word_for_an_event_is_found_in_a_call_and_in_a_colour_map() {
    let words = ["start", "reset"];
    let state = "pub fn log(&mut self, module: Option<usize>, event: &str) {}\n\
                 fn f(s: &mut State) {\n    s.log(Some(m), \"start\", format!(\"{x}\"));\n}\n";
    let files = vec![(
        "crates/dynarole-sim/src/state.rs".to_string(),
        state.to_string(),
    )];
    let problems = rust_event_problems(&files, &words);
    assert!(
        problems
            .iter()
            .any(|p| p.contains("state.rs: `pub fn log(..)`")),
        "{problems:?}"
    );
    assert!(
        problems
            .iter()
            .any(|p| p.contains("state.rs:3: the event `start`")),
        "{problems:?}"
    );
    let js = "const A = { reset: '#d62728' };\nconst B = { running: '#1f77b4' };\n";
    assert_eq!(js_colour_maps(js, &words), vec![1]);
}
