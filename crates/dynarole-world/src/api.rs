//! The robot API: the traits a robot's folder (`robots/NAME/`) implements, and nothing outside
//! it needs more. [`RobotKind`] is the kind (its name, plugin, data files, drawing);
//! [`RobotConfiguration`] one of its validated configurations, held opaque by
//! [`Configuration`]; [`RobotModel`] the robot being reconfigured (doing an `Action`, the
//! [`Motion`] of an action). Reading a file is [`crate::Robots::read_configuration`].

use crate::common::{ConfigError, Metadata, NamedConnection};
use crate::drawing::Drawing;
use crate::drawing::ModulePose;
use crate::geometry::{Rotation, Vec3};
use crate::motion::Motion;
use crate::ops::{OpError, Outcome};
use crate::rigid::Shape;
use crate::shape::{Action, RobotShape};
use std::any::Any;
use std::fmt;

/// What turns done together do, over every relative timing, as a robot's own check says
/// (`RobotModel::turns_together`). Modules are indices.
#[derive(Clone, Debug, PartialEq)]
pub enum GroupVerdict {
    /// Every two parts stay the motions' limit apart.
    Clear,
    /// For some timing, parts of these two modules come this close (under the limit).
    Closest {
        distance: f64,
        modules: (usize, usize),
    },
    /// Not proven within the check's bound: the least distance it proved.
    Unproven {
        distance: f64,
        modules: (usize, usize),
    },
    /// Refused by a rule of the robot's own (a lattice robot's parallel-move rules: one mover
    /// the other's support, cells claimed twice), in words that finish "done at the same
    /// time, ...", naming the two modules it is about.
    Refused {
        modules: (usize, usize),
        reason: String,
    },
}

/// Everything the tree asks of a robot kind that is not about one configuration.
pub trait RobotKind: Send + Sync + 'static {
    /// The plugin name a program gives in `robot NAME;`.
    fn name(&self) -> &'static str;
    /// The value of the `robot` field of its data files.
    fn file_tag(&self) -> &'static str;
    /// Its API plugin: the file name and the TOML text (operations, arguments, reversal).
    fn plugin(&self) -> (&'static str, &'static str);
    /// Reads and validates one of its data files (the `robot` field already matched).
    fn read_configuration(&self, text: &str) -> Result<Configuration, ConfigError>;
    /// How its modules look (the parts of [`crate::ModulePose`]).
    fn drawing(&self) -> Drawing;
    /// The emulated boards its modules' firmware runs on (`simulate --firmware`): `avr` is the
    /// hemisphere board of `runtime/avr`. None by default.
    fn firmware_boards(&self) -> &'static [&'static str] {
        &[]
    }
    /// Its network presets, the default first (none: the simulator's own default).
    fn network_presets(&self) -> &'static [NetworkPreset] {
        &[]
    }
    /// The JSON Schema (draft 2020-12) of its data files, the text of the schema file in its
    /// folder: their structure, with the checks a schema cannot express left to
    /// `read_configuration`. None by default.
    fn schema(&self) -> Option<&'static str> {
        None
    }
    /// Reads a configuration in a format of the robot's own tools, recognised by its content
    /// (a file without dynarole's `robot` field); `None` when the text is in none of them.
    fn read_native(&self, text: &str) -> Option<Result<Configuration, ConfigError>> {
        let _ = text;
        None
    }
    /// Reads a plan of the robot's own planners (a list of configurations, recognised by its
    /// content) into a program whose one sequence, `sequence`, goes through it; `None` when the
    /// text is no plan of this robot's.
    fn import_plan(
        &self,
        text: &str,
        sequence: &str,
        options: &ImportOptions,
    ) -> Option<Result<ImportedPlan, PlanError>> {
        let _ = (text, sequence, options);
        None
    }
    /// The plan formats `import_plan` reads, in words, for messages (none by default).
    fn plan_formats(&self) -> Option<&'static str> {
        None
    }
    /// The formats of its own tools `export_plan` writes, by the name `dynarole export` takes
    /// (none by default).
    fn export_formats(&self) -> &'static [&'static str] {
        &[]
    }
    /// A sequence written in its tools' format `format` (one of `export_formats`); the error
    /// is why the sequence has no such form. `None` for a format it does not write.
    fn export_plan(&self, format: &str, plan: &PlanToExport<'_>) -> Option<Result<String, String>> {
        let _ = (format, plan);
        None
    }
}

/// A sequence to write in a robot's tools' format (`dynarole export`): its parallel groups in
/// order, each the operations of its modules (by name) done at the same time, from `from`.
#[derive(Clone, Copy, Debug)]
pub struct PlanToExport<'a> {
    /// What the plan is called (the sequence's name).
    pub title: &'a str,
    /// Where it says it came from (the program's file).
    pub description: &'a str,
    pub from: &'a Configuration,
    pub sets: &'a [Vec<(String, crate::Action)>],
}

/// How `dynarole import` reads a plan, beyond its text.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ImportOptions {
    /// The plan's module groups that are a fixed ground that never moves (a lattice
    /// planner's static modules, `--ground G`). A plan whose format has no groups refuses
    /// any.
    pub ground: Vec<i64>,
}

/// A planner's plan as a program (`dynarole import`).
#[derive(Clone, Debug)]
pub struct ImportedPlan {
    /// The format the plan was recognised as, in words.
    pub format: &'static str,
    /// The program's text: `robot NAME;` and the one sequence.
    pub program: String,
    /// The plan's first configuration and its last.
    pub from: Configuration,
    pub expect: Configuration,
    /// One line per step, in order, as the command prints them.
    pub steps: Vec<String>,
}

/// Why a plan is refused: where in the file (1-based line and column), and why (naming the
/// configuration by its index from 0).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlanError {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl fmt::Display for PlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}, column {}: {}",
            self.line, self.column, self.message
        )
    }
}

impl std::error::Error for PlanError {}

/// How a robot's transceivers and clocks behave in the simulator, under a name a scenario
/// gives as `network.preset`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NetworkPreset {
    pub name: &'static str,
    /// One half-duplex transceiver per side of a module (`RobotShape::side`), shared by the
    /// side's connectors, so that packets heard at once collide; otherwise a full-duplex
    /// channel per connector.
    pub half_duplex_sides: bool,
    /// Modules power on at uniformly random instants in the first this many microseconds
    /// (0: all at once).
    pub power_on_spread_us: u64,
    /// Broadcast jitter compiled into the runtime (`DR_CONF_BROADCAST_JITTER_MS`).
    pub jitter_ms: u32,
}

/// What a robot's validated configuration answers, whatever the robot. Each robot kind
/// implements it for its configuration type (the `robot_configuration!` macro does it from
/// the type's inherent methods).
pub trait RobotConfiguration: fmt::Debug + Send + Sync + Any {
    /// The robot kind this is a configuration of.
    fn kind(&self) -> &'static dyn RobotKind;
    /// The descriptive fields.
    fn metadata(&self) -> &Metadata;
    /// The questions every command asks of a configuration.
    fn shape(&self) -> &dyn RobotShape;
    /// One line per module, in file order (a command's printed final configuration).
    fn module_lines(&self) -> Vec<String>;
    /// The configuration as rigid bodies (`compare.rs`).
    fn rigid_shape(&self) -> Shape;
    /// The latches as names, male first, in latch order.
    fn named_connections(&self) -> Vec<NamedConnection>;
    /// Every module's parts and connectors placed, by module index (what is drawn).
    fn poses(&self) -> Vec<ModulePose>;
    /// The whole configuration turned by `rotation` and shifted by `translation` (in the
    /// file's position unit). Fails when the result leaves the robot's lattice.
    fn transformed(
        &self,
        rotation: Rotation,
        translation: Vec3,
    ) -> Result<Configuration, ConfigError>;
    /// The configuration in its robot's data-file format, redundant fields included.
    fn to_json_string(&self) -> String;
    /// The robot model that starts from this configuration.
    fn into_model(self: Box<Self>) -> Box<dyn RobotModel>;
    /// A copy.
    fn clone_box(&self) -> Box<dyn RobotConfiguration>;
    /// Whether `other` is the same configuration of the same robot.
    fn same_as(&self, other: &dyn RobotConfiguration) -> bool;
    /// This configuration as `Any`, for the robot's own code to recover its type.
    fn as_any(&self) -> &dyn Any;
}

/// A validated configuration of some robot kind.
pub struct Configuration(Box<dyn RobotConfiguration>);

impl Configuration {
    /// Wraps a robot's own configuration.
    pub fn new(config: impl RobotConfiguration) -> Configuration {
        Configuration(Box::new(config))
    }

    /// The robot kind.
    pub fn kind(&self) -> &'static dyn RobotKind {
        self.0.kind()
    }

    /// The robot's own configuration, if it is a `T` (for the robot's folder and its tests).
    pub fn downcast_ref<T: RobotConfiguration>(&self) -> Option<&T> {
        self.0.as_any().downcast_ref::<T>()
    }

    /// The descriptive fields.
    pub fn metadata(&self) -> &Metadata {
        self.0.metadata()
    }

    /// The questions every command asks of a configuration.
    pub fn shape(&self) -> &dyn RobotShape {
        self.0.shape()
    }

    /// One line per module, in file order, as the robot summarises its modules.
    pub fn module_lines(&self) -> Vec<String> {
        self.0.module_lines()
    }

    /// The configuration as rigid bodies, as its robot reduces it (`compare.rs`).
    pub(crate) fn rigid_shape(&self) -> Shape {
        self.0.rigid_shape()
    }

    /// The latches as names, male first, in latch order.
    pub fn named_connections(&self) -> Vec<NamedConnection> {
        self.0.named_connections()
    }

    /// How another configuration is compared with this one, for messages: `in place` (a
    /// lattice robot's cells) or `up to rigid motion`.
    pub fn equality(&self) -> &'static str {
        if self.0.rigid_shape().anchored {
            "in place"
        } else {
            "up to rigid motion"
        }
    }

    /// Every module's parts and connectors placed, by module index.
    pub fn poses(&self) -> Vec<ModulePose> {
        self.0.poses()
    }

    /// The whole configuration turned by `rotation` and shifted by `translation` (in the file's
    /// position unit). Fails when the result leaves the robot's lattice.
    pub fn transformed(
        &self,
        rotation: Rotation,
        translation: Vec3,
    ) -> Result<Configuration, ConfigError> {
        self.0.transformed(rotation, translation)
    }

    /// Writes the configuration in its robot's data-file format, redundant fields included.
    pub fn to_json_string(&self) -> String {
        self.0.to_json_string()
    }

    /// The robot model that starts from this configuration.
    pub fn into_model(self) -> Box<dyn RobotModel> {
        self.0.into_model()
    }
}

impl Clone for Configuration {
    fn clone(&self) -> Configuration {
        Configuration(self.0.clone_box())
    }
}

impl PartialEq for Configuration {
    fn eq(&self, other: &Configuration) -> bool {
        self.0.same_as(other.0.as_ref())
    }
}

impl fmt::Debug for Configuration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

/// A robot being reconfigured: the configuration it has now, and what an action does to it.
/// Every action either succeeds (possibly with warnings) and leaves a valid configuration, or
/// fails and changes nothing.
pub trait RobotModel: fmt::Debug + Send + Sync {
    /// The name of the robot plugin this model is for: a sequence written for
    /// another robot is refused.
    fn robot(&self) -> &str;
    /// The current configuration's answers.
    fn shape(&self) -> &dyn RobotShape;
    /// Does `action` on `module` (a name); the error is why the robot cannot.
    fn apply(&mut self, module: &str, action: &Action) -> Result<Outcome, OpError>;
    /// Does `action` like [`RobotModel::apply`], its sweep checked as `sweep` says; every
    /// other check (angles, locks, connectivity) is the same. The default checks the sweep
    /// alone whatever `sweep` says: a robot that does not implement this refuses lock-step
    /// turns that clear only together, never accepts a collision.
    fn apply_swept(
        &mut self,
        module: &str,
        action: &Action,
        sweep: crate::SweepCheck,
    ) -> Result<Outcome, OpError> {
        let _ = sweep;
        self.apply(module, action)
    }
    /// The motion `action` would make, without doing it: a turn's legs, what it carries and
    /// its sweep's points; a connector's extend or retract moves in place
    /// ([`Motion::in_place`]). `None` for an action refused before anything moves (a wrong
    /// angle, a locked joint, an unknown module).
    fn motion(&self, module: &str, action: &Action) -> Option<Motion>;
    /// Quarter turns (rounded up) a joint passes through from `from` to `to` in the given
    /// direction: what a turn's duration is counted in.
    fn quarter_turns(&self, from: i64, to: i64, increasing: bool) -> u64;
    /// The unit of the positions and distances of its turn motions, for messages
    /// (`lattice units`).
    fn length_unit(&self) -> &str;
    /// Module centres, when a turn always moves whole modules about their joints, so that two
    /// turns with disjoint moving sides commute; `None` when it moves parts of modules or
    /// the robot does not say.
    fn rigid_module_centres(&self) -> Option<Vec<[f64; 3]>> {
        None
    }
    /// Every point of the robot its sweeps are checked with, with its module's index: the
    /// points a motion's `moving` lists are among these (whole modules' centres by default,
    /// from `rigid_module_centres`; a robot of blocks gives its blocks). `None`: the robot
    /// does not say.
    fn sweep_points(&self) -> Option<Vec<(usize, [f64; 3])>> {
        let centres = self.rigid_module_centres()?;
        Some(centres.into_iter().enumerate().collect())
    }
    /// The robot's own check of turns (or any operations that move: a lattice robot's moves)
    /// done together, each a motion this model gave (`motion`)
    /// with its module's index, over every relative timing (`skew` `None`) or in lock-step
    /// with their fractions at most `skew` apart (a synchronous group): for a robot whose
    /// turns the generic search over motions cannot link (parts of one module turned by two
    /// of its joints at once). `None` (the default) leaves it to that search.
    fn turns_together(
        &self,
        turns: &[(&Motion, usize)],
        skew: Option<f64>,
    ) -> Option<GroupVerdict> {
        let _ = (turns, skew);
        None
    }
    /// The configuration in the data-file format, for a robot that has one.
    fn configuration(&self) -> Option<Configuration>;
    /// The configuration moved out of the model at its end (no copy: a large robot's
    /// simulation ends with this).
    fn into_configuration(self: Box<Self>) -> Option<Configuration> {
        self.configuration()
    }
    /// How the configuration differs from `other`'s (equal up to rigid motion: `None`); the
    /// first line of the answer is a summary.
    fn difference(&self, other: &dyn RobotModel) -> Option<String>;
    /// A copy, to try actions on.
    fn clone_model(&self) -> Box<dyn RobotModel>;
    /// The network presets of its robot kind, the default first (`RobotKind::network_presets`).
    fn network_presets(&self) -> &'static [NetworkPreset] {
        &[]
    }
    /// This model as `Any`, so that an implementation can recognise another of its kind.
    fn as_any(&self) -> &dyn Any;
}

impl Clone for Box<dyn RobotModel> {
    fn clone(&self) -> Self {
        self.clone_model()
    }
}

/// `impl RobotConfiguration` for a robot's configuration type `$config` of kind `$kind` (a
/// static), from the inherent methods every robot's configuration has (`metadata`,
/// `module_lines`, `rigid_shape`, `named_connections`, `transformed` returning `$config`,
/// `to_json_string`, `poses`) and `$model(config)`, the model that starts from it.
#[macro_export]
macro_rules! robot_configuration {
    ($config:ty, $kind:path, $model:path) => {
        impl $crate::RobotConfiguration for $config {
            fn kind(&self) -> &'static dyn $crate::RobotKind {
                &$kind
            }

            fn metadata(&self) -> &$crate::Metadata {
                <$config>::metadata(self)
            }

            fn shape(&self) -> &dyn $crate::RobotShape {
                self
            }

            fn module_lines(&self) -> Vec<String> {
                <$config>::module_lines(self)
            }

            fn rigid_shape(&self) -> $crate::rigid::Shape {
                <$config>::rigid_shape(self)
            }

            fn named_connections(&self) -> Vec<$crate::NamedConnection> {
                <$config>::named_connections(self)
            }

            fn poses(&self) -> Vec<$crate::ModulePose> {
                <$config>::poses(self)
            }

            fn transformed(
                &self,
                rotation: $crate::Rotation,
                translation: $crate::Vec3,
            ) -> Result<$crate::Configuration, $crate::ConfigError> {
                <$config>::transformed(self, rotation, translation).map($crate::Configuration::new)
            }

            fn to_json_string(&self) -> String {
                <$config>::to_json_string(self)
            }

            fn into_model(self: Box<Self>) -> Box<dyn $crate::RobotModel> {
                Box::new($model(*self))
            }

            fn clone_box(&self) -> Box<dyn $crate::RobotConfiguration> {
                Box::new(self.clone())
            }

            fn same_as(&self, other: &dyn $crate::RobotConfiguration) -> bool {
                other.as_any().downcast_ref::<$config>() == Some(self)
            }

            fn as_any(&self) -> &dyn std::any::Any {
                self
            }
        }
    };
}
