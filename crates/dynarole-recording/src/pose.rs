//! Poses as the world model gives them: of a configuration, and of a recording at any time
//! (the settled world of the last keyframe and completed motions, then the turns in progress
//! at their fraction, turned by `dynarole_world::TurnMotion::position_at`).

use crate::format::{Keyframe, LatchLink, Part, Pose, Recording, Turn};
use dynarole_world::{mean_centre, Configuration, PartPose, Port, TurnMotion, View};

/// Every module's pose in `config`, by module index, as its robot places its parts.
pub fn poses(config: &Configuration) -> Vec<Pose> {
    config
        .poses()
        .into_iter()
        .map(|m| Pose {
            centre: m.centre(),
            parts: m
                .parts
                .iter()
                .map(|p| Part {
                    centre: p.centre,
                    up: p.up,
                })
                .collect(),
            connectors: m.connectors,
        })
        .collect()
}

/// Every latch of `config` as module indices and connectors, male first, ordered by the male
/// port.
pub fn latches(config: &Configuration) -> Vec<LatchLink> {
    let view = View::of(config);
    let mut links = Vec::new();
    for m in 0..view.len() {
        for k in (0..view.connectors()).filter(|&k| view.is_male(k)) {
            if let Some(female) = view.latched_to(Port {
                module: m,
                connector: k,
            }) {
                links.push([
                    m,
                    usize::from(k),
                    female.module,
                    usize::from(female.connector),
                ]);
            }
        }
    }
    links
}

/// The settled world at `time_ms`: the last keyframe at or before it, with the motions that
/// completed since (those that ended at `time_ms` included).
pub fn settled_at(recording: &Recording, time_ms: f64) -> Option<Keyframe> {
    let base = recording
        .keyframes
        .iter()
        .take_while(|k| k.time_ms <= time_ms)
        .last()?;
    let mut frame = base.clone();
    for motion in &recording.motions {
        if motion.outcome == "done" && motion.end_ms > base.time_ms && motion.end_ms <= time_ms {
            for (m, pose) in &motion.after {
                if let Some(slot) = frame.poses.get_mut(*m) {
                    *slot = pose.clone();
                }
            }
            frame.latches.retain(|l| !motion.released.contains(l));
            frame.latches.extend(motion.latched.iter().copied());
        }
    }
    frame.time_ms = time_ms;
    Some(frame)
}

/// Every module's pose at `time_ms`, turns in progress included.
pub fn poses_at(recording: &Recording, time_ms: f64) -> Option<Vec<Pose>> {
    let mut frame = settled_at(recording, time_ms)?;
    let part_of: Vec<u8> = recording.connectors.iter().map(|c| c.part).collect();
    for motion in &recording.motions {
        let Some(turn) = &motion.turn else { continue };
        let running = motion.start_ms <= time_ms && time_ms < motion.end_ms;
        if motion.outcome != "done" || !running {
            continue;
        }
        let fraction = (time_ms - motion.start_ms) / (motion.end_ms - motion.start_ms);
        turn_poses(&mut frame.poses, motion.module, turn, fraction, &part_of);
    }
    Some(frame.poses)
}

/// Turns the moving side of `turn` (whole modules and the turning module's moving part) by
/// `fraction` of its angle; `part_of[k]` is the part connector `k` sits on (the recording's
/// `connectors`, as the robot said: `RobotShape::side`).
pub fn turn_poses(poses: &mut [Pose], turner: usize, turn: &Turn, fraction: f64, part_of: &[u8]) {
    let motion = TurnMotion {
        pivot: turn.pivot,
        axis: turn.axis.map(|v| v.round() as i32),
        angle_deg: turn.angle_deg,
        moving: Vec::new(),
        // Only positions are asked of it here, never a clearance.
        limit: 0.0,
    };
    let point = |p: [f64; 3]| motion.position_at(p, fraction);
    let direction = |d: [f64; 3]| {
        let tip = motion.position_at(std::array::from_fn(|i| turn.pivot[i] + d[i]), fraction);
        std::array::from_fn(|i| tip[i] - turn.pivot[i])
    };
    for m in &turn.moving {
        if let Some(pose) = poses.get_mut(*m) {
            pose.centre = point(pose.centre);
            for part in &mut pose.parts {
                part.centre = point(part.centre);
                part.up = direction(part.up);
            }
            pose.connectors.iter_mut().for_each(|c| *c = point(*c));
        }
    }
    turn_part(poses, turner, turn, &point, &direction, part_of);
}

fn turn_part(
    poses: &mut [Pose],
    turner: usize,
    turn: &Turn,
    point: &dyn Fn([f64; 3]) -> [f64; 3],
    direction: &dyn Fn([f64; 3]) -> [f64; 3],
    part_of: &[u8],
) {
    let Some(pose) = poses.get_mut(turner) else {
        return;
    };
    let moving = usize::from(turn.part);
    if let Some(h) = pose.parts.get_mut(moving) {
        h.centre = point(h.centre);
        h.up = direction(h.up);
    }
    // A module's centre is the mean of its parts' centres (`dynarole_world::ModulePose`).
    let parts: Vec<PartPose> = (pose.parts.iter())
        .map(|h| PartPose {
            centre: h.centre,
            up: h.up,
        })
        .collect();
    pose.centre = mean_centre(&parts);
    for (k, c) in pose.connectors.iter_mut().enumerate() {
        if part_of.get(k).is_some_and(|h| usize::from(*h) == moving) {
            *c = point(*c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::turn_poses;
    use crate::format::{Part, Pose, Turn};

    /// A turn moves the connectors on its part as the recording says they sit, not the first
    /// or the second half of the numbers (a robot may number its sides' connectors apart).
    #[test]
    fn a_turn_moves_the_connectors_of_its_part_whatever_their_numbers() {
        let part = Part {
            centre: [0.0; 3],
            up: [0.0, 0.0, 1.0],
        };
        let mut poses = vec![Pose {
            centre: [0.0; 3],
            parts: vec![part, part],
            connectors: vec![[1.0, 0.0, 0.0]; 4],
        }];
        let turn = Turn {
            pivot: [0.0; 3],
            axis: [0, 0, 1].map(f64::from),
            angle_deg: 180.0,
            moving: Vec::new(),
            part: 0,
        };
        turn_poses(&mut poses, 0, &turn, 1.0, &[1, 0, 1, 0]);
        let x: Vec<i64> = poses[0]
            .connectors
            .iter()
            .map(|c| c[0].round() as i64)
            .collect();
        assert_eq!(x, [1, -1, 1, -1]);
    }
}
