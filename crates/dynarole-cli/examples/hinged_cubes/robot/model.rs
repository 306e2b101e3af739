//! The hinged cubes behind the robot API: the configuration answers `RobotShape`, and
//! [`CubesWorld`] is the `RobotModel` that latches, unlatches and bends hinges.
//!
//! Turning a cube's hinge turns everything latched beyond its front face about the cube's
//! centre; it is refused when a loop of latches holds the front to the cube itself, when the
//! hinge is not at `from`, or when a cube would land on an occupied cell.

use super::configuration::{minus, plus, quarters, turned, Cell, CubesConfiguration, BACK, FRONT};
use dynarole_world::rigid::{Body, Shape};
use dynarole_world::{
    model_difference, Action, Carried, Configuration, Motion, OpError, Outcome, Port, RobotModel,
    RobotShape, Rotation, Warning,
};
use std::any::Any;
use std::collections::BTreeSet;

fn port(module: usize, connector: u8) -> Port {
    Port { module, connector }
}

fn warning(warning: Warning) -> Outcome {
    Outcome {
        warnings: vec![warning],
        ..Outcome::default()
    }
}

/// An angle for an error message.
fn angle(a: i64) -> i32 {
    i32::try_from(a).unwrap_or(i32::MAX)
}

/// The frame of a cube heading `heading`, up along +z: what a rigid motion acts on.
fn frame(heading: Cell) -> Rotation {
    Rotation::about_axis([0, 0, 1], quarters(heading)).unwrap_or(Rotation::IDENTITY)
}

/// A frame as the heading it gives (`heading +y`), or the frame itself off the plane.
fn frame_name(frame: Rotation) -> String {
    let x = frame.apply([1, 0, 0]);
    if frame.apply([0, 0, 1]) == [0, 0, 1] {
        format!(
            "heading {}",
            super::configuration::heading_name([x[0], x[1]])
        )
    } else {
        format!("{frame}")
    }
}

impl CubesConfiguration {
    /// The chain as rigid bodies in space, its plane at z = 0, so that comparing two
    /// configurations up to a rigid motion sees a chain turned over as a different one.
    pub fn rigid_shape(&self) -> Shape {
        let bodies = self.cubes.iter().map(|c| {
            let body = Body {
                id: c.id,
                position: [c.cell[0], c.cell[1], 0],
                frame: frame(c.heading),
                joints: vec![c.hinge],
            };
            (c.name.clone(), body)
        });
        let connections = (self.named_connections().into_iter())
            .map(|(a, ca, b, cb)| format!("{a}.C{ca}-{b}.C{cb}"))
            .collect();
        Shape {
            bodies: bodies.collect(),
            connections,
            name_frame: frame_name,
            position_scale: 1,
            anchored: false,
            unnamed: None,
        }
    }
}

impl RobotShape for CubesConfiguration {
    fn connectors(&self) -> u8 {
        super::configuration::CONNECTOR_COUNT
    }

    fn is_male(&self, connector: u8) -> bool {
        connector == FRONT
    }

    /// The front face turns against the body: side 0; the back face is on the body, side 1.
    fn side(&self, connector: u8) -> usize {
        usize::from(connector != FRONT)
    }

    fn len(&self) -> usize {
        self.cubes.len()
    }

    fn name(&self, m: usize) -> Option<&str> {
        self.cubes.get(m).map(|c| c.name.as_str())
    }

    fn id(&self, m: usize) -> Option<u32> {
        self.cubes.get(m).and_then(|c| c.id)
    }

    fn index(&self, name: &str) -> Option<usize> {
        self.module_index(name)
    }

    fn index_by_id(&self, id: u32) -> Option<usize> {
        self.cubes.iter().position(|c| c.id == Some(id))
    }

    fn joint(&self, m: usize, _joint: u8) -> Option<i64> {
        self.cubes.get(m).map(|c| i64::from(c.hinge))
    }

    fn latched_to(&self, port: Port) -> Option<Port> {
        self.latched(port)
    }

    fn facing(&self, port: Port) -> Option<Port> {
        self.touching(port)
    }

    /// A cube talks through a latch or, unlatched, from its front face to the free back face
    /// it touches.
    fn link_target(&self, port: Port) -> Option<Port> {
        dynarole_world::latched_or_male_to_free_female(self, port)
    }

    fn port_name(&self, port: Port) -> String {
        self.port_label(port)
    }
}

/// A chain of hinged cubes being reconfigured.
#[derive(Clone, Debug, PartialEq)]
pub struct CubesWorld {
    config: CubesConfiguration,
}

impl CubesWorld {
    /// Starts from a validated configuration.
    pub fn new(config: CubesConfiguration) -> CubesWorld {
        CubesWorld { config }
    }

    fn known(&self, module: &str) -> Result<usize, OpError> {
        self.config
            .module_index(module)
            .ok_or_else(|| OpError::UnknownModule {
                module: module.to_string(),
            })
    }

    /// The male port `connector` of `module`; the back one and others are refused.
    fn male_port(
        &self,
        module: &str,
        connector: u8,
        action: &'static str,
    ) -> Result<Port, OpError> {
        let m = self.known(module)?;
        match connector {
            FRONT => Ok(port(m, FRONT)),
            BACK => Err(OpError::FemaleConnector {
                port: self.config.port_label(port(m, BACK)),
                action,
            }),
            _ => Err(OpError::NoSuchConnector {
                module: module.to_string(),
                connector,
                count: 2,
            }),
        }
    }

    fn latch(&mut self, module: &str, connector: u8) -> Result<Outcome, OpError> {
        let male = self.male_port(module, connector, "latch")?;
        let config = &self.config;
        if let Some(partner) = config.latched(male) {
            return Ok(warning(Warning::AlreadyLatched {
                port: config.port_label(male),
                partner: config.port_label(partner),
            }));
        }
        let female = (config.touching(male))
            .filter(|p| p.connector == BACK && config.latched(*p).is_none())
            .ok_or_else(|| OpError::NothingToLatchOnto {
                port: config.port_label(male),
                reason: "no free back connector faces it".into(),
            })?;
        self.config.latches.insert((male, female));
        Ok(Outcome::default())
    }

    fn unlatch(&mut self, module: &str, connector: u8) -> Result<Outcome, OpError> {
        let male = self.male_port(module, connector, "unlatch")?;
        match self.config.latched(male) {
            Some(female) => {
                self.config.latches.remove(&(male, female));
                Ok(Outcome::default())
            }
            None => Ok(warning(Warning::NothingLatched {
                port: self.config.port_label(male),
            })),
        }
    }

    /// Cubes reachable from `start` through every latch but `except`.
    fn reachable(&self, start: usize, except: (Port, Port)) -> BTreeSet<usize> {
        let mut seen = BTreeSet::from([start]);
        let mut todo = vec![start];
        while let Some(m) = todo.pop() {
            for (a, b) in self.config.latches.iter().filter(|l| **l != except) {
                let other = match (a.module == m, b.module == m) {
                    (true, _) => b.module,
                    (_, true) => a.module,
                    _ => continue,
                };
                if seen.insert(other) {
                    todo.push(other);
                }
            }
        }
        seen
    }

    /// The cubes a turn of `m`'s hinge carries and the signed angle; checks the angles and
    /// that no loop locks the hinge.
    fn plan(
        &self,
        m: usize,
        from: i64,
        to: i64,
        up: bool,
    ) -> Result<(BTreeSet<usize>, i32), OpError> {
        let cube = &self.config.cubes[m];
        let name = cube.name.clone();
        if ![-90, 0, 90].contains(&to) || (to != from && (to > from) != up) {
            return Err(OpError::InvalidAngle {
                module: name,
                angle: angle(to),
                reason: "a hinge turns between -90 and 90, in the direction of `up`".into(),
            });
        }
        if i64::from(cube.hinge) != from {
            return Err(OpError::WrongStartAngle {
                module: name,
                from: angle(from),
                actual: cube.hinge,
            });
        }
        let turn = angle(to - from);
        let Some(beyond) = self.config.latched(port(m, FRONT)) else {
            return Ok((BTreeSet::new(), turn));
        };
        let carried = self.reachable(beyond.module, (port(m, FRONT), beyond));
        if carried.contains(&m) {
            let loop_modules = carried.iter().map(|i| self.config.cubes[*i].name.clone());
            return Err(OpError::JointLocked {
                module: name,
                loop_modules: loop_modules.collect(),
            });
        }
        Ok((carried, turn))
    }

    fn bend(&mut self, m: usize, from: i64, to: i64, up: bool) -> Result<Outcome, OpError> {
        let (carried, turn) = self.plan(m, from, to, up)?;
        let pivot = self.config.cubes[m].cell;
        let mut next = self.config.clone();
        next.cubes[m].hinge = angle(to);
        for i in &carried {
            let cube = &mut next.cubes[*i];
            cube.cell = plus(pivot, turned(minus(cube.cell, pivot), turn));
            cube.heading = turned(cube.heading, turn);
        }
        let cells: BTreeSet<Cell> = next.cubes.iter().map(|c| c.cell).collect();
        if cells.len() < next.cubes.len() {
            return Err(OpError::NothingToLatchOnto {
                port: self.config.port_label(port(m, FRONT)),
                reason: "the turn would put two cubes on one cell".into(),
            });
        }
        self.config = next;
        let moved = carried.iter().map(|i| self.config.cubes[*i].name.clone());
        Ok(Outcome {
            moved: moved.collect(),
            ..Outcome::default()
        })
    }
}

impl RobotModel for CubesWorld {
    fn robot(&self) -> &str {
        super::NAME
    }

    fn shape(&self) -> &dyn RobotShape {
        &self.config
    }

    fn apply(&mut self, module: &str, action: &Action) -> Result<Outcome, OpError> {
        match *action {
            Action::Extend { connector } => self.latch(module, connector),
            Action::Retract { connector } => self.unlatch(module, connector),
            Action::Turn {
                from,
                to,
                increasing,
                ..
            } => {
                let m = self.known(module)?;
                let from = from.unwrap_or(i64::from(self.config.cubes[m].hinge));
                self.bend(m, from, to, increasing)
            }
            Action::Move { .. } => Err(action.unsupported(module)),
        }
    }

    fn motion(&self, module: &str, action: &Action) -> Option<Motion> {
        let m = self.config.module_index(module)?;
        let Action::Turn {
            from,
            to,
            increasing,
            ..
        } = *action
        else {
            if matches!(action, Action::Move { .. }) {
                return None;
            }
            // A latch moves inside its face: nothing the sweep or the drawing sees.
            return Some(Motion::in_place());
        };
        let from = from.unwrap_or(i64::from(self.config.cubes[m].hinge));
        let (carried, turn) = self.plan(m, from, to, increasing).ok()?;
        let point = |c: Cell| [f64::from(c[0]), f64::from(c[1]), 0.0];
        let mut motion = Motion::turn(
            point(self.config.cubes[m].cell),
            [0, 0, 1],
            f64::from(turn),
            1.0,
        );
        for cube in carried.iter().map(|i| &self.config.cubes[*i]) {
            motion.moving.push((cube.name.clone(), point(cube.cell)));
            let whole = Carried {
                module: cube.name.clone(),
                part: None,
            };
            motion.carried.push(whole);
        }
        if turn != 0 {
            // The hinged front face (part 0) turns with what it carries.
            let face = Carried {
                module: module.to_string(),
                part: Some(0),
            };
            motion.carried.push(face);
        }
        Some(motion)
    }

    fn quarter_turns(&self, from: i64, to: i64, _increasing: bool) -> u64 {
        (to - from).unsigned_abs().div_ceil(90)
    }

    fn length_unit(&self) -> &str {
        "cube edges"
    }

    fn configuration(&self) -> Option<Configuration> {
        Some(Configuration::new(self.config.clone()))
    }

    fn into_configuration(self: Box<Self>) -> Option<Configuration> {
        Some(Configuration::new(self.config))
    }

    fn difference(&self, other: &dyn RobotModel) -> Option<String> {
        model_difference(self, other)
    }

    fn clone_model(&self) -> Box<dyn RobotModel> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
