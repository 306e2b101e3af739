//! The ATRON world: a configuration mutated by the DynaRole ATRON API (extend, retract,
//! rotateFromToBy), rejecting what the hardware or the simulator could not do.

use crate::atron::{
    is_joint_position, is_north, JOINT_UNITS_PER_TURN, MIN_SWEEP_DISTANCE_LATTICE,
    QUARTER_TURN_UNITS,
};
use crate::config::{AtronConfiguration, AtronModule, Port};
use crate::geometry::{add, arc_point_distance, sweep_closest_approach, to_f64, Rotation};
use crate::graph::split_at_joint;
use crate::ops::{OpError, Outcome, Warning};
use crate::structure::Structure;
use crate::world_common::{known_module, latch, release, sweep_verdict, warn, Latching};
use std::collections::BTreeSet;

/// The motion of one joint turn: the moving side turns by `angle_deg` (right-handed, signed)
/// about `axis` through `pivot`. Points are module centres (ATRON, lattice units) or block
/// centres (M-TRAN, block pitches).
#[derive(Clone, Debug, PartialEq)]
pub struct TurnMotion {
    pub pivot: [f64; 3],
    pub axis: crate::geometry::Vec3,
    pub angle_deg: f64,
    /// Name and start position of each moving point (a module, or an M-TRAN block, whose
    /// module's name is repeated for its two blocks).
    pub moving: Vec<(String, [f64; 3])>,
    /// The smallest distance the model allows between a moving point and another one.
    pub limit: f64,
}

impl TurnMotion {
    /// Where a point of the moving side is after `fraction` (0 to 1) of the turn.
    pub fn position_at(&self, point: [f64; 3], fraction: f64) -> [f64; 3] {
        let (a, r, dot, cross) = self.frame(point);
        let t = (self.angle_deg * fraction).to_radians();
        // Rodrigues' rotation formula for a unit axis.
        let (sin, cos) = t.sin_cos();
        std::array::from_fn(|k| {
            self.pivot[k] + r[k] * cos + cross[k] * sin + a[k] * dot * (1.0 - cos)
        })
    }

    /// The smallest distance from the still point `point` to the path of the moving point
    /// `start` over the whole turn, in closed form (not sampled).
    pub fn distance_to_path(&self, start: [f64; 3], point: [f64; 3]) -> f64 {
        let a = self.axis.map(f64::from);
        // Turning by a negative angle about a is the same as a positive one about -a.
        let a = if self.angle_deg < 0.0 {
            a.map(|c| -c)
        } else {
            a
        };
        arc_point_distance(
            self.pivot,
            a,
            self.angle_deg.abs().to_radians(),
            start,
            point,
        )
        .0
    }

    /// The length of the path of the moving point `start` (its radius about the axis times
    /// the angle turned): no point of it moves farther than this during the turn.
    pub fn path_length(&self, start: [f64; 3]) -> f64 {
        let (_, r, dot, _) = self.frame(start);
        let radius = (r.iter().map(|c| c * c).sum::<f64>() - dot * dot)
            .max(0.0)
            .sqrt();
        radius * self.angle_deg.abs().to_radians()
    }

    /// The exact bounding box (low, high) of the path of the moving point `start`: its two
    /// ends, and the extremes of each coordinate that fall within the turn.
    pub fn path_box(&self, start: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let (_, r, _, cross) = self.frame(start);
        let total = self.angle_deg.to_radians();
        let mut low = start;
        let mut high = start;
        let mut include = |p: [f64; 3]| {
            for k in 0..3 {
                low[k] = low[k].min(p[k]);
                high[k] = high[k].max(p[k]);
            }
        };
        include(self.position_at(start, 1.0));
        for k in 0..3 {
            // Coordinate k varies as r_k cos t + cross_k sin t (plus a constant): extreme
            // where tan t = cross_k / r_k, and half a turn later.
            let peak = cross[k].atan2(r[k] - self.axis_component(k, start));
            for extreme in [peak, peak + std::f64::consts::PI] {
                if let Some(fraction) = fraction_of(extreme, total) {
                    include(self.position_at(start, fraction));
                }
            }
        }
        (low, high)
    }

    /// The axis (unit), the point relative to the pivot, its component along the axis and
    /// the axis crossed with it.
    fn frame(&self, point: [f64; 3]) -> ([f64; 3], [f64; 3], f64, [f64; 3]) {
        let a = self.axis.map(f64::from);
        let r = std::array::from_fn(|k| point[k] - self.pivot[k]);
        let dot = a[0] * r[0] + a[1] * r[1] + a[2] * r[2];
        let cross = [
            a[1] * r[2] - a[2] * r[1],
            a[2] * r[0] - a[0] * r[2],
            a[0] * r[1] - a[1] * r[0],
        ];
        (a, r, dot, cross)
    }

    /// Coordinate k of the part of `point` (relative to the pivot) along the axis.
    fn axis_component(&self, k: usize, point: [f64; 3]) -> f64 {
        let (a, _, dot, _) = self.frame(point);
        a[k] * dot
    }
}

/// The fraction of a turn by `total` radians (signed) at which the angle `t` (any turn of it)
/// is reached, if it is.
fn fraction_of(t: f64, total: f64) -> Option<f64> {
    if total == 0.0 {
        return None;
    }
    let tau = std::f64::consts::TAU;
    let t = if total > 0.0 {
        t.rem_euclid(tau)
    } else {
        -(-t).rem_euclid(tau)
    };
    let fraction = t / total;
    (0.0..=1.0).contains(&fraction).then_some(fraction)
}

/// A turn before it is done: the modules on the moving side and the signed quarter turns
/// they make about the axis (`joint_quarters` is the change of the joint angle).
struct PlannedTurn {
    moving: BTreeSet<usize>,
    turn_quarters: i32,
    north_moves: bool,
    joint_quarters: i32,
}

/// An ATRON configuration being reconfigured. Every operation either succeeds (possibly with
/// warnings) and leaves a valid configuration, or fails and changes nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct World {
    config: AtronConfiguration,
}

impl World {
    /// Starts from a validated configuration.
    pub fn new(config: AtronConfiguration) -> World {
        World { config }
    }

    /// The current configuration (all queries live there).
    pub fn configuration(&self) -> &AtronConfiguration {
        &self.config
    }

    /// Gives the current configuration back.
    pub fn into_configuration(self) -> AtronConfiguration {
        self.config
    }

    /// `module.Connector[connector].extend()`: latches a male connector onto the female
    /// connector facing it. Rejected for a female connector or when no female connector faces
    /// it; a connector already latched is reported and left as is.
    pub fn extend(&mut self, module: &str, connector: u8) -> Result<Outcome, OpError> {
        latch(&mut self.config, module, connector, "extend")
    }

    /// `module.Connector[connector].retract()`: releases the latch of a male connector. A
    /// female connector is rejected (only the male side can release); a connector with no latch
    /// is reported; a release that splits the robot in two is reported.
    pub fn retract(&mut self, module: &str, connector: u8) -> Result<Outcome, OpError> {
        release(&mut self.config.structure, module, connector, "retract")
    }

    /// `module.Joint.rotateFromToBy(from, to, increasing, _)`: turns the joint in quarter turns
    /// (angles in 1/432 turn; `increasing` = the DynaRole `true` direction, wrapping mod 432).
    ///
    /// The side with more modules stays still (tie: the side on the north hemisphere moves);
    /// everything latched to the moving hemisphere turns with it. Rejected when the joint is
    /// not at `from`, when a loop of latches joins the two hemispheres, or when a moving module
    /// would pass within [`MIN_SWEEP_DISTANCE_LATTICE`] of a still one at any point of the
    /// continuous turn.
    pub fn rotate(
        &mut self,
        module: &str,
        from_units: u16,
        to_units: u16,
        increasing: bool,
    ) -> Result<Outcome, OpError> {
        let index = known_module(&self.config.structure, module)?;
        let turn = self.plan_turn(index, from_units, to_units, increasing)?;
        if turn.joint_quarters == 0 {
            return Ok(warn(Warning::NoMotion {
                module: module.to_string(),
            }));
        }
        let (moving, turn_quarters, north_moves, quarters) = (
            turn.moving,
            turn.turn_quarters,
            turn.north_moves,
            turn.joint_quarters,
        );
        let closest = self.check_sweep(index, &moving, turn_quarters)?;
        self.apply_turn(index, &moving, turn_quarters, !north_moves, quarters);
        let mut moved: BTreeSet<usize> = moving;
        if !north_moves {
            moved.insert(index);
        }
        Ok(Outcome {
            warnings: Vec::new(),
            moved: self.names(&moved),
            closest_approach: closest,
        })
    }

    /// How a turn would move the robot, without doing it or checking its sweep: the pivot,
    /// the axis, the signed angle of the moving side and the modules on it. Fails like
    /// [`World::rotate`] for a wrong angle or a locked joint. Used to check that two turns
    /// done at the same time do not collide with each other.
    pub fn turn_motion(
        &self,
        module: &str,
        from_units: u16,
        to_units: u16,
        increasing: bool,
    ) -> Result<TurnMotion, OpError> {
        let index = known_module(&self.config.structure, module)?;
        let PlannedTurn {
            moving,
            turn_quarters,
            ..
        } = self.plan_turn(index, from_units, to_units, increasing)?;
        let pivot_module = self.config.module(index);
        Ok(TurnMotion {
            pivot: pivot_module.map_or([0.0; 3], |m| to_f64(m.position)),
            axis: pivot_module.map_or([0, 0, 1], |m| m.orientation.axis()),
            angle_deg: 90.0 * f64::from(turn_quarters),
            moving: moving
                .iter()
                .filter_map(|i| {
                    self.config
                        .module(*i)
                        .map(|m| (m.name.clone(), to_f64(m.position)))
                })
                .collect(),
            limit: MIN_SWEEP_DISTANCE_LATTICE,
        })
    }

    /// Which side of a turn moves and by how much, after checking the angles and that no
    /// loop locks the joint. The side with more modules stays still; on a tie the north side
    /// moves (atron.md a.4).
    fn plan_turn(
        &self,
        index: usize,
        from: u16,
        to: u16,
        increasing: bool,
    ) -> Result<PlannedTurn, OpError> {
        self.check_rotation_angles(index, from, to)?;
        let joint_quarters = quarter_turns(from, to, increasing);
        if joint_quarters == 0 {
            // No motion: nothing to check, even on a locked joint.
            let moving = BTreeSet::new();
            return Ok(PlannedTurn {
                moving,
                turn_quarters: 0,
                north_moves: false,
                joint_quarters,
            });
        }
        let sides = split_at_joint(self.config.latches(), index, is_north, |c| !is_north(c))
            .map_err(|loop_side| OpError::JointLocked {
                module: self.name(index),
                loop_modules: self.names(&loop_side),
            })?;
        let (moving, turn_quarters, north_moves) = sides.moving(joint_quarters);
        Ok(PlannedTurn {
            moving,
            turn_quarters,
            north_moves,
            joint_quarters,
        })
    }

    /// Checks the angles and that the joint is at `from`.
    fn check_rotation_angles(&self, index: usize, from: u16, to: u16) -> Result<(), OpError> {
        let name = self.name(index);
        for angle in [from, to] {
            if !is_joint_position(angle) {
                return Err(OpError::InvalidAngle {
                    module: name,
                    angle: i32::from(angle),
                    reason: "ATRON joint positions are 0, 108, 216 and 324".to_string(),
                });
            }
        }
        let actual = self.config.module(index).map_or(0, |m| m.joint_units);
        if actual != from {
            return Err(OpError::WrongStartAngle {
                module: name,
                from: i32::from(from),
                actual: i32::from(actual),
            });
        }
        Ok(())
    }

    /// The closest approach of the turn, or the collision that forbids it.
    fn check_sweep(
        &self,
        index: usize,
        moving: &BTreeSet<usize>,
        turn_quarters: i32,
    ) -> Result<Option<f64>, OpError> {
        let Some(pivot_module) = self.config.module(index) else {
            return Ok(None);
        };
        let centre = |i: &usize| self.config.module(*i).map(|m| to_f64(m.position));
        let moving_list: Vec<usize> = moving.iter().copied().collect();
        let still_list: Vec<usize> = (0..self.config.modules().len())
            .filter(|i| !moving.contains(i))
            .collect();
        let moving_points: Vec<[f64; 3]> = moving_list.iter().filter_map(centre).collect();
        let still_points: Vec<[f64; 3]> = still_list.iter().filter_map(centre).collect();
        let approach = sweep_closest_approach(
            to_f64(pivot_module.position),
            pivot_module.orientation.axis(),
            90.0 * f64::from(turn_quarters),
            &moving_points,
            &still_points,
        );
        sweep_verdict(approach, MIN_SWEEP_DISTANCE_LATTICE, |a| {
            let pick = |list: &[usize], i: usize| list.get(i).map(|m| self.name(*m));
            [
                self.name(index),
                pick(&moving_list, a.moving).unwrap_or_default(),
                pick(&still_list, a.still).unwrap_or_default(),
            ]
        })
    }

    /// Turns the moving modules about the joint axis and updates the joint (and the module's
    /// own south frame when the south side moves).
    fn apply_turn(
        &mut self,
        index: usize,
        moving: &BTreeSet<usize>,
        turn_quarters: i32,
        south_moves: bool,
        joint_quarters: i32,
    ) {
        let Some(pivot_module) = self.config.module(index) else {
            return;
        };
        let pivot = pivot_module.position;
        let Some(rotation) = Rotation::about_axis(pivot_module.orientation.axis(), turn_quarters)
        else {
            return;
        };
        self.config.turn_modules(moving, pivot, &rotation);
        if let Some(m) = self.config.structure.module_mut(index) {
            if south_moves {
                m.orientation = m.orientation.rotated(&rotation);
            }
            let turn = i32::from(QUARTER_TURN_UNITS) * joint_quarters;
            let joint =
                (i32::from(m.joint_units) + turn).rem_euclid(i32::from(JOINT_UNITS_PER_TURN));
            m.joint_units = u16::try_from(joint).unwrap_or(m.joint_units);
        }
    }

    fn name(&self, index: usize) -> String {
        self.config.structure.module_name(index)
    }

    fn names(&self, indices: &BTreeSet<usize>) -> Vec<String> {
        self.config.structure.module_names(indices)
    }
}

impl Latching for AtronConfiguration {
    type Module = AtronModule;

    fn structure(&self) -> &Structure<AtronModule> {
        &self.structure
    }

    fn structure_mut(&mut self) -> &mut Structure<AtronModule> {
        &mut self.structure
    }

    /// Names the empty site when no module faces `port`.
    fn facing_or_why(&self, port: Port) -> Result<Port, String> {
        self.facing(port).ok_or_else(|| {
            let site = self.module(port.module).and_then(|m| {
                m.connector_offset(port.connector)
                    .map(|o| add(m.position, o))
            });
            format!(
                "no module faces it (site {:?} is empty)",
                site.unwrap_or_default()
            )
        })
    }
}

/// Signed number of quarter turns from `from` to `to` in the given direction (0..=3 steps).
fn quarter_turns(from: u16, to: u16, increasing: bool) -> i32 {
    let turn = i32::from(JOINT_UNITS_PER_TURN);
    let delta = if increasing {
        (i32::from(to) - i32::from(from)).rem_euclid(turn)
    } else {
        -(i32::from(from) - i32::from(to)).rem_euclid(turn)
    };
    delta / i32::from(QUARTER_TURN_UNITS)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Turns about each axis, both ways, of points off the axis and on it.
    fn motions() -> Vec<(TurnMotion, [f64; 3])> {
        let mut out = Vec::new();
        for axis in [[1, 0, 0], [0, -1, 0], [0, 0, 1]] {
            for angle_deg in [90.0, -180.0, 270.0] {
                let motion = TurnMotion {
                    pivot: [0.5, -1.0, 2.0],
                    axis,
                    angle_deg,
                    moving: Vec::new(),
                    limit: MIN_SWEEP_DISTANCE_LATTICE,
                };
                for start in [[2.5, 1.0, 3.0], [0.5, -1.0, 5.0], [-3.0, 0.0, 2.0]] {
                    out.push((motion.clone(), start));
                }
            }
        }
        out
    }

    fn dense(motion: &TurnMotion, start: [f64; 3]) -> Vec<[f64; 3]> {
        (0..=20_000)
            .map(|i| motion.position_at(start, f64::from(i) / 20_000.0))
            .collect()
    }

    #[test]
    fn path_boxes_are_the_exact_bounds_of_the_path() {
        for (motion, start) in motions() {
            let (low, high) = motion.path_box(start);
            let points = dense(&motion, start);
            for k in 0..3 {
                let min = points.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
                let max = points
                    .iter()
                    .map(|p| p[k])
                    .fold(f64::NEG_INFINITY, f64::max);
                assert!((low[k] - min).abs() < 1e-6, "{motion:?} {start:?} {k}");
                assert!((high[k] - max).abs() < 1e-6, "{motion:?} {start:?} {k}");
            }
        }
    }

    #[test]
    fn distance_to_a_path_and_its_length_match_dense_sampling() {
        let point = [1.0, 0.5, 2.5];
        for (motion, start) in motions() {
            let points = dense(&motion, start);
            let distance = |p: &[f64; 3]| {
                ((p[0] - point[0]).powi(2) + (p[1] - point[1]).powi(2) + (p[2] - point[2]).powi(2))
                    .sqrt()
            };
            let sampled = points.iter().map(distance).fold(f64::INFINITY, f64::min);
            assert!((motion.distance_to_path(start, point) - sampled).abs() < 1e-6);
            let walked: f64 = points
                .windows(2)
                .map(|w| {
                    ((w[0][0] - w[1][0]).powi(2)
                        + (w[0][1] - w[1][1]).powi(2)
                        + (w[0][2] - w[1][2]).powi(2))
                    .sqrt()
                })
                .sum();
            assert!((motion.path_length(start) - walked).abs() < 1e-6);
        }
    }
}
