//! The recording's serde types: the schema documented in `docs/viewer.md`.

use crate::trace_event::{unknown_event, TraceEvent, MARKS};
use dynarole_world::{Drawing, Leg};
use serde::{Deserialize, Serialize};

/// Version of the format; a reader refuses any other.
pub const FORMAT_VERSION: u32 = 3;

/// Everything the viewer shows of one run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Recording {
    pub format: u32,
    /// `simulation`, `replay` or `counterexample`.
    pub kind: String,
    pub title: String,
    /// The robot kind's plugin name.
    pub robot: String,
    /// How the robot's modules look, part by part (`dynarole_world::Drawing`): what the viewer
    /// draws the poses' parts with.
    pub drawing: Drawing,
    /// The start configuration, in the data-file JSON format.
    pub start: serde_json::Value,
    pub modules: Vec<ModuleInfo>,
    /// Per connector number: whether it is male and which part it sits on.
    pub connectors: Vec<ConnectorInfo>,
    pub statements: Vec<StatementInfo>,
    /// The sequence's source text, for the statement highlight.
    pub source: Option<SourceText>,
    pub end_ms: f64,
    pub keyframe_interval_ms: f64,
    pub keyframes: Vec<Keyframe>,
    pub events: Vec<Event>,
    pub motions: Vec<Motion>,
    pub packets: Vec<PacketArc>,
    /// Faults and violations to mark on the timeline.
    pub markers: Vec<Marker>,
    /// The run's summary lines (verdict, figures).
    pub summary: Vec<String>,
    /// Packets beyond `builder::MAX_PACKETS`, counted and not kept.
    #[serde(default)]
    pub omitted_packets: u64,
    /// Trace lines of dropped packets beyond `builder::MAX_PACKET_EVENTS`, counted and not kept.
    #[serde(default)]
    pub omitted_packet_events: u64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModuleInfo {
    pub name: String,
    pub id: Option<u32>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ConnectorInfo {
    pub male: bool,
    pub part: u8,
}

/// A statement of the sequence and where it is written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StatementInfo {
    pub text: String,
    /// Byte range in the source text.
    pub start: usize,
    pub end: usize,
    /// 1-based line of its first byte.
    pub line: usize,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SourceText {
    pub name: String,
    pub text: String,
}

/// Where a module is: its centre (the mean of its parts' centres), its rigid parts in the
/// robot's part order (each with the direction its up axis points) and every connector's
/// face, in the robot's drawing unit (`dynarole_world::ModulePose`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    pub centre: [f64; 3],
    pub parts: Vec<Part>,
    pub connectors: Vec<[f64; 3]>,
}

/// One rigid part of a module, placed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Part {
    pub centre: [f64; 3],
    pub up: [f64; 3],
}

/// Two connectors held together: `[module, connector, module, connector]` (module indices).
pub type LatchLink = [usize; 4];

/// The settled world at a time: every module's pose and the latches.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Keyframe {
    pub time_ms: f64,
    pub poses: Vec<Pose>,
    pub latches: Vec<LatchLink>,
}

/// One line of the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Event {
    pub time_ms: f64,
    /// Module index (`None`: the whole run, e.g. `timeout`).
    pub module: Option<usize>,
    /// A [`TraceEvent`]'s name (`Recording::check` refuses any other word).
    pub event: String,
    /// The module's protocol state as its runtime describes it (`-`: none).
    pub state: String,
    pub detail: String,
    /// The statement the event concerns, if any.
    pub statement: Option<usize>,
}

/// One operation as the world performed it (or refused it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    pub statement: usize,
    pub module: usize,
    pub start_ms: f64,
    pub end_ms: f64,
    /// `done`, `refused`, `failed`, `interrupt` or `running` (the run stopped first).
    pub outcome: String,
    /// How the operation moves what it carries, as the world model planned it when it
    /// started (`None`: it moves nothing the drawing shows, a latch).
    pub path: Option<Path>,
    /// Latches made and released when the operation completed.
    pub latched: Vec<LatchLink>,
    pub released: Vec<LatchLink>,
    /// Poses of the modules the operation moved, once done (module index, pose).
    pub after: Vec<(usize, Pose)>,
}

/// A running operation's motion (`dynarole_world::Motion`): its legs, done one after another
/// over equal shares of the operation's time, the modules it carries whole, and the single
/// parts (`[module, part]`) it carries while the rest of their module stays.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Path {
    pub legs: Vec<Leg>,
    pub modules: Vec<usize>,
    pub parts: Vec<[usize; 2]>,
}

impl Path {
    /// The angle its rotations turn through in all, in degrees (unsigned).
    pub fn turned_deg(&self) -> f64 {
        self.legs
            .iter()
            .map(|leg| match leg {
                Leg::Rotate { angle_deg, .. } => angle_deg.abs(),
                Leg::Translate { .. } => 0.0,
            })
            .sum()
    }
}

/// A packet between two connectors: delivered or why not.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PacketArc {
    pub start_ms: f64,
    pub end_ms: f64,
    pub from: [usize; 2],
    pub to: [usize; 2],
    /// `delivered`, or the trace's drop event (`lost`, `collision`...).
    pub fate: String,
}

/// A fault or violation on the timeline, with the modules it hit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    pub time_ms: f64,
    pub kind: String,
    pub modules: Vec<usize>,
    pub label: String,
}

impl Recording {
    /// Reads a recording file's text; errors name the line and column, or the version.
    pub fn from_json(text: &str) -> Result<Recording, String> {
        #[derive(Deserialize)]
        struct Header {
            format: u32,
        }
        let header: Header =
            serde_json::from_str(text).map_err(|e| format!("not a recording: {}", located(&e)))?;
        if header.format != FORMAT_VERSION {
            return Err(format!(
                "field `format`: recording format {} is not the supported {FORMAT_VERSION}",
                header.format
            ));
        }
        let recording: Recording = serde_json::from_str(text).map_err(|e| located(&e))?;
        recording.check()?;
        Ok(recording)
    }

    /// The indices the viewer follows all point at something.
    fn check(&self) -> Result<(), String> {
        let n = self.modules.len();
        let c = self.connectors.len();
        let parts = self.drawing.parts.len();
        if self.connectors.iter().any(|k| usize::from(k.part) >= parts) {
            return Err(format!(
                "field `connectors`: a connector on a part the drawing lacks ({parts} parts)"
            ));
        }
        if self.keyframes.is_empty() {
            return Err("field `keyframes`: a recording needs at least one keyframe".into());
        }
        for (k, frame) in self.keyframes.iter().enumerate() {
            let fits = |p: &Pose| p.connectors.len() == c && p.parts.len() == parts;
            if frame.poses.len() != n || !frame.poses.iter().all(fits) {
                return Err(format!(
                    "field `keyframes[{k}].poses`: expected {n} modules with {parts} parts and \
                     {c} connectors each"
                ));
            }
            check_latches(&frame.latches, n, c, &format!("keyframes[{k}].latches"))?;
        }
        for (k, m) in self.motions.iter().enumerate() {
            let bad_path = m.path.as_ref().is_some_and(|path| {
                path.modules.iter().any(|i| *i >= n)
                    || path.parts.iter().any(|[i, part]| *i >= n || *part >= parts)
            });
            if m.module >= n
                || bad_path
                || m.after
                    .iter()
                    .any(|(i, p)| *i >= n || p.connectors.len() != c || p.parts.len() != parts)
            {
                return Err(format!(
                    "field `motions[{k}]`: a module or part out of range"
                ));
            }
            check_latches(&m.latched, n, c, &format!("motions[{k}].latched"))?;
            check_latches(&m.released, n, c, &format!("motions[{k}].released"))?;
        }
        for (k, p) in self.packets.iter().enumerate() {
            if p.from[0] >= n || p.to[0] >= n || p.from[1] >= c || p.to[1] >= c {
                return Err(format!(
                    "field `packets[{k}]`: a module or connector out of range"
                ));
            }
        }
        if self.events.iter().any(|e| e.module.is_some_and(|m| m >= n))
            || self
                .markers
                .iter()
                .any(|m| m.modules.iter().any(|i| *i >= n))
        {
            return Err("field `events` or `markers`: a module out of range".into());
        }
        self.check_statements()?;
        self.check_times()?;
        self.check_words()
    }

    /// Every event is one of the vocabulary's and every marker one of its kinds: the page
    /// colours and explains them from that table.
    fn check_words(&self) -> Result<(), String> {
        let unknown = |e: &Event| TraceEvent::parse(&e.event).is_none();
        if let Some(k) = self.events.iter().position(unknown) {
            return Err(unknown_event(
                &format!("events[{k}].event"),
                &self.events[k].event,
            ));
        }
        let unmarked = |m: &Marker| MARKS.iter().all(|x| x.name != m.kind);
        match self.markers.iter().position(unmarked) {
            Some(k) => {
                let kinds: Vec<&str> = MARKS.iter().map(|x| x.name).collect();
                Err(format!(
                    "field `markers[{k}].kind`: `{}` is not a marker kind (one of {})",
                    self.markers[k].kind,
                    kinds.join(", ")
                ))
            }
            None => Ok(()),
        }
    }

    /// Every statement index points at a statement, and every statement at its source text
    /// (the page highlights it there: an index out of range once stopped the page).
    fn check_statements(&self) -> Result<(), String> {
        let n = self.statements.len();
        if let Some(k) = self.motions.iter().position(|m| m.statement >= n) {
            return Err(format!(
                "field `motions[{k}].statement`: {} is not one of the {n} statements",
                self.motions[k].statement
            ));
        }
        let bad_event = |e: &Event| e.statement.is_some_and(|s| s >= n);
        if let Some(k) = self.events.iter().position(bad_event) {
            return Err(format!(
                "field `events[{k}].statement`: not one of the {n} statements"
            ));
        }
        let Some(source) = &self.source else {
            return Ok(());
        };
        let text = &source.text;
        let outside = |s: &StatementInfo| {
            s.start > s.end
                || s.end > text.len()
                || !text.is_char_boundary(s.start)
                || !text.is_char_boundary(s.end)
                || s.line == 0
        };
        match self.statements.iter().position(outside) {
            Some(k) => Err(format!(
                "field `statements[{k}]`: its byte range or line is not within `source.text`"
            )),
            None => Ok(()),
        }
    }

    /// Times are finite, keyframes in order, and every motion ends no earlier than it starts.
    fn check_times(&self) -> Result<(), String> {
        if !(self.end_ms.is_finite() && self.end_ms >= 0.0) {
            return Err("field `end_ms`: expected a time of 0 or more".into());
        }
        let times = self.keyframes.iter().map(|k| k.time_ms);
        let mut previous = f64::NEG_INFINITY;
        for (k, t) in times.enumerate() {
            if !t.is_finite() || t < previous {
                return Err(format!(
                    "field `keyframes[{k}].time_ms`: expected a finite time, not before the \
                     keyframe before it"
                ));
            }
            previous = t;
        }
        let bad = |m: &Motion| {
            !(m.start_ms.is_finite() && m.end_ms.is_finite() && m.start_ms <= m.end_ms)
        };
        match self.motions.iter().position(bad) {
            Some(k) => Err(format!(
                "field `motions[{k}]`: expected finite times with `start_ms` <= `end_ms`"
            )),
            None => Ok(()),
        }
    }
}

/// `line 3, column 14: missing field `robot``: the position first, said once.
fn located(e: &serde_json::Error) -> String {
    let message = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    let what = message.strip_suffix(&suffix).unwrap_or(&message);
    format!("line {}, column {}: {what}", e.line(), e.column())
}

fn check_latches(latches: &[LatchLink], n: usize, c: usize, field: &str) -> Result<(), String> {
    if latches
        .iter()
        .any(|l| l[0] >= n || l[2] >= n || l[1] >= c || l[3] >= c)
    {
        return Err(format!(
            "field `{field}`: a module or connector out of range"
        ));
    }
    Ok(())
}
