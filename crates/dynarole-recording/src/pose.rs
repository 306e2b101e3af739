//! Poses as the world model gives them: of a configuration, and of a recording at any time
//! (the settled world of the last keyframe and completed motions, then the turns in progress
//! at their fraction, turned by `dynarole_world::TurnMotion::position_at`).

use crate::format::{Half, Keyframe, LatchLink, Pose, Recording, Turn};
use dynarole_world::geometry::to_f64;
use dynarole_world::{Configuration, TurnMotion, View};

/// Every module's pose in `config`, by module index.
pub fn poses(config: &Configuration) -> Vec<Pose> {
    match config {
        Configuration::Atron(c) => c
            .modules()
            .iter()
            .map(|m| {
                let centre = to_f64(m.position);
                let axis = to_f64(m.orientation.axis());
                // The axis points from the north hemisphere (half 0) to the south one.
                let north = Half {
                    centre,
                    up: axis.map(|v| -v),
                };
                let south = Half { centre, up: axis };
                let connectors = (0..View::of(config).connectors())
                    .map(|k| {
                        let offset = m.connector_offset(k).map_or([0.0; 3], to_f64);
                        std::array::from_fn(|i| centre[i] + offset[i] / 2.0)
                    })
                    .collect();
                Pose {
                    centre,
                    halves: [north, south],
                    connectors,
                }
            })
            .collect(),
        Configuration::Mtran(c) => c
            .modules()
            .iter()
            .map(|m| {
                let pitch = |v: [i32; 3]| to_f64(v).map(|x| x / 2.0);
                let up = to_f64(m.joint_axis());
                let [n, s] = m.block_centres().map(pitch);
                let connectors = (0..View::of(config).connectors())
                    .map(|k| {
                        m.connector(k)
                            .map_or([0.0; 3], |p| pitch(p.face_quarter_pitch))
                    })
                    .collect();
                Pose {
                    centre: std::array::from_fn(|i| (n[i] + s[i]) / 2.0),
                    halves: [Half { centre: n, up }, Half { centre: s, up }],
                    connectors,
                }
            })
            .collect(),
    }
}

/// Every latch of `config` as module indices and connectors, in the configuration's order.
pub fn latches(config: &Configuration) -> Vec<LatchLink> {
    let set = match config {
        Configuration::Atron(c) => c.latches(),
        Configuration::Mtran(c) => c.latches(),
    };
    set.iter()
        .map(|l| {
            [
                l.male.module,
                usize::from(l.male.connector),
                l.female.module,
                usize::from(l.female.connector),
            ]
        })
        .collect()
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
    let half_of: Vec<u8> = recording.connectors.iter().map(|c| c.half).collect();
    for motion in &recording.motions {
        let Some(turn) = &motion.turn else { continue };
        let running = motion.start_ms <= time_ms && time_ms < motion.end_ms;
        if motion.outcome != "done" || !running {
            continue;
        }
        let fraction = (time_ms - motion.start_ms) / (motion.end_ms - motion.start_ms);
        turn_poses(&mut frame.poses, motion.module, turn, fraction, &half_of);
    }
    Some(frame.poses)
}

/// Turns the moving side of `turn` (whole modules and the turning module's moving half) by
/// `fraction` of its angle; `half_of[k]` is the half connector `k` sits on (the recording's
/// `connectors`, as the robot said: `RobotShape::side`).
pub fn turn_poses(poses: &mut [Pose], turner: usize, turn: &Turn, fraction: f64, half_of: &[u8]) {
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
            for half in &mut pose.halves {
                half.centre = point(half.centre);
                half.up = direction(half.up);
            }
            pose.connectors.iter_mut().for_each(|c| *c = point(*c));
        }
    }
    turn_half(poses, turner, turn, &point, &direction, half_of);
}

fn turn_half(
    poses: &mut [Pose],
    turner: usize,
    turn: &Turn,
    point: &dyn Fn([f64; 3]) -> [f64; 3],
    direction: &dyn Fn([f64; 3]) -> [f64; 3],
    half_of: &[u8],
) {
    let Some(pose) = poses.get_mut(turner) else {
        return;
    };
    let half = usize::from(turn.half);
    if let Some(h) = pose.halves.get_mut(half) {
        h.centre = point(h.centre);
        h.up = direction(h.up);
    }
    // The centre lies between the halves (an M-TRAN block moves it; ATRON halves share it).
    let [a, b] = [pose.halves[0].centre, pose.halves[1].centre];
    pose.centre = std::array::from_fn(|i| (a[i] + b[i]) / 2.0);
    for (k, c) in pose.connectors.iter_mut().enumerate() {
        if half_of.get(k).is_some_and(|h| usize::from(*h) == half) {
            *c = point(*c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::turn_poses;
    use crate::format::{Half, Pose, Turn};

    /// A turn moves the connectors on its half as the recording says they sit, not the first
    /// or the second half of the numbers (a robot may number its sides' connectors apart).
    #[test]
    fn a_turn_moves_the_connectors_of_its_half_whatever_their_numbers() {
        let half = Half {
            centre: [0.0; 3],
            up: [0.0, 0.0, 1.0],
        };
        let mut poses = vec![Pose {
            centre: [0.0; 3],
            halves: [half, half],
            connectors: vec![[1.0, 0.0, 0.0]; 4],
        }];
        let turn = Turn {
            pivot: [0.0; 3],
            axis: [0, 0, 1].map(f64::from),
            angle_deg: 180.0,
            moving: Vec::new(),
            half: 0,
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
