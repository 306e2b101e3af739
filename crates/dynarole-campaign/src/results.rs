//! `runs.csv`: one row per run (its parameters, seed and results), appended and flushed as
//! runs finish, and read back to resume an interrupted campaign.

use crate::files;
use crate::inputs::Fingerprint;
use crate::plan::PlannedRun;
use crate::Error;
use dynarole_sim::Report;
use serde::{Deserialize, Serialize};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::Path;

/// How a run ended: the simulator's own verdict (`dynarole_sim::Outcome`), decided there.
pub use dynarole_sim::Outcome;

/// One line of `runs.csv` (the columns, in order).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    pub run: u64,
    pub axis: String,
    pub value: f64,
    pub protocol: String,
    pub preset: String,
    pub seed: u64,
    pub loss: f64,
    pub dead_link_p: f64,
    pub dead_loss: f64,
    pub reset_interval_ms: Option<u64>,
    pub reset_probability: Option<f64>,
    pub timeout_ms: u64,
    pub outcome: Outcome,
    pub completion_ms: Option<f64>,
    pub end_ms: f64,
    pub statements_done: usize,
    pub packets_sent: u64,
    pub packets_lost: u64,
    pub packets_dropped: u64,
    pub s1: usize,
    pub s2: usize,
    pub s3: usize,
    pub resets: u64,
}

/// The column names, in order.
pub const COLUMNS: [&str; 23] = [
    "run",
    "axis",
    "value",
    "protocol",
    "preset",
    "seed",
    "loss",
    "dead_link_p",
    "dead_loss",
    "reset_interval_ms",
    "reset_probability",
    "timeout_ms",
    "outcome",
    "completion_ms",
    "end_ms",
    "statements_done",
    "packets_sent",
    "packets_lost",
    "packets_dropped",
    "s1",
    "s2",
    "s3",
    "resets",
];

impl Row {
    /// The row of a finished run.
    pub fn new(run: &PlannedRun, preset: &str, timeout_ms: u64, report: &Report) -> Row {
        let mut row = Row::parameters(run, preset, timeout_ms);
        let c = &report.counters;
        row.outcome = Outcome::of(report);
        row.completion_ms = report.completion_ms;
        row.end_ms = report.end_ms;
        row.statements_done = report.statements_done;
        row.packets_sent = c.packets_sent;
        row.packets_lost = c.lost + c.dead;
        row.packets_dropped = c.dropped();
        row.s1 = report.count("S1");
        row.s2 = report.count("S2");
        row.s3 = report.count("S3");
        row.resets = c.resets;
        row
    }

    /// The parameter columns of `run`, with empty results.
    fn parameters(run: &PlannedRun, preset: &str, timeout_ms: u64) -> Row {
        Row {
            run: run.index,
            axis: run.axis.name().into(),
            value: run.value,
            protocol: run.protocol.name().into(),
            preset: preset.into(),
            seed: run.seed,
            loss: run.faults.loss,
            dead_link_p: run.faults.dead_link_p,
            dead_loss: run.faults.dead_loss,
            reset_interval_ms: run.faults.resets.map(|r| r.0),
            reset_probability: run.faults.resets.map(|r| r.1),
            timeout_ms,
            outcome: Outcome::Incomplete,
            completion_ms: None,
            end_ms: 0.0,
            statements_done: 0,
            packets_sent: 0,
            packets_lost: 0,
            packets_dropped: 0,
            s1: 0,
            s2: 0,
            s3: 0,
            resets: 0,
        }
    }

    /// Whether the row's results agree with each other as [`Row::new`] makes them: the times
    /// are finite, positive and in order, the lost packets are among the dropped ones, and
    /// the outcome fits the rest (see [`Row::check_outcome`]). The first field that does not,
    /// and why.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        let times = [
            ("end_ms", Some(self.end_ms)),
            ("completion_ms", self.completion_ms),
        ];
        for (field, time) in times {
            if let Some(t) = time.filter(|t| !t.is_finite() || *t < 0.0) {
                return Err((field, format!("{t} is not a time (finite, 0 or more)")));
            }
        }
        if self.completion_ms.is_some_and(|c| c > self.end_ms) {
            return Err((
                "completion_ms",
                "the end was declared after the run ended".into(),
            ));
        }
        if self.packets_lost > self.packets_dropped {
            return Err((
                "packets_lost",
                format!(
                    "{} packets lost but only {} dropped (the lost are among the dropped)",
                    self.packets_lost, self.packets_dropped
                ),
            ));
        }
        self.check_outcome()
    }

    /// A success has its end declared and no violation, a violation has one, a timeout has
    /// no end time, the other outcomes have one and no violation (`Outcome::of`).
    fn check_outcome(&self) -> Result<(), (&'static str, String)> {
        let outcome = self.outcome.name();
        let counts = [
            ("s1", self.s1, "S1"),
            ("s2", self.s2, "S2"),
            ("s3", self.s3, "S3"),
        ];
        let first = counts.into_iter().find(|c| c.1 > 0);
        let ended = self.completion_ms.is_some();
        match (self.outcome, first) {
            (Outcome::Violation, None) => Err((
                "s1",
                "a run whose outcome is violation has no S1, S2 or S3 violation".into(),
            )),
            (Outcome::Violation, Some(_)) => Ok(()),
            (_, Some((field, n, check))) => Err((
                field,
                format!("a run whose outcome is {outcome} has {n} {check} violations"),
            )),
            (Outcome::Timeout, None) if ended => Err((
                "completion_ms",
                "a run whose outcome is timeout has an end time".into(),
            )),
            (Outcome::Timeout, None) => Ok(()),
            // A stopped module may leave every other one waiting: no end need be declared.
            (Outcome::Stopped, None) => Ok(()),
            (_, None) if !ended => Err((
                "completion_ms",
                format!("a run whose outcome is {outcome} has no end time"),
            )),
            _ => Ok(()),
        }
    }

    /// Whether this recorded row is a result of `run` (same index and parameters).
    pub fn is_result_of(&self, run: &PlannedRun, preset: &str, timeout_ms: u64) -> bool {
        let p = Row::parameters(run, preset, timeout_ms);
        (
            self.run,
            &self.axis,
            self.value,
            &self.protocol,
            &self.preset,
            self.seed,
        ) == (p.run, &p.axis, p.value, &p.protocol, &p.preset, p.seed)
            && (self.loss, self.dead_link_p, self.dead_loss) == (p.loss, p.dead_link_p, p.dead_loss)
            && (
                self.reset_interval_ms,
                self.reset_probability,
                self.timeout_ms,
            ) == (p.reset_interval_ms, p.reset_probability, p.timeout_ms)
    }
}

/// A results file read back: the record of its inputs heading it (shard files), and its rows.
#[derive(Debug, Default)]
pub struct Recorded {
    pub inputs: Option<Fingerprint>,
    pub rows: Vec<Row>,
}

/// Reads the rows already in `path` (none if it does not exist), reading at most `bound`
/// bytes. A last line cut short by an interruption (no final newline) is removed from the
/// file.
pub fn read_existing(path: &Path, bound: u64) -> Result<Recorded, Error> {
    let Some(text) = files::read_bounded(path, bound)? else {
        return Ok(Recorded::default());
    };
    let complete = match text.rfind('\n') {
        Some(end) => &text[..=end],
        None => "",
    };
    if complete.len() != text.len() {
        let file = OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(|e| Error::io(path, e))?;
        file.set_len(complete.len() as u64)
            .map_err(|e| Error::io(path, e))?;
    }
    let (inputs, head) = Fingerprint::parse(complete);
    let body: usize = complete
        .split_inclusive('\n')
        .take(head)
        .map(str::len)
        .sum();
    let rows = parse_rows(&complete[body..], path, head as u64)?;
    Ok(Recorded { inputs, rows })
}

/// The number of complete rows in `path` (0 if it does not exist), reading at most `bound`
/// bytes, without changing the file: another process may be appending to it.
pub fn count_complete(path: &Path, bound: u64) -> Result<u64, Error> {
    let Some(text) = files::read_bounded(path, bound)? else {
        return Ok(0);
    };
    let (_, head) = Fingerprint::parse(&text);
    let lines = text.bytes().filter(|&b| b == b'\n').count() as u64;
    Ok(lines.saturating_sub(head as u64 + 1))
}

/// Writes `preamble` (the record of the inputs, for a shard file), the header and `rows` to
/// `path` through a temporary file renamed into place, so that a reader sees the old file or
/// the whole new one, never a part.
pub fn write_atomically(path: &Path, rows: &[Row], preamble: &str) -> Result<(), Error> {
    let name = path
        .file_name()
        .map_or("results".into(), |n| n.to_string_lossy().into_owned());
    let temp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let fail = |e: csv::Error| Error::Results(format!("{}: {e}", temp.display()));
    let mut file = File::create(&temp).map_err(|e| Error::io(&temp, e))?;
    file.write_all(preamble.as_bytes())
        .map_err(|e| Error::io(&temp, e))?;
    let mut writer = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(file);
    writer.write_record(COLUMNS).map_err(fail)?;
    for row in rows {
        writer.serialize(row).map_err(fail)?;
    }
    writer.flush().map_err(|e| Error::io(&temp, e))?;
    drop(writer);
    std::fs::rename(&temp, path).map_err(|e| Error::io(path, e))
}

/// The rows of `text` (a header, then rows), which starts at line `before + 1` of `path`.
fn parse_rows(text: &str, path: &Path, before: u64) -> Result<Vec<Row>, Error> {
    if text.is_empty() {
        return Ok(Vec::new());
    }
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| Error::Results(format!("{}: {e}", path.display())))?
        .clone();
    if headers.iter().ne(COLUMNS) {
        return Err(Error::Results(format!(
            "{}:{}: the columns are not those of this version of dynarole campaign; \
             write to another directory (-o)",
            path.display(),
            before + 1
        )));
    }
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| Error::Results(format!("{}: {e}", path.display())))?;
        let line = before + record.position().map_or(0, |p| p.line());
        let row: Row = record.deserialize(Some(&headers)).map_err(|e| {
            Error::Results(format!("{}:{line}: {}", path.display(), field_error(&e)))
        })?;
        row.check().map_err(|(field, why)| {
            Error::Results(format!(
                "{}:{line}: field {field}: {why}; the row is not one a run writes",
                path.display()
            ))
        })?;
        rows.push(row);
    }
    Ok(rows)
}

/// A row's deserialisation error, with the column's name rather than its number.
fn field_error(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::Deserialize { err, .. } => {
            let field = err
                .field()
                .and_then(|i| COLUMNS.get(i as usize))
                .map_or(String::new(), |name| format!("field {name}: "));
            format!("{field}{}", err.kind())
        }
        _ => e.to_string(),
    }
}

/// Appends rows to `runs.csv`, flushing each.
pub struct Sink {
    writer: csv::Writer<File>,
}

impl Sink {
    /// Opens `path` for appending; writes `preamble` (the record of the inputs, for a shard
    /// file) and the header when the file is new or empty.
    pub fn open(path: &Path, preamble: &str) -> Result<Sink, Error> {
        let mut file = OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| Error::io(path, e))?;
        let empty = file.metadata().map_err(|e| Error::io(path, e))?.len() == 0;
        if empty {
            let head = format!("{preamble}{}\n", COLUMNS.join(","));
            file.write_all(head.as_bytes())
                .map_err(|e| Error::io(path, e))?;
        }
        let writer = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(file);
        Ok(Sink { writer })
    }

    pub fn write(&mut self, row: &Row) -> Result<(), Error> {
        self.writer
            .serialize(row)
            .and_then(|()| self.writer.flush().map_err(csv::Error::from))
            .map_err(|e| Error::Results(format!("cannot write runs.csv: {e}")))
    }
}
