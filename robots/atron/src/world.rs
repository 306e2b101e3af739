//! The ATRON world: a configuration mutated by the DynaRole ATRON API (extend, retract,
//! rotateFromToBy), rejecting what the hardware or the simulator could not do.

use crate::config::{AtronConfiguration, AtronModule};
use crate::lattice::{
    is_joint_position, JOINT_UNITS_PER_TURN, MIN_SWEEP_DISTANCE_LATTICE, QUARTER_TURN_UNITS,
};
use dynarole_world::common::Port;
use dynarole_world::geometry::{add, to_f64, Rotation};
use dynarole_world::structure::Structure;
use dynarole_world::world_common::{
    check_turn_angles, joint_sides, known_module, latch, no_motion, release, turned, Latching,
    Sweep, SweptPoint,
};
use dynarole_world::{Carried, Motion};
use dynarole_world::{OpError, Outcome, SweepCheck};
use std::collections::BTreeSet;

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
        let angles = (from_units, to_units, increasing);
        self.rotate_swept(module, angles, SweepCheck::Alone)
    }

    /// [`World::rotate`], its sweep checked here only when `sweep` is [`SweepCheck::Alone`];
    /// `angles` are `(from, to, increasing)`.
    pub fn rotate_swept(
        &mut self,
        module: &str,
        angles: (u16, u16, bool),
        sweep: SweepCheck,
    ) -> Result<Outcome, OpError> {
        let (from_units, to_units, increasing) = angles;
        let index = known_module(&self.config.structure, module)?;
        let turn = self.plan_turn(index, from_units, to_units, increasing)?;
        if turn.joint_quarters == 0 {
            return Ok(no_motion(module));
        }
        let (moving, turn_quarters, north_moves, quarters) = (
            turn.moving,
            turn.turn_quarters,
            turn.north_moves,
            turn.joint_quarters,
        );
        let closest = match sweep {
            SweepCheck::Alone => self.check_sweep(index, &moving, turn_quarters)?,
            SweepCheck::WithOthers => None,
        };
        self.apply_turn(index, &moving, turn_quarters, !north_moves, quarters);
        let mut moved: BTreeSet<usize> = moving;
        if !north_moves {
            moved.insert(index);
        }
        Ok(turned(&self.config.structure, &moved, closest))
    }

    /// How a turn would move the robot, without doing it or checking its sweep: a rotation
    /// about the joint's axis through the module's centre, carrying the modules on the
    /// moving side whole and the turning module's moving hemisphere (part 0 north, 1 south),
    /// swept with the module centres. Fails like [`World::rotate`] for a wrong angle or a
    /// locked joint. Used to check that two turns done at the same time do not collide.
    pub fn turn_motion(
        &self,
        module: &str,
        from_units: u16,
        to_units: u16,
        increasing: bool,
    ) -> Result<Motion, OpError> {
        let index = known_module(&self.config.structure, module)?;
        let PlannedTurn {
            moving,
            turn_quarters,
            north_moves,
            ..
        } = self.plan_turn(index, from_units, to_units, increasing)?;
        let pivot_module = self.config.module(index);
        let mut motion = Motion::turn(
            pivot_module.map_or([0.0; 3], |m| to_f64(m.position)),
            pivot_module.map_or([0, 0, 1], |m| m.orientation.axis()),
            90.0 * f64::from(turn_quarters),
            MIN_SWEEP_DISTANCE_LATTICE,
        );
        let modules = moving.iter().filter_map(|i| self.config.module(*i));
        for m in modules {
            motion.moving.push((m.name.clone(), to_f64(m.position)));
            motion.carried.push(Carried {
                module: m.name.clone(),
                part: None,
            });
        }
        if turn_quarters != 0 {
            motion.carried.push(Carried {
                module: module.to_string(),
                part: Some(usize::from(!north_moves)),
            });
        }
        Ok(motion)
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
        let actual = self.config.module(index).map_or(0, |m| m.joint_units);
        check_turn_angles(
            self.name(index),
            (from, to),
            actual,
            is_joint_position,
            "ATRON joint positions are 0, 108, 216 and 324",
        )?;
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
        let (moving, turn_quarters, north_moves) =
            joint_sides(&self.config.structure, index)?.moving(joint_quarters);
        Ok(PlannedTurn {
            moving,
            turn_quarters,
            north_moves,
            joint_quarters,
        })
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
        let points = |inside: bool| -> Vec<SweptPoint> {
            let modules = self.config.modules().iter().enumerate();
            modules
                .filter(|(i, _)| moving.contains(i) == inside)
                .map(|(module, m)| SweptPoint {
                    module,
                    centre: to_f64(m.position),
                })
                .collect()
        };
        let sweep = Sweep {
            pivot: to_f64(pivot_module.position),
            axis: pivot_module.orientation.axis(),
            quarters: turn_quarters,
            moving: points(true),
            still: points(false),
            limit: MIN_SWEEP_DISTANCE_LATTICE,
        };
        sweep.verdict(&self.config.structure, index)
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
