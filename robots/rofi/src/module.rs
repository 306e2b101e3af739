//! A RoFI universal module and a configuration of them: three joints, six connectors by
//! index, the connections between connectors, checked as they are added (ids unique, both
//! modules known, each connector used once, alpha and beta within their range, gamma made
//! circular), so that a reader can name the line that breaks a rule.

use std::collections::BTreeMap;
use std::fmt;

/// Alpha and beta turn within ±90 degrees (RoFI's configuration rule; the hardware allows a
/// few degrees more, which plans never use).
pub const SHOE_JOINT_LIMIT_DEG: f64 = 90.0;

/// A module's joints, in the order of RoFI's HAL and its legacy code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Joint {
    /// Body A to shoe A, about the shoe's X axis, within ±90 degrees.
    Alpha = 0,
    /// Body B to shoe B, the same kind of joint.
    Beta = 1,
    /// Body A to body B, about the module's long axis: circular.
    Gamma = 2,
}

impl Joint {
    pub const ALL: [Joint; 3] = [Joint::Alpha, Joint::Beta, Joint::Gamma];

    pub fn name(self) -> &'static str {
        match self {
            Joint::Alpha => "alpha",
            Joint::Beta => "beta",
            Joint::Gamma => "gamma",
        }
    }
}

/// The two halves of a module, each a body and a shoe that carries three connectors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Side {
    A = 0,
    B = 1,
}

impl Side {
    /// Its name in RoFI's files.
    pub fn letter(self) -> &'static str {
        match self {
            Side::A => "A",
            Side::B => "B",
        }
    }

    pub fn other(self) -> Side {
        match self {
            Side::A => Side::B,
            Side::B => Side::A,
        }
    }
}

/// A connector's face on its shoe, as RoFI's legacy code and old text format number them
/// (RofiWorld uses the same numbers under swapped ±X names: only the numbers are used here).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Dock {
    /// The old format's `+X`.
    PlusX = 0,
    /// The old format's `-X`.
    MinusX = 1,
    /// The face away from the module's other half.
    MinusZ = 2,
}

impl Dock {
    pub const ALL: [Dock; 3] = [Dock::PlusX, Dock::MinusX, Dock::MinusZ];

    /// Its name in RoFI's old text format (RofiWorld's ±X names are these swapped).
    pub fn old_name(self) -> &'static str {
        match self {
            Dock::PlusX => "+X",
            Dock::MinusX => "-X",
            Dock::MinusZ => "-Z",
        }
    }
}

/// One of a module's six connectors: index 3 · side + dock.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Connector(u8);

impl Connector {
    pub const COUNT: u8 = 6;

    pub fn new(side: Side, dock: Dock) -> Connector {
        Connector(3 * side as u8 + dock as u8)
    }

    pub fn from_index(index: u8) -> Option<Connector> {
        (index < Connector::COUNT).then_some(Connector(index))
    }

    pub fn index(self) -> u8 {
        self.0
    }

    pub fn side(self) -> Side {
        if self.0 < 3 {
            Side::A
        } else {
            Side::B
        }
    }

    pub fn dock(self) -> Dock {
        Dock::ALL[usize::from(self.0 % 3)]
    }
}

impl fmt::Display for Connector {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// The quarter-turn twist of a connection about the connectors' shared axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Orientation {
    North = 0,
    East = 1,
    South = 2,
    West = 3,
}

impl Orientation {
    pub const ALL: [Orientation; 4] = [
        Orientation::North,
        Orientation::East,
        Orientation::South,
        Orientation::West,
    ];

    pub fn quarter_turns(self) -> u8 {
        self as u8
    }

    /// Its letter in RoFI's old text format.
    pub fn letter(self) -> &'static str {
        match self {
            Orientation::North => "N",
            Orientation::East => "E",
            Orientation::South => "S",
            Orientation::West => "W",
        }
    }
}

/// A module: its ID and joint angles in degrees (gamma in (−180, 180]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Module {
    pub id: u32,
    pub alpha: f64,
    pub beta: f64,
    pub gamma: f64,
}

impl Module {
    pub fn new(id: u32, alpha: f64, beta: f64, gamma: f64) -> Module {
        Module {
            id,
            alpha,
            beta,
            gamma,
        }
    }

    pub fn joint(&self, joint: Joint) -> f64 {
        match joint {
            Joint::Alpha => self.alpha,
            Joint::Beta => self.beta,
            Joint::Gamma => self.gamma,
        }
    }
}

/// A module's connector.
pub type Port = (u32, Connector);

/// Two connectors mated, with the twist between them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Connection {
    pub from: Port,
    pub orientation: Orientation,
    pub to: Port,
}

impl Connection {
    /// The same connection seen from its other end.
    pub fn reversed(self) -> Connection {
        Connection {
            from: self.to,
            orientation: self.orientation,
            to: self.from,
        }
    }
}

/// Why a module or a connection cannot be added.
#[derive(Clone, Debug, PartialEq)]
pub enum ConfigurationError {
    DuplicateModule(u32),
    UnknownModule(u32),
    ConnectorInUse(Port),
    /// A connection from a connector to itself.
    SameConnector(Port),
    /// Alpha or beta outside ±90 degrees.
    JointOutOfRange {
        module: u32,
        joint: Joint,
        degrees: f64,
    },
    /// An angle that is not a finite number.
    NotFinite {
        module: u32,
        joint: Joint,
    },
}

impl fmt::Display for ConfigurationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConfigurationError::DuplicateModule(id) => write!(f, "module {id} is declared twice"),
            ConfigurationError::UnknownModule(id) => {
                write!(f, "module {id} is not declared (before this line)")
            }
            ConfigurationError::ConnectorInUse((id, c)) => {
                write!(f, "connector {c} of module {id} is already connected")
            }
            ConfigurationError::SameConnector((id, c)) => {
                write!(f, "connector {c} of module {id} is connected to itself")
            }
            ConfigurationError::JointOutOfRange {
                module,
                joint,
                degrees,
            } => write!(
                f,
                "module {module}: {} is {degrees} degrees, outside -90..90",
                joint.name()
            ),
            ConfigurationError::NotFinite { module, joint } => {
                write!(f, "module {module}: {} is not a number", joint.name())
            }
        }
    }
}

/// Modules (by ID) and their connections, each rule checked as they are added.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RofiConfiguration {
    modules: BTreeMap<u32, Module>,
    connections: Vec<Connection>,
    /// Which connection holds each used connector.
    used: BTreeMap<Port, usize>,
}

impl RofiConfiguration {
    pub fn new() -> RofiConfiguration {
        RofiConfiguration::default()
    }

    /// The modules, then the connections, each added as by `add_module` and `connect`.
    pub fn from_parts(
        modules: &[Module],
        connections: &[Connection],
    ) -> Result<RofiConfiguration, ConfigurationError> {
        let mut config = RofiConfiguration::new();
        for module in modules {
            config.add_module(*module)?;
        }
        for connection in connections {
            config.connect(*connection)?;
        }
        Ok(config)
    }

    /// Adds a module; gamma is taken modulo 360 into (−180, 180].
    pub fn add_module(&mut self, module: Module) -> Result<(), ConfigurationError> {
        let id = module.id;
        if self.modules.contains_key(&id) {
            return Err(ConfigurationError::DuplicateModule(id));
        }
        for joint in Joint::ALL {
            if !module.joint(joint).is_finite() {
                return Err(ConfigurationError::NotFinite { module: id, joint });
            }
        }
        for joint in [Joint::Alpha, Joint::Beta] {
            let degrees = module.joint(joint);
            if degrees.abs() > SHOE_JOINT_LIMIT_DEG {
                return Err(ConfigurationError::JointOutOfRange {
                    module: id,
                    joint,
                    degrees,
                });
            }
        }
        let gamma = circular(module.gamma);
        self.modules.insert(id, Module { gamma, ..module });
        Ok(())
    }

    /// Adds a connection between two declared modules' free connectors.
    pub fn connect(&mut self, connection: Connection) -> Result<(), ConfigurationError> {
        for (id, _) in [connection.from, connection.to] {
            if !self.modules.contains_key(&id) {
                return Err(ConfigurationError::UnknownModule(id));
            }
        }
        if connection.from == connection.to {
            return Err(ConfigurationError::SameConnector(connection.from));
        }
        for port in [connection.from, connection.to] {
            if self.used.contains_key(&port) {
                return Err(ConfigurationError::ConnectorInUse(port));
            }
        }
        let index = self.connections.len();
        self.used.insert(connection.from, index);
        self.used.insert(connection.to, index);
        self.connections.push(connection);
        Ok(())
    }

    /// Removes the connection at `port` (either end), giving it back as seen from `port`.
    pub fn disconnect(&mut self, port: Port) -> Option<Connection> {
        let removed = self.connection_at(port)?;
        let kept: Vec<Connection> = (self.connections.iter())
            .filter(|c| c.from != port && c.to != port)
            .copied()
            .collect();
        self.connections.clear();
        self.used.clear();
        for c in kept {
            let index = self.connections.len();
            self.used.insert(c.from, index);
            self.used.insert(c.to, index);
            self.connections.push(c);
        }
        Some(removed)
    }

    /// Sets a joint of module `id` (gamma taken into (−180, 180]); false for an unknown module.
    pub fn set_joint(&mut self, id: u32, joint: Joint, degrees: f64) -> bool {
        let Some(module) = self.modules.get_mut(&id) else {
            return false;
        };
        match joint {
            Joint::Alpha => module.alpha = degrees,
            Joint::Beta => module.beta = degrees,
            Joint::Gamma => module.gamma = circular(degrees),
        }
        true
    }

    /// The modules in ID order.
    pub fn modules(&self) -> impl Iterator<Item = &Module> {
        self.modules.values()
    }

    pub fn module(&self, id: u32) -> Option<&Module> {
        self.modules.get(&id)
    }

    pub fn len(&self) -> usize {
        self.modules.len()
    }

    pub fn is_empty(&self) -> bool {
        self.modules.is_empty()
    }

    /// The connections in the order they were added.
    pub fn connections(&self) -> &[Connection] {
        &self.connections
    }

    /// The connection at `port`, seen from it, if any.
    pub fn connection_at(&self, port: Port) -> Option<Connection> {
        let c = self.connections[*self.used.get(&port)?];
        Some(if c.from == port { c } else { c.reversed() })
    }
}

/// An angle in degrees taken into (−180, 180] (an angle already there is kept exactly).
pub fn circular(degrees: f64) -> f64 {
    if degrees > -180.0 && degrees <= 180.0 {
        return degrees;
    }
    let wrapped = degrees.rem_euclid(360.0);
    if wrapped > 180.0 {
        wrapped - 360.0
    } else {
        wrapped
    }
}
