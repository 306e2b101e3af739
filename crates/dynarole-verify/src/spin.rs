//! Running spin on a generated model: generate the verifier (`spin -a`), compile it with a
//! memory limit, run it with a time limit (reporting progress to an observer), read its
//! figures, replay a counterexample, and tell a verdict from a failure of the tools.

use crate::report::{Observer, Phase};
pub use crate::search::{Check, PanResult};
use crate::VerifyError;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Limits of one search.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    pub memory_mb: u64,
    pub time_s: u64,
    /// Bitstate hashing (`-DBITSTATE`): a partial search in a fixed amount of memory.
    pub bitstate: bool,
    /// Iterative shortening (`-DREACH`, `pan -i`, safety only): the shortest counterexample.
    pub shortest: bool,
    /// A bounded search: no run longer than this many steps (`pan -m`, with `-DREACH` so that
    /// a state met again on a shorter path is searched again: every run within the bound is
    /// covered).
    pub depth: Option<u64>,
}

const MAX_DEPTH: &str = "-m1000000";

/// Checks that spin and a C compiler are there; the error says how to install them.
pub fn check_tools() -> Result<(), VerifyError> {
    let spin = Command::new("spin")
        .arg("-V")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if spin.is_err() {
        return Err(VerifyError::Internal(
            "spin is not installed (it is needed to model-check): install it with `sudo apt-get install spin` (Debian, Ubuntu) or from https://spinroot.com, or run ./scripts/test once, which installs it".into(),
        ));
    }
    let cc = Command::new("cc")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if cc.is_err() {
        return Err(VerifyError::Internal(
            "no C compiler `cc` (spin's verifiers are C programs): install gcc or clang".into(),
        ));
    }
    Ok(())
}

/// Where an internal failure should be reported, and what to attach.
const REPORT: &str = "this is a bug in dynarole or a limit of spin it does not handle, not a verdict on the sequence: please report it with the sequence, the configuration and the options, and the files `--keep DIR` writes (model.pml and the logs)";

/// A tool that `verify` runs, for the messages of its failures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// `spin -a`: reads the model and writes the verifier's C.
    Spin,
    /// `cc` on spin's `pan.c`.
    Compiler,
    /// The verifier, `pan`.
    Pan,
    /// `spin -t`: replays a counterexample.
    Replay,
}

/// The internal failure of `tool`, from its output: the lines that say what went wrong.
pub fn tool_failure(tool: Tool, output: &str) -> VerifyError {
    let what = match tool {
        Tool::Spin => "spin rejected the generated model",
        Tool::Compiler => "the C compiler failed on spin's verifier (pan.c)",
        Tool::Pan => "spin's verifier (pan) stopped without a result",
        Tool::Replay => "spin could not replay the counterexample",
    };
    let lines: Vec<&str> = output
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    // spin: `spin: model.pml:145, Error: d_step sequence too long`; cc: `pan.c:12: error: ...`;
    // pan: `pan: error, VECTORSZ too small ...`.
    let said: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| {
            let lower = l.to_ascii_lowercase();
            lower.contains("error") || lower.starts_with("pan:") || lower.contains("killed")
        })
        .take(5)
        .collect();
    let said = if said.is_empty() {
        lines.iter().rev().take(5).rev().copied().collect()
    } else {
        said
    };
    let detail = if said.is_empty() {
        "(no output)".to_string()
    } else {
        said.join("\n  ")
    };
    VerifyError::Internal(format!("{what}:\n  {detail}\n{REPORT}"))
}

fn log_file(dir: &Path, log: &str) -> Result<(std::fs::File, std::fs::File), VerifyError> {
    let cannot = |e: std::io::Error| {
        VerifyError::Internal(format!("cannot write in {}: {e}", dir.display()))
    };
    let out = std::fs::File::create(dir.join(log)).map_err(cannot)?;
    let err = out.try_clone().map_err(cannot)?;
    Ok((out, err))
}

fn spawn(cmd: &mut Command, dir: &Path, log: &str, tool: Tool) -> Result<Child, VerifyError> {
    let (out, err) = log_file(dir, log)?;
    cmd.current_dir(dir)
        .stdout(out)
        .stderr(err)
        .spawn()
        .map_err(|e| tool_failure(tool, &format!("cannot run it: {e}")))
}

/// Runs a tool that must succeed (spin -a, cc) with its output in `dir/log`, reporting progress.
fn run_to_file(
    cmd: &mut Command,
    dir: &Path,
    log: &str,
    tool: Tool,
    progress: &mut Progress,
) -> Result<(), VerifyError> {
    let mut child = spawn(cmd, dir, log, tool)?;
    let succeeded = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status.success(),
            Ok(None) if progress.stop_requested() => return Err(stopped(&mut child)),
            Ok(None) => {
                progress.tick(None);
                std::thread::sleep(POLL);
            }
            Err(e) => return Err(tool_failure(tool, &format!("waiting for it: {e}"))),
        }
    };
    if !succeeded {
        let text = std::fs::read_to_string(dir.join(log)).unwrap_or_default();
        return Err(tool_failure(tool, &text));
    }
    Ok(())
}

/// A tool stopped because the check was asked to stop.
fn stopped(child: &mut Child) -> VerifyError {
    let _ = child.kill();
    let _ = child.wait();
    VerifyError::Interrupted
}

/// How often a running tool is looked at.
const POLL: Duration = Duration::from_millis(20);

/// Progress of the tool runs of one check, told to an observer (which decides how and how
/// often to show it): begun when made, ended when dropped.
pub struct Progress<'o> {
    label: String,
    phase: Phase,
    observer: &'o mut dyn Observer,
}

impl<'o> Progress<'o> {
    /// Progress of the check named `label` (e.g. `M3: S1, S2, S3 (safety)`).
    pub fn new(label: &str, observer: &'o mut dyn Observer) -> Progress<'o> {
        observer.begin(label);
        Progress {
            label: label.to_string(),
            phase: Phase::Generating,
            observer,
        }
    }

    fn phase(&mut self, phase: Phase) {
        self.phase = phase;
        self.tick(None);
    }

    /// Reports what runs now; `search` is pan's (states, depth) so far.
    /// Whether the observer asks the check to stop.
    fn stop_requested(&mut self) -> bool {
        self.observer.stop_requested()
    }

    fn tick(&mut self, search: Option<(u64, u64)>) {
        self.observer.progress(&self.label, self.phase, search);
    }
}

impl Drop for Progress<'_> {
    fn drop(&mut self) {
        self.observer.end();
    }
}

/// The processes of a model whose count is not known (a model file written elsewhere): the
/// most spin runs (its process numbers are bytes).
const MOST_PROCESSES: usize = 255;

/// Generates, compiles and runs the verifier for `check` on `dir/model.pml`, a model written
/// elsewhere (its processes not known: the fairness bound allows the most spin runs), with
/// no progress shown. Failures of the tools are internal failures; a search that hits a
/// limit is a result (incomplete).
pub fn run_check(
    dir: &Path,
    check: Check,
    limits: Limits,
    label: &str,
) -> Result<PanResult, VerifyError> {
    let mut quiet = crate::report::Quiet;
    let mut progress = Progress::new(label, &mut quiet);
    build(dir, check, limits, MOST_PROCESSES, &mut progress)?;
    search(dir, check, limits, &mut progress)
}

/// [`run_check`] on a model of `processes` processes (`Model::processes`), with `progress`.
pub fn run_model(
    dir: &Path,
    check: Check,
    limits: Limits,
    processes: usize,
    progress: &mut Progress,
) -> Result<PanResult, VerifyError> {
    build(dir, check, limits, processes, progress)?;
    search(dir, check, limits, progress)
}

/// Generates and compiles the verifier (`dir/pan`) for `check` within `limits` (the depth
/// bound is given to pan when it runs, so one build serves every bound); `processes`: the
/// model's (`Model::processes`), for the fairness bound of liveness.
pub fn build(
    dir: &Path,
    check: Check,
    limits: Limits,
    processes: usize,
    progress: &mut Progress,
) -> Result<(), VerifyError> {
    let mut spin = Command::new("spin");
    if check == Check::Liveness {
        spin.arg("-DLIVENESS");
    }
    spin.args(["-a", "model.pml"]);
    run_to_file(&mut spin, dir, "spin.log", Tool::Spin, progress)?;
    let mut cc = Command::new("cc");
    // Measured on eight2car's models: -O1 halves the compile time and runs a safety search
    // as fast as -O2; the liveness search (weak fairness) runs twice as fast with -O2.
    let optimise = match check {
        Check::Safety => "-O1",
        Check::Liveness => "-O2",
    };
    cc.args([optimise, "-w", "-o", "pan", "pan.c", "-DVECTORSZ=8192"]);
    cc.arg(format!("-DMEMLIM={}", limits.memory_mb));
    match check {
        Check::Safety => {
            cc.args(["-DSAFETY", "-DNOCLAIM"]);
        }
        Check::Liveness => {
            cc.arg(format!("-DNFAIR={}", fairness_bound(processes)));
        }
    }
    if limits.bitstate {
        cc.arg("-DBITSTATE");
    } else {
        cc.arg("-DCOLLAPSE");
    }
    if (limits.shortest && check == Check::Safety) || limits.depth.is_some() {
        cc.arg("-DREACH");
    }
    progress.phase(Phase::Compiling);
    run_to_file(&mut cc, dir, "cc.log", Tool::Compiler, progress)?;
    Ok(())
}

/// pan's `NFAIR` for a model of `processes` processes: weak fairness needs
/// (8 * NFAIR) / 2 - 2 > processes, counting `init` and the never claim (pan's own check).
fn fairness_bound(processes: usize) -> usize {
    (processes + 2 + 3).div_ceil(4) + 1
}

/// Runs the verifier that [`build`] made, within `limits`, and reads its figures.
pub fn search(
    dir: &Path,
    check: Check,
    limits: Limits,
    progress: &mut Progress,
) -> Result<PanResult, VerifyError> {
    progress.phase(Phase::Searching);
    let started = Instant::now();
    let mut child = spawn(&mut pan_command(check, limits), dir, "pan.log", Tool::Pan)?;
    let ended = wait_for_pan(
        &mut child,
        dir,
        Duration::from_secs(limits.time_s),
        progress,
    )?;
    let text = std::fs::read_to_string(dir.join("pan.log")).unwrap_or_default();
    let mut result = parse_pan(&text);
    let timed_out = ended == PanEnd::TimedOut;
    // The system's out-of-memory killer stops pan without a word: a search out of memory.
    result.out_of_memory |= ended == PanEnd::Killed && !result.reported;
    if !timed_out && !result.reported && !result.out_of_memory {
        return Err(tool_failure(Tool::Pan, &text));
    }
    result.timed_out = timed_out;
    result.bitstate = limits.bitstate;
    result.bounded = limits.depth.is_some();
    if timed_out {
        result.seconds = started.elapsed().as_secs_f64();
    }
    Ok(result)
}

/// pan's command line for `check` within `limits`.
fn pan_command(check: Check, limits: Limits) -> Command {
    let mut pan = Command::new("./pan");
    match limits.depth {
        Some(depth) => pan.arg(format!("-m{depth}")),
        None => pan.arg(MAX_DEPTH),
    };
    if limits.bitstate {
        // 2^k bits of hash array, within the memory limit (at most 2^33 bits = 1 GiB).
        let bits = (limits.memory_mb.max(16) * 8 * 1024 * 1024 / 2)
            .ilog2()
            .min(33);
        pan.arg(format!("-w{bits}"));
    }
    if check == Check::Liveness {
        pan.args(["-a", "-f", "-N", "finishes"]);
    } else if limits.shortest {
        pan.arg("-i");
    }
    pan
}

/// How a pan run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PanEnd {
    /// It stopped by itself.
    Exited,
    /// The system killed it (SIGKILL: the out-of-memory killer).
    Killed,
    /// It ran out of time and was stopped.
    TimedOut,
}

/// Waits for pan (stopping it after `time`), telling `progress` its figures so far.
fn wait_for_pan(
    child: &mut Child,
    dir: &Path,
    time: Duration,
    progress: &mut Progress,
) -> Result<PanEnd, VerifyError> {
    let started = Instant::now();
    let mut looked = Instant::now();
    let mut search = None;
    loop {
        match child.try_wait() {
            Ok(Some(status)) if killed_by_the_system(status) => return Ok(PanEnd::Killed),
            Ok(Some(_)) => return Ok(PanEnd::Exited),
            Ok(None) if started.elapsed() > time => {
                let _ = child.kill();
                let _ = child.wait();
                return Ok(PanEnd::TimedOut);
            }
            Ok(None) if progress.stop_requested() => return Err(stopped(child)),
            Ok(None) => {
                // pan prints `Depth= ... States= ...` every million states.
                if looked.elapsed() >= Duration::from_secs(1) {
                    looked = Instant::now();
                    let text = std::fs::read_to_string(dir.join("pan.log")).unwrap_or_default();
                    let so_far = parse_pan(&text);
                    search = (so_far.states > 0).then_some((so_far.states, so_far.depth));
                }
                progress.tick(search);
                std::thread::sleep(POLL);
            }
            Err(e) => return Err(tool_failure(Tool::Pan, &format!("waiting for it: {e}"))),
        }
    }
}

/// Whether a process was ended by SIGKILL, which the system's out-of-memory killer sends.
#[cfg(unix)]
fn killed_by_the_system(status: std::process::ExitStatus) -> bool {
    use std::os::unix::process::ExitStatusExt;
    status.signal() == Some(9)
}

#[cfg(not(unix))]
fn killed_by_the_system(_status: std::process::ExitStatus) -> bool {
    false
}

/// Reads pan's report.
pub fn parse_pan(text: &str) -> PanResult {
    let mut r = PanResult::default();
    let number = |s: &str| -> u64 {
        s.trim()
            .split(|c: char| !c.is_ascii_digit() && c != 'e' && c != '+' && c != '.')
            .next()
            .and_then(|t| t.parse::<f64>().ok())
            .map_or(0, |f| f as u64)
    };
    for line in text.lines() {
        let t = line.trim();
        // Progress lines of an unfinished search: `Depth=  5279 States=  7e+06 ...`.
        if let Some(rest) = t.strip_prefix("Depth=") {
            let mut words = rest.split_whitespace();
            let depth = words.next().map_or(0, number);
            r.depth = r.depth.max(depth);
            if let (Some("States="), Some(states)) = (words.next(), words.next()) {
                r.states = r.states.max(number(states));
            }
            continue;
        }
        if let Some(rest) = t.strip_prefix("State-vector") {
            r.reported = true;
            if let Some(d) = rest.split("depth reached").nth(1) {
                r.depth = number(d.trim_start());
            }
            if let Some(e) = rest.split("errors:").nth(1) {
                r.errors = number(e.trim_start());
            }
        } else if t.contains("states, stored") {
            r.states = number(t);
        } else if t.ends_with("transitions (= stored+matched)") {
            r.transitions = number(t);
        } else if let Some(rest) = t.strip_prefix("pan: elapsed time") {
            r.seconds = rest
                .split_whitespace()
                .next()
                .and_then(|s| s.parse().ok())
                .unwrap_or(0.0);
        } else if t.ends_with("total actual memory usage") {
            r.memory_mb = t
                .split_whitespace()
                .next()
                .and_then(|s| s.parse().ok())
                .unwrap_or(0.0);
        } else if t.contains("out of memory") || t.contains("reached -DMEMLIM bound") {
            r.out_of_memory = true;
        } else if t.contains("max search depth too small") {
            r.depth_limited = true;
        } else if r.error_line.is_none()
            && t.starts_with("pan:")
            && (t.contains("assertion violated") || t.contains("acceptance cycle"))
        {
            r.error_line = Some(t.to_string());
        }
    }
    r
}

/// Replays the counterexample of the last run (`model.pml.trail`) and returns what the model
/// printed (its `@` events and spin's cycle marker).
pub fn replay_trail(dir: &Path, check: Check) -> Result<String, VerifyError> {
    let mut spin = Command::new("spin");
    if check == Check::Liveness {
        spin.arg("-DLIVENESS");
    }
    spin.args(["-T", "-t", "-k", "model.pml.trail", "model.pml"]);
    let output = spin
        .current_dir(dir)
        .output()
        .map_err(|e| tool_failure(Tool::Replay, &format!("cannot run it: {e}")))?;
    if !output.status.success() {
        return Err(tool_failure(
            Tool::Replay,
            &String::from_utf8_lossy(&output.stderr),
        ));
    }
    Ok(String::from_utf8_lossy(&output.stdout).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn internal(failure: &VerifyError) -> &str {
        match failure {
            VerifyError::Internal(m) => m,
            other => panic!("not an internal failure: {other:?}"),
        }
    }

    #[test]
    fn spin_rejecting_the_model_is_an_internal_failure_with_its_reason() {
        let log = "ltl finishes: <> ([] ((g_state[0]==254)))\nspin: model.pml:145, Error: d_step sequence too long\n";
        let failure = tool_failure(Tool::Spin, log);
        let message = internal(&failure);
        assert!(message.starts_with("spin rejected the generated model:"));
        assert!(message.contains("model.pml:145, Error: d_step sequence too long"));
        assert!(!message.contains("ltl finishes"), "{message}");
        assert!(message.contains("please report it"));
    }

    #[test]
    fn the_compiler_failing_and_pan_stopping_are_internal_failures() {
        let cc = "pan.c: In function 'main':\npan.c:12:5: error: expected ';' before '}' token\n";
        let message = internal(&tool_failure(Tool::Compiler, cc)).to_string();
        assert!(message.contains("the C compiler failed on spin's verifier"));
        assert!(message.contains("pan.c:12:5: error: expected ';'"));
        let pan = "pan: error, VECTORSZ too small, recompile pan.c with -DVECTORSZ=N\n";
        let message = internal(&tool_failure(Tool::Pan, pan)).to_string();
        assert!(message.contains("pan) stopped without a result"));
        assert!(message.contains("VECTORSZ too small"));
        let silent = internal(&tool_failure(Tool::Replay, "")).to_string();
        assert!(silent.contains("(no output)"));
    }

    #[test]
    fn the_fairness_bound_passes_pans_own_check() {
        for processes in [0, 1, 5, 13, 64, MOST_PROCESSES] {
            let nfair = fairness_bound(processes);
            // `init` and the never claim are processes too.
            assert!(8 * nfair / 2 - 2 > processes + 2, "{processes}: {nfair}");
        }
    }

    #[test]
    fn limits_met_by_pan_are_an_incomplete_search_not_a_failure() {
        let oom = "pan: out of memory\n\thint: to reduce memory, recompile with\nState-vector 476 byte, depth reached 91, errors: 0\n";
        let r = parse_pan(oom);
        assert!(r.out_of_memory && !r.complete() && r.errors == 0);
        let memlim = "pan: reached -DMEMLIM bound\n\t1.0737e+09 bytes used\n";
        let r = parse_pan(memlim);
        assert!(r.out_of_memory && !r.reported);
        let depth = "error: max search depth too small\nState-vector 476 byte, depth reached 99, errors: 0\n     3949 states, stored\n";
        let r = parse_pan(depth);
        assert!(r.depth_limited && r.reported && !r.complete());
        assert_eq!((r.states, r.depth), (3949, 99));
    }

    #[test]
    fn a_violation_is_read_with_its_first_line() {
        let text = "pan:1: assertion violated 0 (at depth 69)\npan: wrote model.pml.trail\nState-vector 476 byte, depth reached 69, errors: 1\n     3949 states, stored\n";
        let r = parse_pan(text);
        assert_eq!(r.errors, 1);
        assert_eq!(
            r.error_line.as_deref(),
            Some("pan:1: assertion violated 0 (at depth 69)")
        );
    }

    #[test]
    fn progress_lines_of_a_running_search_give_its_figures() {
        let text = "Depth=    5279 States=    1e+06 Transitions= 3.2e+06 Memory=   200.1\nDepth=    6011 States=    2e+06 Transitions= 6.5e+06 Memory=   380.4\n";
        let r = parse_pan(text);
        assert_eq!((r.states, r.depth, r.reported), (2_000_000, 6011, false));
    }

    /// A real spin run on a model past spin's limit on a `d_step`'s jumps (2048): the
    /// rejection is an internal failure naming spin's reason.
    #[test]
    fn a_model_spin_rejects_is_reported_as_an_internal_failure() {
        let dir = std::env::temp_dir().join(format!("dynarole-spin-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a scratch directory");
        let branches = "    if :: x > 0 -> x-- :: else -> x++ fi;\n".repeat(1500);
        let model = format!(
            "byte x;\nactive proctype p() {{\n    d_step {{\n{branches}    skip\n    }}\n}}\n"
        );
        std::fs::write(dir.join("model.pml"), model).expect("the model written");
        let limits = Limits {
            memory_mb: 64,
            time_s: 10,
            bitstate: false,
            shortest: false,
            depth: None,
        };
        let outcome = run_check(&dir, Check::Safety, limits, "test");
        let _ = std::fs::remove_dir_all(&dir);
        let failure = outcome.expect_err("spin rejects the model");
        let message = internal(&failure);
        assert!(
            message.contains("spin rejected the generated model")
                && message.contains("d_step sequence too long"),
            "{message}"
        );
    }
}
