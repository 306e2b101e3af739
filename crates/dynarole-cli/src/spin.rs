//! Running spin on a generated model: generate the verifier (`spin -a`), compile it with a
//! memory limit, run it with a time limit, read its figures, and replay a counterexample.

use crate::load::Failure;
use std::path::Path;
use std::process::{Command, Stdio};
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
}

/// Safety (assertions S1-S3) or liveness (the LTL formula `finishes`, weak fairness).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Check {
    Safety,
    Liveness,
}

/// What one pan run said.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PanResult {
    pub errors: u64,
    pub states: u64,
    pub transitions: u64,
    pub depth: u64,
    pub seconds: f64,
    pub memory_mb: f64,
    pub out_of_memory: bool,
    pub depth_limited: bool,
    pub timed_out: bool,
    pub bitstate: bool,
    /// pan printed its statistics (a search that ran, whatever it found).
    pub reported: bool,
    /// The first line of pan's error report, e.g. `pan:1: assertion violated false (at depth 17)`.
    pub error_line: Option<String>,
}

impl PanResult {
    /// The search covered every reachable state.
    pub fn complete(&self) -> bool {
        !self.out_of_memory && !self.depth_limited && !self.timed_out && !self.bitstate
    }
}

const MAX_DEPTH: &str = "-m1000000";

/// Checks that spin and a C compiler are there; the error says how to install them.
pub fn check_tools() -> Result<(), Failure> {
    let spin = Command::new("spin")
        .arg("-V")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if spin.is_err() {
        return Err(Failure::Input(
            "spin is not installed (it is needed to model-check): install it with `sudo apt-get install spin` (Debian, Ubuntu) or from https://spinroot.com, or run ./scripts/test once, which installs it".into(),
        ));
    }
    let cc = Command::new("cc")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if cc.is_err() {
        return Err(Failure::Input(
            "no C compiler `cc` (spin's verifiers are C programs): install gcc or clang".into(),
        ));
    }
    Ok(())
}

fn run_to_file(cmd: &mut Command, dir: &Path, log: &str, what: &str) -> Result<(), Failure> {
    let out = std::fs::File::create(dir.join(log))
        .map_err(|e| Failure::Input(format!("cannot write in {}: {e}", dir.display())))?;
    let err = out
        .try_clone()
        .map_err(|e| Failure::Input(format!("cannot write in {}: {e}", dir.display())))?;
    let status = cmd
        .current_dir(dir)
        .stdout(out)
        .stderr(err)
        .status()
        .map_err(|e| Failure::Input(format!("cannot run {what}: {e}")))?;
    if !status.success() {
        let text = std::fs::read_to_string(dir.join(log)).unwrap_or_default();
        let tail: Vec<&str> = text.lines().rev().take(15).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        return Err(Failure::Input(format!(
            "{what} failed in {}:\n{}",
            dir.display(),
            tail.join("\n")
        )));
    }
    Ok(())
}

/// Generates, compiles and runs the verifier for `check` on `dir/model.pml`.
pub fn run_check(dir: &Path, check: Check, limits: Limits) -> Result<PanResult, Failure> {
    let mut spin = Command::new("spin");
    if check == Check::Liveness {
        spin.arg("-DLIVENESS");
    }
    spin.args(["-a", "model.pml"]);
    run_to_file(&mut spin, dir, "spin.log", "spin -a")?;
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
            // Weak fairness needs (8 * NFAIR) / 2 - 2 > processes (pan's own check).
            let text = std::fs::read_to_string(dir.join("model.pml")).unwrap_or_default();
            let processes = text.matches("run ").count() + 2;
            cc.arg(format!("-DNFAIR={}", (processes + 3).div_ceil(4) + 1));
        }
    }
    if limits.bitstate {
        cc.arg("-DBITSTATE");
    } else {
        cc.arg("-DCOLLAPSE");
    }
    if limits.shortest && check == Check::Safety {
        cc.arg("-DREACH");
    }
    run_to_file(&mut cc, dir, "cc.log", "cc (spin's verifier)")?;
    let log = std::fs::File::create(dir.join("pan.log"))
        .map_err(|e| Failure::Input(format!("cannot write in {}: {e}", dir.display())))?;
    let log_err = log
        .try_clone()
        .map_err(|e| Failure::Input(format!("cannot write in {}: {e}", dir.display())))?;
    let mut pan = Command::new("./pan");
    pan.arg(MAX_DEPTH);
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
    let started = Instant::now();
    let mut child = pan
        .current_dir(dir)
        .stdout(log)
        .stderr(log_err)
        .spawn()
        .map_err(|e| Failure::Input(format!("cannot run pan: {e}")))?;
    let deadline = Duration::from_secs(limits.time_s);
    let mut timed_out = false;
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) => {
                if started.elapsed() > deadline {
                    let _ = child.kill();
                    let _ = child.wait();
                    timed_out = true;
                    break;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
            Err(e) => return Err(Failure::Input(format!("waiting for pan: {e}"))),
        }
    }
    let text = std::fs::read_to_string(dir.join("pan.log")).unwrap_or_default();
    let mut result = parse_pan(&text);
    if !timed_out && !result.reported && !result.out_of_memory {
        let first: Vec<&str> = text.lines().take(5).collect();
        return Err(Failure::Input(format!(
            "pan stopped without a result in {}:\n{}",
            dir.display(),
            first.join("\n")
        )));
    }
    result.timed_out = timed_out;
    result.bitstate = limits.bitstate;
    if timed_out {
        result.seconds = started.elapsed().as_secs_f64();
    }
    Ok(result)
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
pub fn replay_trail(dir: &Path, check: Check) -> Result<String, Failure> {
    let mut spin = Command::new("spin");
    if check == Check::Liveness {
        spin.arg("-DLIVENESS");
    }
    spin.args(["-T", "-t", "-k", "model.pml.trail", "model.pml"]);
    let output = spin
        .current_dir(dir)
        .stderr(Stdio::null())
        .output()
        .map_err(|e| Failure::Input(format!("cannot run spin -t: {e}")))?;
    Ok(String::from_utf8_lossy(&output.stdout).into_owned())
}
