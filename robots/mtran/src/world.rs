//! The M-TRAN world: an M-TRAN configuration mutated by connect, disconnect and joint turns,
//! with the same acceptance rules as the ATRON world (see `README.md`).

use crate::module::{
    MtranConfiguration, MtranJoint, MtranModule, MtranOrientation, MTRAN_JOINT_LIMIT_DEG,
    MTRAN_MIN_SWEEP_DISTANCE_BLOCKS,
};
use dynarole_world::common::Port;
use dynarole_world::geometry::{add, sub, Rotation, Vec3};
use dynarole_world::structure::Structure;
use dynarole_world::world_common::{
    check_turn_angles, joint_sides, known_module, latch, no_motion, release, turned, Latching,
    Sweep, SweptPoint,
};
use dynarole_world::{Carried, Motion};
use dynarole_world::{OpError, Outcome, SweepCheck};
use std::collections::BTreeSet;

/// An M-TRAN configuration being reconfigured; operations succeed (maybe with warnings) or
/// fail and change nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct MtranWorld {
    config: MtranConfiguration,
}

/// Quarter pitches to block pitches, the unit of the sweep check.
pub(crate) fn pitches(v: Vec3) -> [f64; 3] {
    v.map(|c| f64::from(c) / 2.0)
}

impl MtranWorld {
    /// Starts from a validated configuration.
    pub fn new(config: MtranConfiguration) -> MtranWorld {
        MtranWorld { config }
    }

    /// The current configuration.
    pub fn configuration(&self) -> &MtranConfiguration {
        &self.config
    }

    /// Gives the configuration back.
    pub fn into_configuration(self) -> MtranConfiguration {
        self.config
    }

    /// Connects male connector `connector` (0-2) to the female connector whose face touches it.
    pub fn connect(&mut self, module: &str, connector: u8) -> Result<Outcome, OpError> {
        latch(&mut self.config, module, connector, "connect")
    }

    /// Disconnects male connector `connector`; reports a connector with nothing connected and
    /// a release that splits the robot.
    pub fn disconnect(&mut self, module: &str, connector: u8) -> Result<Outcome, OpError> {
        release(&mut self.config.structure, module, connector, "disconnect")
    }

    /// Turns `joint` from `from_deg` to `to_deg` (multiples of 90 within -90..90), in the
    /// positive direction when `positive` (which must agree with the sign of `to - from`, the
    /// range being limited). The side with more modules stays still (tie: the north side
    /// moves); rejected on a wrong start angle, a loop through the module, or a block sweeping
    /// within [`MTRAN_MIN_SWEEP_DISTANCE_BLOCKS`] of a still one.
    pub fn rotate(
        &mut self,
        module: &str,
        joint: MtranJoint,
        from_deg: i16,
        to_deg: i16,
        positive: bool,
    ) -> Result<Outcome, OpError> {
        let angles = (from_deg, to_deg, positive);
        self.rotate_swept(module, joint, angles, SweepCheck::Alone)
    }

    /// [`MtranWorld::rotate`], its sweep checked here only when `sweep` is
    /// [`SweepCheck::Alone`]; `angles` are `(from, to, positive)`.
    pub fn rotate_swept(
        &mut self,
        module: &str,
        joint: MtranJoint,
        angles: (i16, i16, bool),
        sweep: SweepCheck,
    ) -> Result<Outcome, OpError> {
        let (from_deg, to_deg, positive) = angles;
        let index = known_module(&self.config.structure, module)?;
        self.check_angles(index, joint, from_deg, to_deg, positive)?;
        if from_deg == to_deg {
            return Ok(no_motion(module));
        }
        let (moving, turn_quarters, north_moves) = self.plan_turn(index, from_deg, to_deg)?;
        let (pivot, axis) = self.joint_pivot(index, joint);
        let closest = match sweep {
            SweepCheck::Alone => {
                self.check_sweep(index, north_moves, &moving, (pivot, axis), turn_quarters)?
            }
            SweepCheck::WithOthers => None,
        };
        let rotation = Rotation::about_axis(axis, turn_quarters).unwrap_or(Rotation::IDENTITY);
        let mut moved = moving;
        if north_moves {
            moved.insert(index);
        }
        for i in &moved {
            if let Some(m) = self.config.structure.module_mut(*i) {
                m.centre_quarter_pitch =
                    add(pivot, rotation.apply(sub(m.centre_quarter_pitch, pivot)));
                m.orientation =
                    MtranOrientation::from_frame(rotation.compose(&m.orientation.frame()));
            }
        }
        if let Some(m) = self.config.structure.module_mut(index) {
            m.joints_deg[joint.index()] = to_deg;
        }
        Ok(turned(&self.config.structure, &moved, closest))
    }

    /// How a turn would move the robot, without doing it or checking its sweep: a rotation
    /// about the joint's axis, carrying the modules on the moving side whole and the turning
    /// module's moving block (part 0 north, 1 south), swept with the centres of the blocks
    /// that turn, in block pitches. Fails like [`MtranWorld::rotate`] for a wrong angle or a
    /// locked joint. Used to check two turns done at the same time.
    pub fn turn_motion(
        &self,
        module: &str,
        joint: MtranJoint,
        from_deg: i16,
        to_deg: i16,
        positive: bool,
    ) -> Result<Motion, OpError> {
        let index = known_module(&self.config.structure, module)?;
        self.check_angles(index, joint, from_deg, to_deg, positive)?;
        let (pivot, axis) = self.joint_pivot(index, joint);
        let mut motion = Motion::turn(pitches(pivot), axis, 0.0, MTRAN_MIN_SWEEP_DISTANCE_BLOCKS);
        if from_deg == to_deg {
            return Ok(motion);
        }
        let (moving, turn_quarters, north_moves) = self.plan_turn(index, from_deg, to_deg)?;
        let (blocks, _) = self.partition_blocks(index, north_moves, &moving);
        motion = Motion::turn(
            pitches(pivot),
            axis,
            90.0 * f64::from(turn_quarters),
            MTRAN_MIN_SWEEP_DISTANCE_BLOCKS,
        );
        motion.moving = blocks
            .iter()
            .map(|b| (self.name(b.module), b.centre))
            .collect();
        let whole = moving.iter().map(|m| (*m, None));
        let own_block = [(index, Some(usize::from(!north_moves)))];
        motion.carried = whole
            .chain(own_block)
            .map(|(m, part)| Carried {
                module: self.name(m),
                part,
            })
            .collect();
        Ok(motion)
    }

    /// The modules on the side that turns, its signed quarter turns and whether it is the
    /// north side; fails when a loop of latches locks the joint.
    fn plan_turn(
        &self,
        index: usize,
        from_deg: i16,
        to_deg: i16,
    ) -> Result<(BTreeSet<usize>, i32, bool), OpError> {
        let delta_quarters = i32::from(to_deg - from_deg) / 90;
        Ok(joint_sides(&self.config.structure, index)?.moving(delta_quarters))
    }

    /// Range, step, direction and start-angle checks.
    fn check_angles(
        &self,
        index: usize,
        joint: MtranJoint,
        from: i16,
        to: i16,
        positive: bool,
    ) -> Result<(), OpError> {
        let actual = self
            .config
            .structure
            .module(index)
            .map_or(0, |m| m.joints_deg[joint.index()]);
        check_turn_angles(
            self.name(index),
            (from, to),
            actual,
            // A range, not `abs()`: i16::MIN has no absolute value.
            |angle| {
                (-MTRAN_JOINT_LIMIT_DEG..=MTRAN_JOINT_LIMIT_DEG).contains(&angle) && angle % 90 == 0
            },
            "M-TRAN joints take -90, 0 or 90 (range -90..90, lattice steps of 90)",
        )?;
        if from != to && (to > from) != positive {
            return Err(OpError::InvalidAngle {
                module: self.name(index),
                angle: i32::from(to),
                reason: format!(
                    "turning {} from {from} cannot reach {to} within the range -90..90",
                    if positive { "positively" } else { "negatively" }
                ),
            });
        }
        Ok(())
    }

    /// Centre of the joint's block (the turn's pivot) and the joint axis.
    fn joint_pivot(&self, index: usize, joint: MtranJoint) -> (Vec3, Vec3) {
        match self.config.structure.module(index) {
            Some(m) => {
                let block = match joint {
                    MtranJoint::North => m.north_block(),
                    MtranJoint::South => m.south_block(),
                };
                (block.centre_quarter_pitch, m.joint_axis())
            }
            None => ([0; 3], [0, 1, 0]),
        }
    }

    /// Closest approach (block pitches) between moving and still blocks, or the collision.
    fn check_sweep(
        &self,
        index: usize,
        north_moves: bool,
        moving: &BTreeSet<usize>,
        (pivot, axis): (Vec3, Vec3),
        turn_quarters: i32,
    ) -> Result<Option<f64>, OpError> {
        let (moving, still) = self.partition_blocks(index, north_moves, moving);
        let sweep = Sweep {
            pivot: pitches(pivot),
            axis,
            quarters: turn_quarters,
            moving,
            still,
            limit: MTRAN_MIN_SWEEP_DISTANCE_BLOCKS,
        };
        sweep.verdict(&self.config.structure, index)
    }

    /// Splits all blocks into those that turn and those that stay. Both joints separate the
    /// turning module's north block from its south block, so its north block turns with the
    /// north side and its south block with the south side (the pivot block spins in place).
    /// Centres in block pitches.
    fn partition_blocks(
        &self,
        index: usize,
        north_moves: bool,
        moving: &BTreeSet<usize>,
    ) -> (Vec<SweptPoint>, Vec<SweptPoint>) {
        let mut moving_blocks = Vec::new();
        let mut still_blocks = Vec::new();
        for (i, m) in self.config.modules().iter().enumerate() {
            for (b, centre) in m.block_centres().into_iter().enumerate() {
                let block = SweptPoint {
                    module: i,
                    centre: pitches(centre),
                };
                let turns = if i == index {
                    (b == 0) == north_moves
                } else {
                    moving.contains(&i)
                };
                if turns {
                    moving_blocks.push(block);
                } else {
                    still_blocks.push(block);
                }
            }
        }
        (moving_blocks, still_blocks)
    }

    fn name(&self, index: usize) -> String {
        self.config.structure.module_name(index)
    }
}

impl Latching for MtranConfiguration {
    type Module = MtranModule;

    fn structure(&self) -> &Structure<MtranModule> {
        &self.structure
    }

    fn structure_mut(&mut self) -> &mut Structure<MtranModule> {
        &mut self.structure
    }

    fn facing_or_why(&self, port: Port) -> Result<Port, String> {
        self.facing(port)
            .ok_or_else(|| "no connector face touches it".to_string())
    }
}
