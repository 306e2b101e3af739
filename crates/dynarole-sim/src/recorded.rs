//! The trace kept as data when a run is traced (below the state that fills it, the report
//! that carries it and `record.rs`, which makes the viewer's recording of it).

use dynarole_recording::TraceEvent;

/// One trace line as data (time in microseconds).
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub time_us: u64,
    pub module: Option<usize>,
    pub event: TraceEvent,
    pub state: String,
    pub detail: String,
}

/// One packet: (start, end) in microseconds, sender and receiver (module, connector), fate.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PacketRow {
    pub start_us: u64,
    pub end_us: u64,
    pub from: [usize; 2],
    pub to: [usize; 2],
    pub fate: &'static str,
}

/// Trace lines a recording (`--record`, `--html`) keeps at most: the recording holds the
/// whole run until it is written (about 200 B a line here, then the recording's own copy),
/// so a longer run is refused naming this figure rather than exhausting memory. A trace
/// file has no such limit (`Outputs::trace`).
pub const MAX_RECORDED: usize = 1_000_000;

/// Packets kept for a recording: the recording's own `MAX_PACKETS` (dynarole-recording's
/// `builder.rs`), which keeps no more and counts the rest; so are they counted here.
pub const RECORDED_PACKETS: usize = 200_000;

/// What a traced run keeps for its recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Recorded {
    pub rows: Vec<Row>,
    pub packets: Vec<PacketRow>,
    /// Packets after the first `packet_cap`, counted and not kept.
    pub omitted_packets: u64,
    /// When (µs) the run passed `limit` lines: nothing later was kept, and no recording is
    /// made of it.
    pub full_at_us: Option<u64>,
    /// Lines kept at most ([`MAX_RECORDED`] unless a caller asks less).
    pub limit: usize,
    /// Packets kept ([`RECORDED_PACKETS`] unless a caller asks otherwise).
    pub packet_cap: usize,
}

impl Default for Recorded {
    fn default() -> Recorded {
        Recorded::with_limits(MAX_RECORDED, RECORDED_PACKETS)
    }
}

impl Recorded {
    /// An empty recording keeping at most `limit` lines and `packet_cap` packets.
    pub fn with_limits(limit: usize, packet_cap: usize) -> Recorded {
        Recorded {
            rows: Vec::new(),
            packets: Vec::new(),
            omitted_packets: 0,
            full_at_us: None,
            limit,
            packet_cap,
        }
    }

    pub fn row(
        &mut self,
        time_us: u64,
        module: Option<usize>,
        event: TraceEvent,
        state: &str,
        detail: &str,
    ) {
        if self.rows.len() >= self.limit {
            self.full_at_us.get_or_insert(time_us);
        }
        if self.full_at_us.is_some() {
            return;
        }
        self.rows.push(Row {
            time_us,
            module,
            event,
            state: state.into(),
            detail: detail.into(),
        });
    }

    /// Keeps a packet's fate, or counts it past `packet_cap`.
    pub fn packet(&mut self, packet: PacketRow) {
        if self.packets.len() < self.packet_cap {
            self.packets.push(packet);
        } else {
            self.omitted_packets += 1;
        }
    }
}
