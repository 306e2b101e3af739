//! Builds a recording from a run's events, replaying its operations on the world model: a
//! motion is what `RobotWorld::motion` says when it starts, an operation's effect
//! what `RobotWorld::apply` does when it completes, exactly as the simulator does them.

use crate::format::{
    ConnectorInfo, Event, Keyframe, LatchLink, Marker, ModuleInfo, Motion, PacketArc, Path, Pose,
    Recording, SourceText, StatementInfo, FORMAT_VERSION,
};
use crate::pose::{latches, poses};
use crate::trace_event::{Mark, Operation, TraceEvent};
use dynarole_core::check::ResolvedStatement;
use dynarole_core::robot::RobotApi;
use dynarole_replay::RobotWorld;
use dynarole_world::{Configuration, View};

/// Keyframes every second of run time in which the world changed: a seek replays at most a
/// second of motions (a keyframe is left out while nothing moves; the last one still holds).
pub const KEYFRAME_INTERVAL_MS: f64 = 1000.0;
/// Packets kept in a recording; the rest are counted (`omitted_packets`), so that the page
/// of a long or large run stays small enough to load.
pub const MAX_PACKETS: usize = 200_000;
/// Trace lines of dropped packets kept (the other trace lines are always kept).
pub const MAX_PACKET_EVENTS: usize = 200_000;

/// The sequence's source file, for the statement highlight.
#[derive(Clone, Copy, Debug)]
pub struct Source<'a> {
    pub name: &'a str,
    pub text: &'a str,
}

/// A recording under construction; feed it the run's events in time order.
pub struct Builder<'r> {
    robot: &'r RobotApi,
    statements: &'r [ResolvedStatement],
    world: RobotWorld,
    /// The configuration the world started from.
    start: Configuration,
    recording: Recording,
    /// Per (event, link) of the faults that strike every packet, the time of its last drop.
    last_link_drop: Vec<(TraceEvent, String, f64)>,
    powered_once: Vec<bool>,
    /// Interval keyframes written so far (some left out), and whether the world changed
    /// since the last one written.
    intervals: usize,
    changed: bool,
    packet_events: usize,
}

impl<'r> Builder<'r> {
    /// `texts` are the statements as executed (one per resolved statement).
    pub fn new(
        kind: &str,
        title: &str,
        start: &Configuration,
        robot: &'r RobotApi,
        statements: &'r [ResolvedStatement],
        texts: &[String],
        source: Option<Source>,
    ) -> Result<Builder<'r>, String> {
        let world = RobotWorld::new(start.clone(), robot)?;
        let view = View::of(start);
        let statements_info = statements
            .iter()
            .zip(texts)
            .map(|(s, text)| statement_info(s, text, source))
            .collect();
        let recording = Recording {
            format: FORMAT_VERSION,
            kind: kind.into(),
            title: title.into(),
            robot: start.kind().name().into(),
            drawing: start.kind().drawing(),
            start: serde_json::from_str(&start.to_json_string())
                .map_err(|e| format!("the start configuration: {e}"))?,
            modules: (0..view.len())
                .map(|m| ModuleInfo {
                    name: view.name(m),
                    id: view.id(m),
                })
                .collect(),
            connectors: (0..view.connectors())
                .map(|c| ConnectorInfo {
                    male: view.is_male(c),
                    part: u8::try_from(view.side(c)).unwrap_or(u8::MAX),
                })
                .collect(),
            statements: statements_info,
            source: source.map(|s| SourceText {
                name: s.name.into(),
                text: s.text.into(),
            }),
            end_ms: 0.0,
            keyframe_interval_ms: KEYFRAME_INTERVAL_MS,
            keyframes: Vec::new(),
            events: Vec::new(),
            motions: Vec::new(),
            packets: Vec::new(),
            markers: Vec::new(),
            summary: Vec::new(),
            omitted_packets: 0,
            omitted_packet_events: 0,
        };
        let n = view.len();
        let mut builder = Builder {
            robot,
            statements,
            world,
            start: start.clone(),
            recording,
            last_link_drop: Vec::new(),
            powered_once: vec![false; n],
            intervals: 0,
            changed: true,
            packet_events: 0,
        };
        builder.keyframes_until(0.0, true);
        Ok(builder)
    }

    /// One trace line. Events that start or end an operation (the vocabulary's
    /// `Operation`) name their statement as `#N` at the start of `detail`.
    pub fn event(
        &mut self,
        time_ms: f64,
        module: Option<usize>,
        event: TraceEvent,
        state: &str,
        detail: &str,
    ) {
        self.keyframes_until(time_ms, false);
        let statement = statement_of(detail).filter(|s| *s < self.statements.len());
        if let (Some(m), Some(s)) = (module, statement) {
            match event.spec().operation {
                Operation::Starts => self.op_start(time_ms, m, s),
                Operation::Ends(_) => self.op_end(time_ms, m, s, event.name()),
                Operation::None => {}
            }
        }
        self.mark(time_ms, module, event, statement, detail);
        if event.spec().dropped_packet {
            if self.packet_events >= MAX_PACKET_EVENTS {
                self.recording.omitted_packet_events += 1;
                return;
            }
            self.packet_events += 1;
        }
        self.recording.events.push(Event {
            time_ms,
            module,
            event: event.name().into(),
            state: state.into(),
            detail: detail.into(),
            statement,
        });
    }

    /// One operation on a model without time (replay, a counterexample's trail): module `m`
    /// does statement `s` from `start_ms` for `duration(s, turn)` milliseconds; the world
    /// performs it or refuses it. Returns when it ends and the world's reason for a refusal.
    pub fn operation(
        &mut self,
        start_ms: f64,
        m: usize,
        s: usize,
        duration: &dyn Fn(usize, Option<&Path>) -> f64,
    ) -> (f64, Option<String>) {
        let label = format!("#{s} {}", self.statement_text(s));
        self.event(start_ms, Some(m), TraceEvent::Start, "-", &label);
        let path = self.last_path();
        let end_ms = start_ms + duration(s, path.as_ref());
        let refusal = self.statements.get(s).and_then(|statement| {
            let mut trial = self.world.clone();
            trial
                .apply(self.robot, statement, &self.module_name(m))
                .err()
        });
        match &refusal {
            None => self.event(end_ms, Some(m), TraceEvent::Done, "-", &label),
            Some(reason) => self.event(
                end_ms,
                Some(m),
                TraceEvent::Refused,
                "-",
                &format!("{label}: {reason}"),
            ),
        }
        (end_ms, refusal)
    }

    /// The path of the operation started last, if it moves something.
    pub fn last_path(&self) -> Option<Path> {
        self.recording.motions.last().and_then(|x| x.path.clone())
    }

    fn statement_text(&self, s: usize) -> String {
        self.recording
            .statements
            .get(s)
            .map_or_else(String::new, |x| x.text.clone())
    }

    /// A packet between two connectors (delivered or dropped).
    pub fn packet(&mut self, arc: PacketArc) {
        if self.recording.packets.len() < MAX_PACKETS {
            self.recording.packets.push(arc);
        } else {
            self.recording.omitted_packets += 1;
        }
    }

    /// The recording, with keyframes up to `end_ms`.
    pub fn finish(mut self, end_ms: f64, summary: Vec<String>) -> Recording {
        self.keyframes_until(end_ms, true);
        self.recording.end_ms = end_ms;
        self.recording.summary = summary;
        self.recording
    }

    /// The world's configuration as the recording has replayed it so far.
    pub fn configuration(&self) -> Configuration {
        // The world was made from a configuration file (`new`), so it always has one; the
        // start stands in only to keep this total.
        self.world
            .configuration()
            .unwrap_or_else(|| self.start.clone())
    }

    fn module_name(&self, m: usize) -> String {
        self.world.view().name(m)
    }

    fn op_start(&mut self, time_ms: f64, m: usize, s: usize) {
        let path = self.path(m, s);
        self.recording.motions.push(Motion {
            statement: s,
            module: m,
            start_ms: time_ms,
            end_ms: time_ms,
            outcome: "running".into(),
            path,
            latched: Vec::new(),
            released: Vec::new(),
            after: Vec::new(),
        });
    }

    /// The path of the operation a statement starts, as the world model plans it (`None` for
    /// one that moves nothing the drawing shows): its legs, and what it carries by index.
    fn path(&self, m: usize, s: usize) -> Option<Path> {
        let statement = self.statements.get(s)?;
        let motion = self
            .world
            .motion(self.robot, statement, &self.module_name(m))?;
        if !motion.moves() {
            return None;
        }
        let view = self.world.view();
        let mut modules = Vec::new();
        let mut parts = Vec::new();
        for carried in &motion.carried {
            let Some(i) = view.index(&carried.module) else {
                continue;
            };
            match carried.part {
                None => modules.push(i),
                Some(part) => parts.push([i, part]),
            }
        }
        modules.sort_unstable();
        modules.dedup();
        parts.sort_unstable();
        parts.dedup();
        Some(Path {
            legs: motion.legs,
            modules,
            parts,
        })
    }

    fn op_end(&mut self, time_ms: f64, m: usize, s: usize, outcome: &str) {
        let Some(index) = self
            .recording
            .motions
            .iter()
            .rposition(|x| x.statement == s && x.module == m && x.outcome == "running")
        else {
            return;
        };
        let (latched, released, after) = if outcome == "done" {
            self.apply(m, s)
        } else {
            (Vec::new(), Vec::new(), Vec::new())
        };
        if let Some(motion) = self.recording.motions.get_mut(index) {
            motion.end_ms = time_ms;
            motion.outcome = outcome.into();
            motion.latched = latched;
            motion.released = released;
            motion.after = after;
        }
    }

    /// Applies statement `s` by module `m` (a joint already at its target changes nothing,
    /// as in the simulator) and returns what changed.
    fn apply(
        &mut self,
        m: usize,
        s: usize,
    ) -> (Vec<LatchLink>, Vec<LatchLink>, Vec<(usize, Pose)>) {
        let Some(statement) = self.statements.get(s) else {
            return (Vec::new(), Vec::new(), Vec::new());
        };
        let before = self.configuration();
        let name = self.module_name(m);
        if self.world.apply(self.robot, statement, &name).is_err() {
            return (Vec::new(), Vec::new(), Vec::new());
        }
        let after = self.configuration();
        self.changed = true;
        let (old, new) = (latches(&before), latches(&after));
        let latched = new.iter().filter(|l| !old.contains(l)).copied().collect();
        let released = old.iter().filter(|l| !new.contains(l)).copied().collect();
        let (old_poses, new_poses) = (poses(&before), poses(&after));
        let moved = new_poses
            .into_iter()
            .enumerate()
            .filter(|(i, p)| old_poses.get(*i) != Some(p))
            .collect();
        (latched, released, moved)
    }

    /// Keyframes of the settled world at every interval before `time_ms` (and at it when
    /// `inclusive`).
    fn keyframes_until(&mut self, time_ms: f64, inclusive: bool) {
        loop {
            let next = self.intervals as f64 * KEYFRAME_INTERVAL_MS;
            let due = if inclusive {
                next <= time_ms
            } else {
                next < time_ms
            };
            if !due {
                break;
            }
            self.intervals += 1;
            if !self.changed {
                continue;
            }
            self.changed = false;
            let config = self.configuration();
            self.recording.keyframes.push(Keyframe {
                time_ms: next,
                poses: poses(&config),
                latches: latches(&config),
            });
        }
    }

    /// The event's marker on the timeline (the vocabulary's `mark`), but for a module's
    /// first power-on (every module has one) and for a link's drops after the first of an
    /// episode (a blocked or dead link strikes every packet).
    fn mark(
        &mut self,
        time_ms: f64,
        module: Option<usize>,
        event: TraceEvent,
        statement: Option<usize>,
        detail: &str,
    ) {
        let (Some(m), Some(kind)) = (module, event.mark()) else {
            return;
        };
        if event == TraceEvent::PowerOn {
            let first = !self.powered_once.get(m).copied().unwrap_or(true);
            if let Some(p) = self.powered_once.get_mut(m) {
                *p = true;
            }
            if first {
                return;
            }
        }
        if kind == Mark::Link && !self.new_link_episode(event, detail, time_ms) {
            return;
        }
        let what = match statement {
            Some(_) if event != TraceEvent::Refused => {
                format!("{event} on {}: {detail}", self.module_name(m))
            }
            Some(s) => format!("refused #{s} on {}", self.module_name(m)),
            None => format!("{event} on {} {detail}", self.module_name(m)),
        };
        self.recording.markers.push(Marker {
            time_ms,
            kind: kind.name().into(),
            modules: vec![m],
            label: what.trim_end().into(),
        });
    }
}

impl Builder<'_> {
    /// Whether a blocked or dead link's drop starts an episode (no drop of the same kind on
    /// the same link in the last `LINK_EPISODE_GAP_MS`): one marker per episode, not per packet.
    fn new_link_episode(&mut self, event: TraceEvent, detail: &str, time_ms: f64) -> bool {
        // The detail is `M3.C0 <- M5.C1 (17 bytes)`: the link is what precedes the size.
        let link = detail.split(" (").next().unwrap_or(detail);
        let slot = (self.last_link_drop.iter_mut()).find(|(e, l, _)| *e == event && l == link);
        match slot {
            Some((_, _, last)) => {
                let new = time_ms - *last > LINK_EPISODE_GAP_MS;
                *last = time_ms;
                new
            }
            None => {
                self.last_link_drop.push((event, link.to_string(), time_ms));
                true
            }
        }
    }
}

/// Drops on one link closer than this belong to one fault episode.
const LINK_EPISODE_GAP_MS: f64 = 3000.0;

/// `#12 M3.Joint...` names statement 12.
fn statement_of(detail: &str) -> Option<usize> {
    let rest = detail.strip_prefix('#')?;
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok()
}

fn statement_info(s: &ResolvedStatement, text: &str, source: Option<Source>) -> StatementInfo {
    let start = s.span.start as usize;
    let end = s.span.end as usize;
    let line = source.map_or(0, |src| {
        1 + src
            .text
            .get(..start.min(src.text.len()))
            .map_or(0, |before| before.matches('\n').count())
    });
    StatementInfo {
        text: text.into(),
        start,
        end,
        line,
    }
}
