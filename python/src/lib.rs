//! The `dynarole._native` extension module: the library API of `dynarole-cli` (`api.rs`) for
//! the Python package in `python/dynarole`. Options cross as the subcommand's argument list
//! (parsed by the command line's own definitions), values as JSON text, failures as
//! `NativeFailure(kind, message, diagnostics)`; the package turns them into its objects.

use dynarole_cli::api::{self, Failure, Progress};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

pyo3::create_exception!(
    _native,
    NativeFailure,
    PyException,
    "A command that could not run: (kind, message, diagnostics as JSON)."
);

/// How often a long call looks at Python's signals and tells its progress.
const POLL: Duration = Duration::from_millis(100);

/// `failure` as the exception the package translates: its kind (the exit code's meaning),
/// the text the command line prints, and a refused file's located diagnostics.
fn raised(failure: Failure) -> PyErr {
    let kind = match &failure {
        Failure::Input(_) | Failure::Toml { .. } => "input",
        Failure::Usage(_) => "usage",
        Failure::Checked { .. } => "checked",
        Failure::Internal(_) => "internal",
    };
    let diagnostics = match &failure {
        Failure::Checked {
            path,
            source,
            diagnostics,
            ..
        } => json_text(&api::locate(path, source, diagnostics)),
        _ => Ok("[]".to_string()),
    };
    match diagnostics {
        Ok(diagnostics) => NativeFailure::new_err((kind, api::failure_text(&failure), diagnostics)),
        Err(e) => e,
    }
}

fn json_text<T: serde::Serialize + ?Sized>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| {
        NativeFailure::new_err(("internal", format!("cannot serialise a result: {e}"), "[]"))
    })
}

/// `dynarole check ARGV`: the diagnostics (warnings) as JSON; errors raise.
#[pyfunction]
fn check(py: Python<'_>, argv: Vec<String>) -> PyResult<String> {
    let found = py.detach(|| api::check(&argv)).map_err(raised)?;
    json_text(&found)
}

/// `dynarole reverse FILE SEQUENCE [--name NAME]`: the text the command prints.
#[pyfunction]
#[pyo3(signature = (path, sequence, name=None, plugins=Vec::new()))]
fn reverse(
    py: Python<'_>,
    path: std::path::PathBuf,
    sequence: String,
    name: Option<String>,
    plugins: Vec<std::path::PathBuf>,
) -> PyResult<String> {
    py.detach(|| api::reverse(&path, &sequence, name.as_deref(), &plugins))
        .map_err(raised)
}

/// `dynarole replay ARGV` as JSON.
#[pyfunction]
fn replay(py: Python<'_>, argv: Vec<String>) -> PyResult<String> {
    let value = py.detach(|| api::replay(&argv)).map_err(raised)?;
    json_text(&value)
}

/// `dynarole parallelise ARGV` as JSON.
#[pyfunction]
fn parallelise(py: Python<'_>, argv: Vec<String>) -> PyResult<String> {
    let value = py.detach(|| api::parallelise(&argv)).map_err(raised)?;
    json_text(&value)
}

/// `dynarole verify ARGV` as JSON. The check runs on a thread of its own while this one looks
/// at Python's signals every 100 ms: Ctrl-C stops spin or pan and raises `KeyboardInterrupt`.
#[pyfunction]
fn verify(py: Python<'_>, argv: Vec<String>) -> PyResult<String> {
    let stop = AtomicBool::new(false);
    let (outcome, stopped) = std::thread::scope(|scope| {
        let check = scope.spawn(|| api::verify_until(&argv, &stop));
        let mut stopped: Option<PyErr> = None;
        loop {
            let finished = py.detach(|| {
                std::thread::sleep(POLL);
                check.is_finished()
            });
            if let (Err(e), None) = (py.check_signals(), &stopped) {
                stop.store(true, Ordering::Relaxed);
                stopped = Some(e);
            }
            if finished {
                break;
            }
        }
        (py.detach(|| check.join()), stopped)
    });
    let outcome = outcome
        .map_err(|_| NativeFailure::new_err(("internal", "the check's thread panicked", "[]")))?;
    match (stopped, outcome) {
        (Some(e), _) => Err(e),
        (None, Err(failure)) => Err(raised(failure)),
        (None, Ok(value)) => json_text(&value),
    }
}

/// The viewer's page of the recording at `path`.
#[pyfunction]
fn view_html(py: Python<'_>, path: std::path::PathBuf) -> PyResult<String> {
    py.detach(|| api::view_html(&path)).map_err(raised)
}

/// `dynarole simulate ARGV --json`: `each(report_json)` after every run, with Python's lock
/// held only then; a signal (Ctrl-C) or an exception in `each` ends the runs and is raised.
#[pyfunction]
fn simulate(py: Python<'_>, argv: Vec<String>, each: Py<PyAny>) -> PyResult<()> {
    let mut stopped: Option<PyErr> = None;
    let outcome = py.detach(|| {
        api::simulate(&argv, &mut |report| {
            Python::attach(|py| {
                let told = py
                    .check_signals()
                    .and_then(|()| each.call1(py, (report.to_string(),)).map(drop));
                told.map_err(|e| {
                    stopped = Some(e);
                    Failure::Internal("the caller stopped the runs".into())
                })
            })
        })
    });
    match (stopped, outcome) {
        (Some(e), _) => Err(e),
        (None, Err(failure)) => Err(raised(failure)),
        (None, Ok(())) => Ok(()),
    }
}

/// A campaign's progress as counters the calling thread reads, and its stop request.
#[derive(Default)]
struct Counted {
    before: AtomicU64,
    done: AtomicU64,
    total: AtomicU64,
    stop: AtomicBool,
}

impl Progress for &Counted {
    fn started(&mut self, _label: &str, before: u64, total: u64, _what: &str) {
        self.before.store(before, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    fn advanced(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }

    fn stop_requested(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// `dynarole campaign ARGV` as JSON. The campaign runs on its own threads; this one calls
/// `progress(done, total)` every 100 ms and looks at Python's signals: Ctrl-C or an exception
/// in `progress` stops the runs (those recorded stay, and the campaign resumes from them).
#[pyfunction]
fn campaign(py: Python<'_>, argv: Vec<String>, progress: Py<PyAny>) -> PyResult<String> {
    let counted = Counted::default();
    let (outcome, stopped) = std::thread::scope(|scope| {
        let runs = scope.spawn(|| api::campaign(&argv, &mut &counted));
        let mut stopped: Option<PyErr> = None;
        loop {
            let finished = py.detach(|| {
                std::thread::sleep(POLL);
                runs.is_finished()
            });
            let done =
                counted.before.load(Ordering::Relaxed) + counted.done.load(Ordering::Relaxed);
            let total = counted.total.load(Ordering::Relaxed);
            let told = py
                .check_signals()
                .and_then(|()| progress.call1(py, (done, total)).map(drop));
            if let (Err(e), None) = (told, &stopped) {
                counted.stop.store(true, Ordering::Relaxed);
                stopped = Some(e);
            }
            if finished {
                break;
            }
        }
        let outcome = py.detach(|| runs.join());
        (outcome, stopped)
    });
    let outcome = outcome.map_err(|_| {
        NativeFailure::new_err(("internal", "the campaign's thread panicked", "[]"))
    })?;
    match (stopped, outcome) {
        (Some(e), _) => Err(e),
        (None, Err(failure)) => Err(raised(failure)),
        (None, Ok(value)) => json_text(&value),
    }
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("NativeFailure", m.py().get_type::<NativeFailure>())?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(reverse, m)?)?;
    m.add_function(wrap_pyfunction!(replay, m)?)?;
    m.add_function(wrap_pyfunction!(parallelise, m)?)?;
    m.add_function(wrap_pyfunction!(verify, m)?)?;
    m.add_function(wrap_pyfunction!(view_html, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(campaign, m)?)?;
    Ok(())
}
