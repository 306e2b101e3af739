//! Runs a target over its corpus (regression) and over seeded mutations of it (proptest, so a
//! failure shrinks to a small input, which is saved to be added to the corpus).

use crate::corpus::{Corpus, Entry};
use crate::mutate::{apply, cases, Case};
use crate::targets::{Context, Outcome, Target, EXTREMES};
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestError, TestRng, TestRunner};
use std::cell::Cell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Environment variable: mutated cases per target.
pub const CASES_VAR: &str = "DYNAROLE_FUZZ_CASES";
/// Environment variable: the seed of the mutations (a `u64`).
pub const SEED_VAR: &str = "DYNAROLE_FUZZ_SEED";
/// The seed when [`SEED_VAR`] is not set.
pub const DEFAULT_SEED: u64 = 0x6479_6e61_726f_6c65;
/// Longest piece of a failing input quoted in the failure message (the file has all of it).
const QUOTE_CHARS: usize = 2000;

/// How many cases, from which seed, and where failing inputs go.
#[derive(Clone, Debug)]
pub struct Settings {
    pub cases: u32,
    pub seed: u64,
    pub failures_dir: PathBuf,
}

impl Settings {
    /// [`CASES_VAR`] (else `default_cases`) and [`SEED_VAR`] (else [`DEFAULT_SEED`]); an
    /// unreadable value is an error naming the variable.
    pub fn from_env(default_cases: u32, failures_dir: PathBuf) -> Result<Settings, String> {
        Ok(Settings {
            cases: read_var(CASES_VAR, default_cases)?,
            seed: read_var(SEED_VAR, DEFAULT_SEED)?,
            failures_dir,
        })
    }
}

fn read_var<T: std::str::FromStr>(name: &str, default: T) -> Result<T, String> {
    match std::env::var(name) {
        Ok(text) => text
            .trim()
            .parse()
            .map_err(|_| format!("{name}={text}: expected a non-negative integer")),
        Err(std::env::VarError::NotPresent) => Ok(default),
        Err(e) => Err(format!("{name}: {e}")),
    }
}

/// What a run did, for the test log.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    pub inputs: u64,
    pub accepted: u64,
    pub rejected: u64,
    pub elapsed: Duration,
}

impl Summary {
    fn count(&mut self, outcome: Outcome) {
        self.inputs += 1;
        match outcome {
            Outcome::Accepted => self.accepted += 1,
            Outcome::Rejected => self.rejected += 1,
        }
    }
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} inputs ({} accepted, {} rejected) in {:.2} s",
            self.inputs,
            self.accepted,
            self.rejected,
            self.elapsed.as_secs_f64()
        )
    }
}

/// Runs every corpus file through `target`; the first broken property or panic is an error
/// naming the file.
pub fn run_corpus(target: Target, ctx: &Context, corpus: &Corpus) -> Result<Summary, String> {
    let started = Instant::now();
    let mut summary = Summary::default();
    for entry in &corpus.entries {
        let outcome = run_one(target, ctx, &entry.text())
            .map_err(|e| format!("{}/{}: {e}", target.name(), entry.name))?;
        summary.count(outcome);
    }
    summary.elapsed = started.elapsed();
    Ok(summary)
}

/// `target` on `text`, a panic turned into an error.
fn run_one(target: Target, ctx: &Context, text: &str) -> Result<Outcome, String> {
    match catch_unwind(AssertUnwindSafe(|| target.run(ctx, text))) {
        Ok(result) => result,
        Err(panic) => Err(format!("panicked: {}", panic_text(panic.as_ref()))),
    }
}

fn panic_text(panic: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = panic.downcast_ref::<&str>() {
        return (*s).to_string();
    }
    panic.downcast_ref::<String>().cloned().unwrap_or_default()
}

/// Runs `settings.cases` seeded mutations of the corpus through `target`. A failure is
/// shrunk, saved under `settings.failures_dir`, and reported with the input.
pub fn run_mutations(
    target: Target,
    ctx: &Context,
    corpus: &Corpus,
    settings: &Settings,
) -> Result<Summary, String> {
    if corpus.entries.is_empty() || settings.cases == 0 {
        return Ok(Summary::default());
    }
    let started = Instant::now();
    let config = Config {
        cases: settings.cases,
        failure_persistence: None,
        max_shrink_iters: 4096,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(config, rng(settings.seed, target));
    let summary = Cell::new(Summary::default());
    let strategy = cases(target.vocabulary(), EXTREMES);
    let result = runner.run(&strategy, |case| {
        let text = String::from_utf8_lossy(&apply(&case, &corpus.entries)).into_owned();
        let outcome = run_one(target, ctx, &text).map_err(TestCaseError::fail)?;
        let mut s = summary.take();
        s.count(outcome);
        summary.set(s);
        Ok(())
    });
    let mut summary = summary.take();
    summary.elapsed = started.elapsed();
    match result {
        Ok(()) => Ok(summary),
        Err(TestError::Fail(reason, case)) => Err(report_failure(
            target,
            &corpus.entries,
            settings,
            &reason.to_string(),
            &case,
        )),
        Err(TestError::Abort(reason)) => Err(format!("{}: aborted: {reason}", target.name())),
    }
}

/// A ChaCha generator seeded by `seed` and the target's name, so targets get different cases.
fn rng(seed: u64, target: Target) -> TestRng {
    let mut bytes = [0u8; 32];
    let name_hash = fnv1a(target.name().as_bytes());
    bytes[..8].copy_from_slice(&seed.to_le_bytes());
    bytes[8..16].copy_from_slice(&name_hash.to_le_bytes());
    TestRng::from_seed(RngAlgorithm::ChaCha, &bytes)
}

fn report_failure(
    target: Target,
    corpus: &[Entry],
    settings: &Settings,
    reason: &str,
    case: &Case,
) -> String {
    let bytes = apply(case, corpus);
    let saved = save_failure(target, settings, &bytes);
    let text = String::from_utf8_lossy(&bytes);
    let quoted: String = text.chars().take(QUOTE_CHARS).collect();
    format!(
        "{}: {reason}\nseed {} ({SEED_VAR}); input ({} bytes) {saved}:\n{quoted:?}\n\
         Keep it as a regression case: move it to fuzz/corpus/{} (or fuzz/regressions/{}).",
        target.name(),
        settings.seed,
        bytes.len(),
        target.name(),
        target.name()
    )
}

/// Writes a failing input under `failures_dir/<target>/`; says where (or why not).
fn save_failure(target: Target, settings: &Settings, bytes: &[u8]) -> String {
    let dir = settings.failures_dir.join(target.name());
    let hash = fnv1a(bytes);
    let path = dir.join(format!("failure-{hash:016x}"));
    match std::fs::create_dir_all(&dir).and_then(|()| std::fs::write(&path, bytes)) {
        Ok(()) => format!("saved to {}", path.display()),
        Err(e) => format!("not saved ({}: {e})", path.display()),
    }
}

/// FNV-1a: a stable hash (std's hashers are not guaranteed stable across releases).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    })
}
