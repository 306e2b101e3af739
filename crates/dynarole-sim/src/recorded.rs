//! The trace kept as data when a run is traced (below the state that fills it, the report
//! that carries it and `record.rs`, which makes the viewer's recording of it).

/// One trace line as data (time in microseconds).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Row {
    pub time_us: u64,
    pub module: Option<usize>,
    pub event: String,
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

/// What a traced run keeps for its recording.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recorded {
    pub rows: Vec<Row>,
    pub packets: Vec<PacketRow>,
}

impl Recorded {
    pub fn row(
        &mut self,
        time_us: u64,
        module: Option<usize>,
        event: &str,
        state: &str,
        detail: &str,
    ) {
        self.rows.push(Row {
            time_us,
            module,
            event: event.into(),
            state: state.into(),
            detail: detail.into(),
        });
    }
}
