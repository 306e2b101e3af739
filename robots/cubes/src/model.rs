//! The cubes robot model: a module's move checked by the cube planners' move rules and made
//! (`lattice.rs`), its motion for the sweeps, the simulator and the viewer (slides translate,
//! pivots turn about an edge), and moves done together checked by the planners'
//! parallel-move rules over every timing.

use crate::lattice::{Cell, Lattice, Move, SetError};
use crate::robot::CubesRobot;
use dynarole_world::{
    model_difference, Action, Carried, Configuration, GroupVerdict, Motion, OpError, Outcome,
    RobotModel, RobotShape,
};
use std::any::Any;

/// The least distance between the centres of a moving cube and another cube the sweeps allow,
/// in cube edges: cubes that touch are one edge apart, and nothing passes closer.
pub const MOTION_LIMIT: f64 = 0.99;

/// A configuration of cubes being reconfigured.
#[derive(Clone, Debug, PartialEq)]
pub struct CubesModel {
    robot: CubesRobot,
}

impl CubesModel {
    pub fn new(robot: CubesRobot) -> CubesModel {
        CubesModel { robot }
    }

    pub fn robot(&self) -> &CubesRobot {
        &self.robot
    }

    fn lattice(&self) -> &Lattice {
        self.robot.lattice()
    }

    fn known(&self, module: &str) -> Result<usize, OpError> {
        (self.robot.index(module)).ok_or_else(|| OpError::UnknownModule {
            module: module.to_string(),
        })
    }

    /// The move `action` names, or why it names none.
    fn move_of(&self, module: &str, action: &Action) -> Result<Move, OpError> {
        let Action::Move { operation, args } = *action else {
            return Err(action.unsupported(module));
        };
        Move::from_operation(operation, args).map_err(|reason| OpError::Unproven {
            module: module.to_string(),
            reason,
        })
    }

    fn refused(&self, module: &str, why: String) -> OpError {
        OpError::Unproven {
            module: module.to_string(),
            reason: why,
        }
    }

    fn name(&self) -> impl Fn(usize) -> String + '_ {
        |m| self.robot.name(m).unwrap_or("?").to_string()
    }

    /// The move of module `turner` a motion this model gave is (the same legs from where the
    /// module is).
    fn move_of_motion(&self, motion: &Motion, turner: usize) -> Option<Move> {
        let start = centre(self.lattice().position(turner)?);
        Move::all()
            .into_iter()
            .find(|mv| mv.legs(start) == motion.legs)
    }
}

/// The two modules a refusal of the set `moves` is about (one twice where it names one).
fn modules_of(e: &SetError, moves: &[(usize, Move)]) -> (usize, usize) {
    let mover = |index: usize| moves.get(index).map_or(0, |(m, _)| *m);
    match e {
        SetError::Twice { module } => (*module, *module),
        SetError::Move { index, .. } => (mover(*index), mover(*index)),
        SetError::ClaimedTwice { movers, .. } => (movers[0], movers[1]),
        SetError::Reserved {
            mover, underway, ..
        } => (*mover, *underway),
        SetError::Enters { mover, leaver, .. } => (*mover, *leaver),
        SetError::Supports { mover, support, .. } => (*mover, *support),
        SetError::StayPutApart { first, apart } => (*first, *apart),
    }
}

/// A cell's centre, in cube edges.
fn centre(cell: Cell) -> [f64; 3] {
    cell.map(f64::from)
}

impl RobotModel for CubesModel {
    fn robot(&self) -> &str {
        "cubes"
    }

    fn shape(&self) -> &dyn RobotShape {
        &self.robot
    }

    fn apply(&mut self, module: &str, action: &Action) -> Result<Outcome, OpError> {
        let m = self.known(module)?;
        let mv = self.move_of(module, action)?;
        let mut lattice = self.lattice().clone();
        (lattice.apply_move(m, &mv)).map_err(|e| self.refused(module, e.describe(&self.name())))?;
        self.robot = self.robot.with_lattice(lattice);
        Ok(Outcome {
            moved: vec![module.to_string()],
            ..Outcome::default()
        })
    }

    fn motion(&self, module: &str, action: &Action) -> Option<Motion> {
        let m = self.robot.index(module)?;
        let mv = self.move_of(module, action).ok()?;
        self.lattice().check_move(m, &mv).ok()?;
        let start = centre(self.lattice().position(m)?);
        Some(Motion {
            legs: mv.legs(start),
            carried: vec![Carried {
                module: module.to_string(),
                part: None,
            }],
            moving: vec![(module.to_string(), start)],
            limit: MOTION_LIMIT,
        })
    }

    /// Cubes have no joints.
    fn quarter_turns(&self, _from: i64, _to: i64, _increasing: bool) -> u64 {
        0
    }

    fn length_unit(&self) -> &str {
        "cube edges"
    }

    /// Every cube moves whole.
    fn rigid_module_centres(&self) -> Option<Vec<[f64; 3]>> {
        let lattice = self.lattice();
        (0..lattice.len())
            .map(|m| lattice.position(m).map(centre))
            .collect()
    }

    /// The planners' parallel-move rules (`Lattice::check_set`): the cells each move claims
    /// cover its swept volume, so moves whose claims are apart and that hold one another up
    /// by no mover are safe for every timing, lock-step or not.
    fn turns_together(
        &self,
        turns: &[(&Motion, usize)],
        _skew: Option<f64>,
    ) -> Option<GroupVerdict> {
        let moves = (turns.iter())
            .map(|(motion, turner)| Some((*turner, self.move_of_motion(motion, *turner)?)))
            .collect::<Option<Vec<(usize, Move)>>>()?;
        Some(match self.lattice().check_set(&moves) {
            Ok(()) => GroupVerdict::Clear,
            Err(e) => GroupVerdict::Refused {
                modules: modules_of(&e, &moves),
                reason: e.describe(&self.name()),
            },
        })
    }

    fn configuration(&self) -> Option<Configuration> {
        Some(Configuration::new(self.robot.clone()))
    }

    fn into_configuration(self: Box<Self>) -> Option<Configuration> {
        Some(Configuration::new(self.robot))
    }

    fn difference(&self, other: &dyn RobotModel) -> Option<String> {
        model_difference(self, other)
    }

    fn clone_model(&self) -> Box<dyn RobotModel> {
        Box::new(self.clone())
    }

    fn network_presets(&self) -> &'static [dynarole_world::NetworkPreset] {
        &crate::NETWORK_PRESETS
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
