//! What a traced run notes for its recording (`recorded.rs` holds it), and the viewer's
//! recording built from it (`dynarole_recording::Builder` replays the operations on the world
//! model).

use crate::recorded::PacketRow;
use crate::report::Report;
use crate::state::State;
use crate::{Run, SimError, Simulator};
use dynarole_recording::{Builder, PacketArc, Recording, Source};

impl State {
    /// Notes a packet's fate for the recording (traced runs only).
    pub fn record_packet(&mut self, packet: &crate::packet::Packet, fate: &'static str) {
        if !self.record {
            return;
        }
        let row = PacketRow {
            start_us: packet.start,
            end_us: packet.end,
            from: [packet.from().module, usize::from(packet.from().connector)],
            to: [packet.to().module, usize::from(packet.to().connector)],
            fate,
        };
        self.recorded.packet(row);
    }
}

/// Why a run is not recorded: it passed the recording's limit at `at_us`.
fn too_long(limit: usize, at_us: u64) -> String {
    format!(
        "the run is too long to record: --record and --html keep at most {limit} trace lines, and this run passed that at {:.3} s of simulated time; record a shorter run (a smaller `timeout_ms` in the scenario) or write the trace with --trace, which has no limit",
        ms(at_us) / 1000.0
    )
}

fn ms(us: u64) -> f64 {
    us as f64 / 1000.0
}

impl Simulator {
    /// The viewer's recording of a traced run (`run.trace` must have been set).
    pub fn recording(
        &self,
        run: &Run,
        report: &Report,
        title: &str,
        source: Option<Source>,
    ) -> Result<Recording, SimError> {
        let recorded = report
            .recorded
            .as_ref()
            .ok_or_else(|| SimError::Input("the run kept no trace to record".into()))?;
        if let Some(at) = recorded.full_at_us {
            return Err(SimError::Input(too_long(recorded.limit, at)));
        }
        let texts: Vec<String> = (0..self.sequence.len())
            .map(|s| self.sequence.text(s).to_string())
            .collect();
        let mut builder = Builder::new(
            "simulation",
            title,
            run.start,
            &self.sequence.robot,
            &self.sequence.resolved,
            &texts,
            source,
        )
        .map_err(SimError::Input)?;
        for row in &recorded.rows {
            builder.event(
                ms(row.time_us),
                row.module,
                row.event,
                &row.state,
                &row.detail,
            );
        }
        let arc = |p: &crate::recorded::PacketRow| PacketArc {
            start_ms: ms(p.start_us),
            end_ms: ms(p.end_us),
            from: p.from,
            to: p.to,
            fate: p.fate.into(),
        };
        for p in &recorded.packets {
            builder.packet(arc(p));
        }
        // The builder keeps as many packets as were kept here and counts the rest: given
        // the count, it writes what it would have written from every packet.
        if let Some(last) = recorded.packets.last() {
            for _ in 0..recorded.omitted_packets {
                builder.packet(arc(last));
            }
        }
        // The replayed world must end where the simulator's did: else the recording would
        // show another run.
        let replayed = builder.configuration().to_json_string();
        let simulated = (report.final_configuration.as_ref())
            .map_or_else(|| "null".to_string(), |c| c.to_json_string());
        if replayed != simulated {
            return Err(SimError::Build(format!(
                "the recording's world ended elsewhere than the simulator's: {replayed} != {simulated}"
            )));
        }
        let summary = report.summary().lines().map(str::to_string).collect();
        Ok(builder.finish(report.end_ms, summary))
    }
}
