//! Poses as the world model gives them: of a configuration, and of a recording at any time
//! (the settled world of the last keyframe and completed motions, then the operations in
//! progress at their fraction, moved by `dynarole_world::Motion::position_at`).

use crate::format::{Keyframe, LatchLink, Part, Path, Pose, Recording};
use dynarole_world::{mean_centre, Configuration, Motion, PartPose, Port, View};

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

/// Every module's pose at `time_ms`, operations in progress included.
pub fn poses_at(recording: &Recording, time_ms: f64) -> Option<Vec<Pose>> {
    let mut frame = settled_at(recording, time_ms)?;
    let part_of: Vec<u8> = recording.connectors.iter().map(|c| c.part).collect();
    for motion in &recording.motions {
        let Some(path) = &motion.path else { continue };
        let running = motion.start_ms <= time_ms && time_ms < motion.end_ms;
        if motion.outcome != "done" || !running {
            continue;
        }
        let fraction = (time_ms - motion.start_ms) / (motion.end_ms - motion.start_ms);
        path_poses(&mut frame.poses, path, fraction, &part_of);
    }
    Some(frame.poses)
}

/// Moves what `path` carries (whole modules, and single parts with the connectors on them)
/// by `fraction` of its motion; `part_of[k]` is the part connector `k` sits on (the
/// recording's `connectors`, as the robot said: `RobotShape::side`).
pub fn path_poses(poses: &mut [Pose], path: &Path, fraction: f64, part_of: &[u8]) {
    let motion = Motion {
        legs: path.legs.clone(),
        ..Motion::in_place()
    };
    let point = |p: [f64; 3]| motion.position_at(p, fraction);
    let direction = |d: [f64; 3]| motion.direction_at(d, fraction);
    for m in &path.modules {
        if let Some(pose) = poses.get_mut(*m) {
            pose.centre = point(pose.centre);
            for part in &mut pose.parts {
                part.centre = point(part.centre);
                part.up = direction(part.up);
            }
            pose.connectors.iter_mut().for_each(|c| *c = point(*c));
        }
    }
    for &[m, part] in &path.parts {
        if let Some(pose) = poses.get_mut(m) {
            move_part(pose, part, &point, &direction, part_of);
        }
    }
}

/// Moves one part of a module and the connectors on it; the module's centre follows as the
/// mean of its parts' centres (`dynarole_world::ModulePose`).
fn move_part(
    pose: &mut Pose,
    moving: usize,
    point: &dyn Fn([f64; 3]) -> [f64; 3],
    direction: &dyn Fn([f64; 3]) -> [f64; 3],
    part_of: &[u8],
) {
    if let Some(h) = pose.parts.get_mut(moving) {
        h.centre = point(h.centre);
        h.up = direction(h.up);
    }
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
    use super::path_poses;
    use crate::format::{Part, Path, Pose};
    use dynarole_world::Leg;

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
        let turn = Path {
            legs: vec![Leg::Rotate {
                pivot: [0.0; 3],
                axis: [0.0, 0.0, 1.0],
                angle_deg: 180.0,
            }],
            modules: Vec::new(),
            parts: vec![[0, 0]],
        };
        path_poses(&mut poses, &turn, 1.0, &[1, 0, 1, 0]);
        let x: Vec<i64> = poses[0]
            .connectors
            .iter()
            .map(|c| c[0].round() as i64)
            .collect();
        assert_eq!(x, [1, -1, 1, -1]);
    }

    /// A corner slide carries a whole module along both legs, its parts' up directions
    /// unchanged; a part carried alone moves with its connectors and drags the centre.
    #[test]
    fn a_path_of_translations_slides_whole_modules_and_single_parts() {
        let part = |x: f64| Part {
            centre: [x, 0.0, 0.0],
            up: [0.0, 0.0, 1.0],
        };
        let pose = Pose {
            centre: [0.5, 0.0, 0.0],
            parts: vec![part(0.0), part(1.0)],
            connectors: vec![[0.0; 3], [1.0, 0.0, 0.0]],
        };
        let mut poses = vec![pose.clone(), pose];
        let path = Path {
            legs: vec![
                Leg::Translate {
                    by: [0.0, 2.0, 0.0],
                },
                Leg::Translate {
                    by: [0.0, 0.0, 2.0],
                },
            ],
            modules: vec![0],
            parts: vec![[1, 1]],
        };
        path_poses(&mut poses, &path, 0.75, &[0, 1]);
        assert_eq!(poses[0].centre, [0.5, 2.0, 1.0]);
        assert_eq!(poses[0].parts[1].centre, [1.0, 2.0, 1.0]);
        assert_eq!(poses[0].parts[1].up, [0.0, 0.0, 1.0]);
        assert_eq!(poses[0].connectors[0], [0.0, 2.0, 1.0]);
        assert_eq!(poses[1].parts[0].centre, [0.0, 0.0, 0.0]);
        assert_eq!(poses[1].parts[1].centre, [1.0, 2.0, 1.0]);
        assert_eq!(poses[1].centre, [0.5, 1.0, 0.5]);
        assert_eq!(poses[1].connectors, vec![[0.0; 3], [1.0, 2.0, 1.0]]);
    }
}
