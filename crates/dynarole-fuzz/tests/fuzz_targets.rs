//! The fuzz run of `cargo test`: for each target, every file of `fuzz/corpus/<target>/`, then
//! `DYNAROLE_FUZZ_CASES` seeded mutations of them (see `docs/fuzzing.md`). The hostile
//! regression inputs of `fuzz/regressions/` wait for the size limits to land.

use dynarole_fuzz::{corpus, run_corpus, run_mutations, Context, Corpus, Settings, Target};
use std::path::PathBuf;

/// Mutated cases per target when `DYNAROLE_FUZZ_CASES` is not set: the whole run stays within
/// about a minute in a debug build on two cores.
const DEFAULT_CASES: u32 = 2000;

fn context() -> Context {
    let plugins =
        Corpus::load(&corpus::root().join("corpus/plugin")).unwrap_or_else(|e| panic!("{e}"));
    let texts: Vec<String> = plugins.entries.iter().map(|e| e.text()).collect();
    Context::new(&texts)
}

fn settings() -> Settings {
    let failures = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz-failures");
    Settings::from_env(DEFAULT_CASES, failures).unwrap_or_else(|e| panic!("{e}"))
}

/// The corpus of `target` and the mutations of it.
fn fuzz(target: Target) {
    let dir = corpus::root().join("corpus").join(target.name());
    let corpus = Corpus::load(&dir).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        !corpus.entries.is_empty(),
        "{}: empty corpus",
        dir.display()
    );
    let ctx = context();
    let regression = run_corpus(target, &ctx, &corpus).unwrap_or_else(|e| panic!("{e}"));
    eprintln!("{} corpus: {regression}", target.name());
    let mutations =
        run_mutations(target, &ctx, &corpus, &settings()).unwrap_or_else(|e| panic!("{e}"));
    eprintln!("{} mutations: {mutations}", target.name());
}

#[test]
fn parse() {
    fuzz(Target::Parse);
}

#[test]
fn check() {
    fuzz(Target::Check);
}

#[test]
fn format() {
    fuzz(Target::Format);
}

#[test]
fn configuration() {
    fuzz(Target::Configuration);
}

#[test]
fn scenario() {
    fuzz(Target::Scenario);
}

#[test]
fn campaign() {
    fuzz(Target::Campaign);
}

#[test]
fn plugin() {
    fuzz(Target::Plugin);
}

#[test]
fn plan() {
    fuzz(Target::Plan);
}

/// The hostile inputs of `target` (`fuzz/regressions/<target>/`), every path run.
fn regressions(target: Target) {
    let dir = corpus::root().join("regressions").join(target.name());
    let corpus = Corpus::load(&dir).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        !corpus.entries.is_empty(),
        "{}: no regressions",
        dir.display()
    );
    let summary = run_corpus(target, &context(), &corpus).unwrap_or_else(|e| panic!("{e}"));
    eprintln!("{} regressions: {summary}", target.name());
}

/// Lines of thousands of unknown characters: one diagnostic each until the lexer merges them.
#[test]
fn parse_regressions() {
    regressions(Target::Parse);
}

/// `seeds = 4294967296`: planned one run per seed before any limit.
#[test]
fn campaign_regressions() {
    regressions(Target::Campaign);
}

/// `count = 1000000000`: the loader names every index before checking the count.
#[test]
fn plugin_regressions() {
    regressions(Target::Plugin);
}

/// Two runs from one seed see the same cases (the counts of each outcome agree).
#[test]
fn one_seed_gives_the_same_cases() {
    let dir = corpus::root().join("corpus").join(Target::Scenario.name());
    let corpus = Corpus::load(&dir).unwrap_or_else(|e| panic!("{e}"));
    let settings = Settings {
        cases: 300,
        seed: 3,
        ..settings()
    };
    let ctx = context();
    let counts = || {
        let s = run_mutations(Target::Scenario, &ctx, &corpus, &settings)
            .unwrap_or_else(|e| panic!("{e}"));
        (s.inputs, s.accepted, s.rejected)
    };
    let first = counts();
    assert_eq!(first.0, 300);
    assert_eq!(first, counts());
}
