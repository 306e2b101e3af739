//! `simulate`'s progress on stderr, in simulated time: how far the run in progress has come
//! toward its timeout, so that no long run is silent (drawn by `crate::progress`, as every
//! long command's progress is: a bar on a terminal, else a line every
//! `DYNAROLE_PROGRESS_SECONDS`; stdout stays the report's).

use crate::progress::{Look, ProgressMode, Shown, Status};
use indicatif::ProgressBar;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How often the bar is brought up to the simulator's clock.
const BAR_TICK: Duration = Duration::from_millis(200);

/// Progress of `runs` runs of at most `timeout_ms` simulated milliseconds each.
pub struct RunProgress {
    shared: Arc<Shared>,
    shown: Shown,
}

struct Shared {
    /// The simulated time of the run in progress (µs), set by the simulator as it runs
    /// (`dynarole_sim::Outputs::clock`).
    clock: Arc<AtomicU64>,
    /// Runs done.
    done: AtomicU64,
    runs: u64,
    timeout_us: u64,
    started: Instant,
    /// When the run in progress started (ms since `started`), for its speed.
    run_started_ms: AtomicU64,
}

impl RunProgress {
    pub fn start(mode: ProgressMode, runs: u64, timeout_ms: u64) -> RunProgress {
        let shared = Arc::new(Shared {
            clock: Arc::new(AtomicU64::new(0)),
            done: AtomicU64::new(0),
            runs,
            timeout_us: timeout_ms.saturating_mul(1000),
            started: Instant::now(),
            run_started_ms: AtomicU64::new(0),
        });
        // A bar of simulated seconds up to the timeout.
        let look = Look {
            template: "simulate: {elapsed_precise} [{wide_bar}] {pos}/{len} simulated s, {msg}"
                .into(),
            length: (timeout_ms / 1000).max(1),
            steady: None,
            poll: Some(BAR_TICK),
        };
        let shown = Shown::start(mode, look, Arc::clone(&shared) as Arc<dyn Status>);
        RunProgress { shared, shown }
    }

    /// The clock the simulator sets (`dynarole_sim::Outputs::clock`).
    pub fn clock(&self) -> Arc<AtomicU64> {
        Arc::clone(&self.shared.clock)
    }

    /// One run done: the next starts from simulated time 0.
    pub fn run_done(&self) {
        let s = &self.shared;
        s.done.fetch_add(1, Ordering::Relaxed);
        s.clock.store(0, Ordering::Relaxed);
        let now = u64::try_from(s.started.elapsed().as_millis()).unwrap_or(u64::MAX);
        s.run_started_ms.store(now, Ordering::Relaxed);
    }

    /// Runs `f` (which prints) with the bar out of the way.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.shown.suspend(f)
    }

    /// Stops showing progress (the bar is cleared; lines end with one for the finish).
    pub fn finish(self) {
        self.shown.finish();
    }
}

impl Status for Shared {
    /// `simulate: run 1 of 1: 52000.0 of at most 1000000.0 simulated s (5.2 %), 10400 x real
    /// time, 5 s elapsed`
    fn line(&self) -> String {
        let done = self.done.load(Ordering::Relaxed);
        let simulated = self.clock.load(Ordering::Relaxed) as f64 / 1e6;
        let elapsed = self.started.elapsed().as_secs_f64();
        let run_wall = elapsed - self.run_started_ms.load(Ordering::Relaxed) as f64 / 1000.0;
        let speed = if run_wall > 0.0 {
            simulated / run_wall
        } else {
            0.0
        };
        let timeout = self.timeout_us as f64 / 1e6;
        let share = if timeout > 0.0 {
            100.0 * simulated / timeout
        } else {
            100.0
        };
        if done >= self.runs {
            return format!(
                "simulate: {} of {} runs done, {elapsed:.0} s elapsed",
                done, self.runs
            );
        }
        format!(
            "simulate: run {} of {}: {simulated:.1} of at most {timeout:.1} simulated s ({share:.1} %), {speed:.0} x real time, {elapsed:.0} s elapsed",
            done + 1,
            self.runs
        )
    }

    /// The bar moved to the clock (the simulator only stores its clock).
    fn update(&self, bar: &ProgressBar) {
        bar.set_position(self.clock.load(Ordering::Relaxed) / 1_000_000);
        let run = self.done.load(Ordering::Relaxed) + 1;
        bar.set_message(format!("run {} of {}", run.min(self.runs), self.runs));
    }
}
