//! A run's trace written to a file as the run goes (`Simulator::run_with`, `Outputs::trace`):
//! the same bytes as the trace kept in memory, the same report, the first write error
//! reported as such; a recording bounded by its limit, refused past it with an error naming
//! the limit; the clock a progress line reads.

mod common;

use common::*;
use dynarole_codegen::Protocol;
use dynarole_sim::{
    Outputs, RandomResets, Report, Run, Scenario, SimError, Simulator, RECORDED_PACKETS,
};
use std::io::{self, Write};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// A writer that hands its bytes to a shared buffer (the test reads them after the run).
#[derive(Clone, Default)]
struct Shared(Arc<Mutex<Vec<u8>>>);

impl Write for Shared {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.0
            .lock()
            .expect("not poisoned")
            .extend_from_slice(bytes);
        Ok(bytes.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// A disk that fills up after `room` bytes.
struct Full {
    room: usize,
}

impl Write for Full {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        if bytes.len() > self.room {
            return Err(io::Error::other("no space left"));
        }
        self.room -= bytes.len();
        Ok(bytes.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// Lossy, with random resets: re-issues, retries and violations in the trace.
fn faulty() -> Scenario {
    let mut scenario = Scenario::default();
    scenario.network.loss = 0.3;
    scenario.random_resets = Some(RandomResets {
        interval_ms: 1000,
        probability: 0.1,
    });
    scenario.faults_until_ms = Some(60_000);
    scenario
}

fn run_with(
    sim: &Simulator,
    scenario: &Scenario,
    keep: bool,
    outputs: Outputs,
) -> Result<Report, SimError> {
    let start = config(EIGHT);
    let expect = config(CAR);
    sim.run_with(
        &Run {
            start: &start,
            expect: Some(&expect),
            scenario,
            seed: 11,
            trace: keep,
        },
        outputs,
    )
}

#[test]
fn a_streamed_trace_is_the_trace_kept_in_memory() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let scenario = faulty();
    let kept = run_with(&sim, &scenario, true, Outputs::default()).expect("runs");
    let file = Shared::default();
    let outputs = Outputs {
        trace: Some(Box::new(file.clone())),
        ..Outputs::default()
    };
    let streamed = run_with(&sim, &scenario, false, outputs).expect("runs");
    let written = String::from_utf8(file.0.lock().expect("not poisoned").clone()).expect("text");
    let expected = kept.trace_file().expect("kept");
    assert!(expected.lines().count() > 100, "{expected}");
    assert_eq!(written, expected);
    assert_eq!(streamed.trace, None, "nothing kept in memory");
    assert_eq!(streamed.recorded, None, "nothing recorded");
    let report = Report {
        trace: None,
        recorded: None,
        ..kept.clone()
    };
    assert_eq!(streamed, report, "the same run");
}

#[test]
fn a_recording_beside_a_streamed_trace_is_the_one_kept_with_it() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let scenario = faulty();
    let kept = run_with(&sim, &scenario, true, Outputs::default()).expect("runs");
    let file = Shared::default();
    let outputs = Outputs {
        trace: Some(Box::new(file.clone())),
        record: true,
        ..Outputs::default()
    };
    let both = run_with(&sim, &scenario, false, outputs).expect("runs");
    assert_eq!(both.recorded, kept.recorded);
    let written = String::from_utf8(file.0.lock().expect("not poisoned").clone()).expect("text");
    assert_eq!(Some(written), kept.trace_file());
}

#[test]
fn a_trace_that_cannot_be_written_is_an_error_of_its_own() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let outputs = Outputs {
        trace: Some(Box::new(Full { room: 20_000 })),
        ..Outputs::default()
    };
    let error = run_with(&sim, &Scenario::default(), false, outputs).expect_err("full");
    assert!(matches!(error, SimError::Trace(_)), "{error}");
    assert_eq!(error.to_string(), "cannot write the trace: no space left");
}

#[test]
fn a_run_longer_than_the_recording_limit_is_refused_naming_it() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let outputs = Outputs {
        record: true,
        record_limit: 100,
        ..Outputs::default()
    };
    let start = config(EIGHT);
    let run = Run {
        start: &start,
        expect: None,
        scenario: &faulty(),
        seed: 11,
        trace: false,
    };
    let report = sim.run_with(&run, outputs).expect("runs");
    let recorded = report.recorded.as_ref().expect("recorded");
    assert_eq!(recorded.rows.len(), 100, "kept up to the limit, no further");
    assert!(recorded.full_at_us.is_some());
    let error = sim
        .recording(&run, &report, "long", None)
        .expect_err("refused");
    let message = error.to_string();
    assert!(matches!(error, SimError::Input(_)), "{message}");
    assert!(message.contains("at most 100 trace lines"), "{message}");
    assert!(message.contains("--trace"), "{message}");
}

#[test]
fn the_clock_follows_the_run() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let clock = Arc::new(AtomicU64::new(0));
    let outputs = Outputs {
        clock: Some(Arc::clone(&clock)),
        ..Outputs::default()
    };
    let report = run_with(&sim, &Scenario::default(), false, outputs).expect("runs");
    assert!(report.success, "{}", report.summary());
    let last_event_ms = clock.load(Ordering::Relaxed) as f64 / 1000.0;
    assert_eq!(last_event_ms, report.end_ms);
}

/// Packets past the recording's own limit are counted, not kept, and the recording is the
/// one made from all of them (a run at loss 1.0 for 10,000 simulated seconds: about 230,000).
#[test]
fn packets_past_the_recordings_limit_are_counted_and_the_recording_is_the_same() {
    let sim = simulator(EIGHT2CAR, &["eight2car"], Protocol::Lattice);
    let start = config(EIGHT);
    let mut scenario = Scenario::default();
    scenario.network.loss = 1.0;
    scenario.timeout_ms = 10_000_000;
    let run = Run {
        start: &start,
        expect: None,
        scenario: &scenario,
        seed: 3,
        trace: false,
    };
    let recording = |packets: usize| {
        let outputs = Outputs {
            record: true,
            record_packets: packets,
            ..Outputs::default()
        };
        let report = sim.run_with(&run, outputs).expect("runs");
        let kept = report.recorded.as_ref().expect("recorded");
        let counts = (kept.packets.len(), kept.omitted_packets);
        let recording = sim.recording(&run, &report, "lost", None).expect("records");
        (
            serde_json::to_string(&recording).expect("serialises"),
            counts,
        )
    };
    let (bounded, (kept, omitted)) = recording(RECORDED_PACKETS);
    let (all, (every, none)) = recording(usize::MAX);
    assert_eq!(kept, RECORDED_PACKETS);
    assert!(omitted > 0 && none == 0 && every == kept + omitted as usize);
    assert!(bounded == all, "the same recording");
}
