//! `simulate`'s progress on stderr, in simulated time: how far the run in progress has come
//! toward its timeout, so that no long run is silent (a bar on a terminal, else a line every
//! `DYNAROLE_PROGRESS_SECONDS`, as every long command shows progress; stdout stays the
//! report's).

use dynarole_campaign::ProgressMode;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How often the bar is brought up to the simulator's clock.
const BAR_TICK: Duration = Duration::from_millis(200);

/// Progress of `runs` runs of at most `timeout_ms` simulated milliseconds each.
pub struct RunProgress {
    shared: Arc<Shared>,
    bar: Option<ProgressBar>,
    stop: Option<Sender<()>>,
    ticker: Option<JoinHandle<()>>,
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
        let bar = (mode == ProgressMode::Bar).then(|| bar(timeout_ms / 1000));
        let every = match mode {
            ProgressMode::Off => None,
            ProgressMode::Bar => Some(BAR_TICK),
            ProgressMode::Lines { every } => Some(every),
        };
        let mut progress = RunProgress {
            shared,
            bar,
            stop: None,
            ticker: None,
        };
        if let Some(every) = every {
            let (stop, stopped) = channel::<()>();
            let shared = Arc::clone(&progress.shared);
            let bar = progress.bar.clone();
            progress.stop = Some(stop);
            progress.ticker = Some(std::thread::spawn(move || {
                tick(&shared, bar.as_ref(), every, &stopped);
            }));
        }
        progress
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
        match &self.bar {
            Some(bar) => bar.suspend(f),
            None => f(),
        }
    }

    /// Stops showing progress (the bar is cleared; lines end with one for the finish).
    pub fn finish(mut self) {
        self.stop_now();
    }

    fn stop_now(&mut self) {
        self.stop = None;
        if let Some(ticker) = self.ticker.take() {
            let _ = ticker.join();
        }
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl Drop for RunProgress {
    fn drop(&mut self) {
        self.stop_now();
    }
}

impl Shared {
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
}

/// Every `every` until `stopped`: the bar moved to the clock, or a line (a thread rather
/// than a check in the simulator's loop: the simulator only stores its clock). Lines end
/// with one for the finish when any was printed.
fn tick(shared: &Shared, bar: Option<&ProgressBar>, every: Duration, stopped: &Receiver<()>) {
    let mut printed = false;
    while let Err(RecvTimeoutError::Timeout) = stopped.recv_timeout(every) {
        match bar {
            Some(bar) => {
                bar.set_position(shared.clock.load(Ordering::Relaxed) / 1_000_000);
                let run = shared.done.load(Ordering::Relaxed) + 1;
                bar.set_message(format!("run {} of {}", run.min(shared.runs), shared.runs));
            }
            None => {
                eprintln!("{}", shared.line());
                printed = true;
            }
        }
    }
    if printed {
        eprintln!("{}", shared.line());
    }
}

/// A bar of simulated seconds up to the timeout.
fn bar(timeout_s: u64) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(timeout_s.max(1)), ProgressDrawTarget::stderr());
    let template = "simulate: {elapsed_precise} [{wide_bar}] {pos}/{len} simulated s, {msg}";
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar
}
