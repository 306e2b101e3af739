//! Where a run's trace goes as the run makes it: kept in memory for the report
//! (`Run::trace`), written to a file line by line through a buffer (`Outputs::trace`), or
//! both, the same bytes either way; and how much of it a recording may keep. A run writing
//! its trace to a file holds one line at a time, however long it lasts (a run of 10^9 ms at
//! loss 1.0 once needed 5.9 GB for its trace in memory).

use crate::report::trace_header;
use std::io::{self, BufWriter, Write};
use std::sync::atomic::AtomicU64;
use std::sync::Arc;

/// What a run writes besides its report (`Simulator::run_with`).
pub struct Outputs {
    /// The trace file (its header, then one line per event), written as the run goes.
    pub trace: Option<Box<dyn Write>>,
    /// Keep the trace as data for the viewer's recording (`Report::recorded`), up to
    /// `record_limit` lines, and `record_packets` packets (the rest counted).
    pub record: bool,
    /// [`crate::MAX_RECORDED`] unless a caller wants less.
    pub record_limit: usize,
    /// [`crate::RECORDED_PACKETS`], the recording's own figure, unless a caller wants
    /// another.
    pub record_packets: usize,
    /// Set to the simulated time (µs) of each event as the run dispatches it, for a progress
    /// line on another thread.
    pub clock: Option<Arc<AtomicU64>>,
}

impl Default for Outputs {
    fn default() -> Outputs {
        Outputs {
            trace: None,
            record: false,
            record_limit: crate::recorded::MAX_RECORDED,
            record_packets: crate::recorded::RECORDED_PACKETS,
            clock: None,
        }
    }
}

/// The trace being written.
pub struct Trace {
    /// The lines kept for the report.
    memory: Option<String>,
    /// The file being written, until its first error.
    stream: Option<BufWriter<Box<dyn Write>>>,
    error: Option<io::Error>,
    /// The line being formatted (one allocation for the whole run).
    pub line: String,
}

impl Trace {
    /// A trace kept in memory (`keep`) and/or written to `stream` (its header first).
    pub fn new(keep: bool, stream: Option<Box<dyn Write>>) -> Option<Trace> {
        if !keep && stream.is_none() {
            return None;
        }
        let mut trace = Trace {
            memory: keep.then(String::new),
            stream: stream.map(BufWriter::new),
            error: None,
            line: String::new(),
        };
        // The file starts as `Report::trace_file` does; the memory keeps the lines only.
        trace.write(trace_header().as_bytes());
        Some(trace)
    }

    /// Whether the lines are kept in memory.
    pub fn keeps(&self) -> bool {
        self.memory.is_some()
    }

    /// Ends `line` (trailing spaces removed, as the columns pad them) and passes it on.
    pub fn end_line(&mut self) {
        self.line.truncate(self.line.trim_end_matches(' ').len());
        self.line.push('\n');
        if let Some(memory) = &mut self.memory {
            memory.push_str(&self.line);
        }
        let line = std::mem::take(&mut self.line);
        self.write(line.as_bytes());
        self.line = line;
        self.line.clear();
    }

    /// Bytes to the file; after an error nothing more is written (the error is reported at
    /// the end of the run).
    fn write(&mut self, bytes: &[u8]) {
        if let Some(stream) = &mut self.stream {
            if let Err(e) = stream.write_all(bytes) {
                self.error = Some(e);
                self.stream = None;
            }
        }
    }

    /// Writes what is buffered to the file and closes it; the first error writing it, if
    /// any. The lines kept in memory stay.
    pub fn flush(&mut self) -> io::Result<()> {
        let flushed = match self.stream.take() {
            Some(mut stream) => stream.flush(),
            None => Ok(()),
        };
        self.error.take().map_or(flushed, Err)
    }

    /// The lines kept in memory (without the header, which `Report::trace_file` adds).
    pub fn into_lines(self) -> Option<String> {
        self.memory
    }
}
