//! Progress of long commands on stderr (stdout stays deterministic): a bar with rate and time
//! left on a terminal, else one line every few seconds (CI logs), so that no long command is
//! silent. The one place that draws progress bars: `campaign` (through the library's
//! `dynarole_campaign::Progress`), `simulate --repeat` (`simulate/progress.rs`) and `view
//! --video`.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Overrides the interval of the one-line progress (seconds; 0 turns it off).
pub const INTERVAL_VARIABLE: &str = "DYNAROLE_PROGRESS_SECONDS";

/// Seconds between two progress lines when stderr is not a terminal.
const DEFAULT_INTERVAL_S: u64 = 10;

/// How progress is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgressMode {
    /// Nothing.
    Off,
    /// A bar redrawn in place (stderr is a terminal).
    Bar,
    /// One line on stderr every `every`.
    Lines { every: Duration },
}

impl ProgressMode {
    /// A bar when stderr is a terminal, else lines every `DYNAROLE_PROGRESS_SECONDS`
    /// (default 10 s). A value that is not a number of seconds is an error naming it.
    pub fn for_stderr() -> Result<ProgressMode, String> {
        if std::io::stderr().is_terminal() {
            return Ok(ProgressMode::Bar);
        }
        let every = match std::env::var(INTERVAL_VARIABLE) {
            Ok(text) => text
                .trim()
                .parse::<f64>()
                .ok()
                .and_then(|s| Duration::try_from_secs_f64(s).ok())
                .ok_or_else(|| {
                    format!("{INTERVAL_VARIABLE}={text}: expected seconds, 0 or more (0: no progress lines)")
                })?,
            Err(_) => Duration::from_secs(DEFAULT_INTERVAL_S),
        };
        Ok(if every.is_zero() {
            ProgressMode::Off
        } else {
            ProgressMode::Lines { every }
        })
    }
}

/// What a long command has done so far, as its progress shows it.
pub trait Status: Send + Sync {
    /// The line printed every few seconds when stderr is not a terminal.
    fn line(&self) -> String;
    /// Brings the bar up to date (called every `Look::poll`).
    fn update(&self, _bar: &ProgressBar) {}
}

/// How the bar of a command looks and moves.
pub struct Look {
    /// indicatif's template.
    pub template: String,
    pub length: u64,
    /// Redrawn by indicatif every this, so that the elapsed time moves during a long unit of
    /// work.
    pub steady: Option<Duration>,
    /// Brought up to the status every this (`Status::update`), for a count that is only
    /// stored where the work runs.
    pub poll: Option<Duration>,
}

/// The bar, or the lines, of one command: the lines (and the polls of the bar) from a thread
/// rather than a check on each unit done, since one is due even while one long unit runs.
pub struct Shown {
    bar: Option<ProgressBar>,
    /// Dropped to stop the thread.
    stop: Option<Sender<()>>,
    ticker: Option<JoinHandle<()>>,
}

impl Shown {
    /// Starts showing `status` as `mode` says (`look`: its bar).
    pub fn start(mode: ProgressMode, look: Look, status: Arc<dyn Status>) -> Shown {
        let bar = (mode == ProgressMode::Bar).then(|| bar(&look));
        let every = match mode {
            ProgressMode::Off => None,
            ProgressMode::Bar => look.poll,
            ProgressMode::Lines { every } => Some(every),
        };
        let mut shown = Shown {
            bar,
            stop: None,
            ticker: None,
        };
        if let Some(every) = every {
            let (stop, stopped) = channel::<()>();
            let bar = shown.bar.clone();
            shown.stop = Some(stop);
            shown.ticker = Some(std::thread::spawn(move || {
                tick(status.as_ref(), bar.as_ref(), every, &stopped);
            }));
        }
        shown
    }

    /// The bar, when one is shown.
    pub fn bar(&self) -> Option<&ProgressBar> {
        self.bar.as_ref()
    }

    /// Runs `f` (which prints) with the bar out of the way.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        match &self.bar {
            Some(bar) => bar.suspend(f),
            None => f(),
        }
    }

    /// Stops showing progress (the bar is cleared; the lines end with one for the finish).
    pub fn finish(mut self) {
        self.stop_now();
    }

    /// The thread first, so that no poll moves a bar already cleared.
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

impl Drop for Shown {
    fn drop(&mut self) {
        self.stop_now();
    }
}

/// Every `every` until `stopped`: the bar brought up to `status`, or a line. A command that
/// printed lines ends with a last one; one shorter than the interval prints none.
fn tick(status: &dyn Status, bar: Option<&ProgressBar>, every: Duration, stopped: &Receiver<()>) {
    let mut printed = false;
    while let Err(RecvTimeoutError::Timeout) = stopped.recv_timeout(every) {
        match bar {
            Some(bar) => status.update(bar),
            None => {
                eprintln!("{}", status.line());
                printed = true;
            }
        }
    }
    if printed {
        eprintln!("{}", status.line());
    }
}

fn bar(look: &Look) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(look.length), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(&look.template) {
        bar.set_style(style);
    }
    if let Some(every) = look.steady {
        bar.enable_steady_tick(every);
    }
    bar
}

/// Progress of `total` units of work (`what`, e.g. "runs"), counted from any thread.
pub struct Progress {
    shown: Shown,
    count: Arc<Count>,
}

struct Count {
    label: String,
    what: String,
    total: u64,
    /// Units done before this command (a resumed campaign or shard): counted in the share
    /// done, not in the rate.
    before: u64,
    done: AtomicU64,
    started: Instant,
}

impl Progress {
    /// Starts showing progress of `label` (the command) over `total` `what`.
    pub fn start(mode: ProgressMode, label: &str, total: u64, what: &str) -> Progress {
        Progress::resume(mode, label, 0, total, what)
    }

    /// Starts showing progress of `label` over `total` `what` of which `before` were done
    /// earlier (a resumed campaign or shard): the bar and the lines count from there, the rate
    /// and the time left from the units done now.
    pub fn resume(
        mode: ProgressMode,
        label: &str,
        before: u64,
        total: u64,
        what: &str,
    ) -> Progress {
        let count = Arc::new(Count {
            label: label.to_string(),
            what: what.to_string(),
            total,
            before: before.min(total),
            done: AtomicU64::new(0),
            started: Instant::now(),
        });
        let look = Look {
            template: format!(
                "{label}: {{elapsed_precise}} [{{wide_bar}}] {{pos}}/{{len}} {what}, {{per_sec}}, {{eta}} left"
            ),
            length: total,
            steady: Some(Duration::from_secs(1)),
            poll: None,
        };
        let shown = Shown::start(mode, look, Arc::clone(&count) as Arc<dyn Status>);
        if let Some(bar) = shown.bar() {
            bar.set_position(count.before);
            bar.reset_eta();
        }
        Progress { shown, count }
    }

    /// One more unit done.
    pub fn inc(&self) {
        self.count.done.fetch_add(1, Ordering::Relaxed);
        if let Some(bar) = self.shown.bar() {
            bar.inc(1);
        }
    }

    /// Stops showing progress (the bar is cleared; the lines end with one for the finish).
    pub fn finish(self) {
        self.shown.finish();
    }
}

impl Status for Count {
    /// `campaign: 1200 of 198000 runs (0.6 %), 24.1 runs/s, 50 s elapsed, about 2 h 16 min left`
    fn line(&self) -> String {
        let now = self.done.load(Ordering::Relaxed);
        let done = self.before + now;
        let elapsed = self.started.elapsed().as_secs_f64();
        let rate = if elapsed > 0.0 {
            now as f64 / elapsed
        } else {
            0.0
        };
        let percent = if self.total > 0 {
            100.0 * done as f64 / self.total as f64
        } else {
            100.0
        };
        let left = if done >= self.total {
            "all done".to_string()
        } else if rate > 0.0 {
            format!(
                "about {} left",
                duration_text(self.total.saturating_sub(done) as f64 / rate)
            )
        } else {
            "time left not known yet".to_string()
        };
        format!(
            "{}: {done} of {} {} ({percent:.1} %), {rate:.1} {}/s, {} elapsed, {left}",
            self.label,
            self.total,
            self.what,
            self.what,
            duration_text(elapsed)
        )
    }
}

/// A campaign's progress (`dynarole_campaign::Progress`) shown as every long command's is.
pub struct CampaignProgress {
    mode: ProgressMode,
    shown: Option<Progress>,
}

impl CampaignProgress {
    pub fn new(mode: ProgressMode) -> CampaignProgress {
        CampaignProgress { mode, shown: None }
    }
}

impl dynarole_campaign::Progress for CampaignProgress {
    fn started(&mut self, label: &str, before: u64, total: u64, what: &str) {
        self.shown = Some(Progress::resume(self.mode, label, before, total, what));
    }

    fn advanced(&self) {
        if let Some(progress) = &self.shown {
            progress.inc();
        }
    }

    fn finished(&mut self) {
        if let Some(progress) = self.shown.take() {
            progress.finish();
        }
    }
}

/// `42 s`, `3 min 5 s`, `2 h 16 min`.
fn duration_text(seconds: f64) -> String {
    let s = seconds.round().max(0.0) as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {} s", s / 60, s % 60),
        _ => format!("{} h {} min", s / 3600, s % 3600 / 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_read_naturally() {
        assert_eq!(duration_text(42.4), "42 s");
        assert_eq!(duration_text(185.0), "3 min 5 s");
        assert_eq!(duration_text(8160.0), "2 h 16 min");
    }

    #[test]
    fn a_line_gives_count_share_rate_and_time_left() {
        let count = Count {
            label: "campaign".into(),
            what: "runs".into(),
            total: 200,
            before: 0,
            done: AtomicU64::new(50),
            started: Instant::now() - Duration::from_secs(10),
        };
        let line = count.line();
        assert!(
            line.starts_with(
                "campaign: 50 of 200 runs (25.0 %), 5.0 runs/s, 10 s elapsed, about 30 s left"
            ),
            "{line}"
        );
    }

    #[test]
    fn a_resumed_count_starts_from_the_units_done_before() {
        let count = Count {
            label: "shard 3/8".into(),
            what: "runs".into(),
            total: 200,
            before: 100,
            done: AtomicU64::new(20),
            started: Instant::now() - Duration::from_secs(10),
        };
        let line = count.line();
        assert!(
            line.starts_with(
                "shard 3/8: 120 of 200 runs (60.0 %), 2.0 runs/s, 10 s elapsed, about 40 s left"
            ),
            "{line}"
        );
    }
}
