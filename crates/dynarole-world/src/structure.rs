//! What the configurations of robots built of modules and latches share: modules in file order, the latches between
//! them, their validation, and the compact indices that keep look-ups by name and id
//! logarithmic and by port constant.

use crate::common::{ConfigError, Latch, NamedConnection, Port};
use std::collections::{BTreeMap, BTreeSet};

/// What the shared code needs to know about one robot's modules and connector rules.
pub trait RobotModule: Sized {
    /// The robot's name in messages.
    const ROBOT: &'static str;
    /// Connectors per module, numbered from 0.
    const CONNECTOR_COUNT: u8;
    /// What a latch needs at the other end, as said in messages.
    const FEMALE_CONNECTOR: &'static str;

    /// The module's label.
    fn name(&self) -> &str;

    /// The module's numeric ID, if given.
    fn id(&self) -> Option<u32>;

    /// True for the connectors that can be commanded to latch and release.
    fn is_male(connector: u8) -> bool;

    /// True for the connectors on the north side of the module's joints, the side that
    /// turns against the others.
    fn is_north_side(connector: u8) -> bool;

    /// Why a connection between two male (`both_male`) or two female connectors is wrong.
    fn same_gender_message(label_a: &str, label_b: &str, both_male: bool) -> String;

    /// Checks that the two ends of a connection (ports and their labels) face each other.
    fn check_facing(
        modules: &[Self],
        path: &str,
        a: (Port, &str),
        b: (Port, &str),
    ) -> Result<(), ConfigError>;
}

/// The queries every robot's configuration answers alike, from its `metadata` and
/// `structure` fields. Expanded inside each configuration's own `impl` (with its module
/// type), so that they stay inherent methods and callers need no trait in scope.
#[macro_export]
macro_rules! configuration_queries {
    ($module:ty) => {
        /// The descriptive fields.
        pub fn metadata(&self) -> &$crate::common::Metadata {
            &self.metadata
        }

        /// Modules in file order (the order never changes).
        pub fn modules(&self) -> &[$module] {
            self.structure.modules()
        }

        /// The module at `index`.
        pub fn module(&self, index: usize) -> Option<&$module> {
            self.structure.module(index)
        }

        /// Index of the module called `name`.
        pub fn module_index(&self, name: &str) -> Option<usize> {
            self.structure.module_index(name)
        }

        /// Index of the module with numeric ID `id`.
        pub fn module_index_by_id(&self, id: u32) -> Option<usize> {
            self.structure.module_index_by_id(id)
        }

        /// The latches, ordered by male port.
        pub fn latches(&self) -> &std::collections::BTreeSet<$crate::common::Latch> {
            self.structure.latches()
        }

        /// `M3.C4` for a port.
        pub fn port_name(&self, port: $crate::common::Port) -> String {
            self.structure.port_name(port)
        }

        /// The port latched to `port`, if any.
        pub fn latched_to(&self, port: $crate::common::Port) -> Option<$crate::common::Port> {
            self.structure.latched_to(port)
        }

        /// True when `port` is latched.
        pub fn is_latched(&self, port: $crate::common::Port) -> bool {
            self.latched_to(port).is_some()
        }

        /// The latches as names, male first, in latch order.
        pub fn named_connections(&self) -> Vec<$crate::common::NamedConnection> {
            self.structure.named_connections()
        }
    };
}

/// Modules and latches, with indices by name, id and port. The indices only follow from the
/// modules and latches, so comparing them too (derived `PartialEq`) changes no answer. They
/// are compact (a simulated robot may have a million modules): a name is stored once, in
/// its module, and a port is one u32.
#[derive(Clone, PartialEq)]
pub struct Structure<M> {
    modules: Vec<M>,
    latches: BTreeSet<Latch>,
    /// Module indices in name order (names are unique), searched by bisection.
    by_name: Vec<u32>,
    by_id: BTreeMap<u32, usize>,
    /// Both ends of every latch, each mapped to the other: the entry of port p is
    /// `partners[packed(p)]`, the packed port latched to it or `FREE`.
    partners: Vec<u32>,
}

/// A `partners` entry of a connector that is not latched.
const FREE: u32 = u32::MAX;

impl<M: RobotModule> Structure<M> {
    /// Most modules a configuration can have: every port packs into a u32 below `FREE`.
    fn max_modules() -> usize {
        (FREE / u32::from(M::CONNECTOR_COUNT)) as usize
    }

    /// Modules without latches, after checking that names are non-empty and unique and that
    /// given ids are unique.
    pub fn new(modules: Vec<M>) -> Result<Structure<M>, ConfigError> {
        if modules.len() > Self::max_modules() {
            return Err(ConfigError::new(
                "modules",
                format!(
                    "{} modules; at most {} are supported",
                    modules.len(),
                    Self::max_modules()
                ),
            ));
        }
        let mut names = BTreeMap::new();
        let mut by_id = BTreeMap::new();
        for (i, m) in modules.iter().enumerate() {
            let name = m.name();
            if name.is_empty() {
                return Err(ConfigError::new(format!("modules[{i}].name"), "empty name"));
            }
            if let Some(j) = names.insert(name, i) {
                return Err(ConfigError::new(
                    format!("modules[{i}].name"),
                    format!("duplicate module name \"{name}\" (also modules[{j}])"),
                ));
            }
            if let Some(id) = m.id() {
                if let Some(j) = by_id.insert(id, i) {
                    return Err(ConfigError::new(
                        format!("modules[{i}].id"),
                        format!("duplicate module id {id} (also modules[{j}])"),
                    ));
                }
            }
        }
        // In name order, as `names` holds them (fits: checked against max_modules above).
        let by_name = names.into_values().map(|i| i as u32).collect();
        let partners = vec![FREE; modules.len() * usize::from(M::CONNECTOR_COUNT)];
        Ok(Structure {
            modules,
            latches: BTreeSet::new(),
            by_name,
            by_id,
            partners,
        })
    }

    /// Where `port`'s entry is in `partners` (`None` for a port of no module).
    fn packed(&self, port: Port) -> Option<usize> {
        (port.module < self.modules.len() && port.connector < M::CONNECTOR_COUNT)
            .then(|| port.module * usize::from(M::CONNECTOR_COUNT) + usize::from(port.connector))
    }

    /// The port of a `partners` value.
    fn unpacked(value: u32) -> Option<Port> {
        let connectors = u32::from(M::CONNECTOR_COUNT);
        (value != FREE).then(|| Port {
            module: (value / connectors) as usize,
            connector: (value % connectors) as u8,
        })
    }

    /// Latches `a` to `b` (or frees `a` when `b` is `None`) in `partners`.
    fn set_partner(&mut self, a: Port, b: Option<Port>) {
        // Fits in a u32 below FREE: the module count is checked in `new`.
        let value = b.and_then(|p| self.packed(p)).map_or(FREE, |v| v as u32);
        if let Some(slot) = self.packed(a).and_then(|k| self.partners.get_mut(k)) {
            *slot = value;
        }
    }

    /// Resolves, checks and latches every connection: known modules, connectors in range, one
    /// male and one female end, the two connectors facing each other, no connector used twice.
    pub fn connect_all(&mut self, connections: &[NamedConnection]) -> Result<(), ConfigError> {
        let mut used: BTreeMap<Port, usize> = BTreeMap::new();
        for (k, (name_a, conn_a, name_b, conn_b)) in connections.iter().enumerate() {
            let path = format!("connections[{k}]");
            let a = self.resolve(k, 0, name_a, *conn_a)?;
            let b = self.resolve(k, 2, name_b, *conn_b)?;
            let (la, lb) = (format!("{name_a}.C{conn_a}"), format!("{name_b}.C{conn_b}"));
            let latch = male_and_female::<M>(&path, (a, &la), (b, &lb))?;
            M::check_facing(&self.modules, &path, (a, &la), (b, &lb))?;
            for (port, index, label) in [(a, 1, &la), (b, 3, &lb)] {
                if let Some(j) = used.insert(port, k) {
                    return Err(ConfigError::new(
                        format!("connections[{k}][{index}]"),
                        format!("connector {label} is already used by connections[{j}]"),
                    ));
                }
            }
            self.latch(latch);
        }
        Ok(())
    }

    /// Finds the module of a connection end; `field` is 0 or 2 (module name position in the
    /// array).
    fn resolve(
        &self,
        k: usize,
        field: usize,
        name: &str,
        connector: u8,
    ) -> Result<Port, ConfigError> {
        let module = self.module_index(name).ok_or_else(|| {
            ConfigError::new(
                format!("connections[{k}][{field}]"),
                format!("unknown module \"{name}\""),
            )
        })?;
        if connector >= M::CONNECTOR_COUNT {
            return Err(ConfigError::new(
                format!("connections[{k}][{}]", field + 1),
                format!(
                    "connector {connector} does not exist; {} connectors are 0-{}",
                    M::ROBOT,
                    M::CONNECTOR_COUNT - 1
                ),
            ));
        }
        Ok(Port { module, connector })
    }

    /// Modules in file order.
    pub fn modules(&self) -> &[M] {
        &self.modules
    }

    /// The module at `index`.
    pub fn module(&self, index: usize) -> Option<&M> {
        self.modules.get(index)
    }

    /// The module at `index`, to change its pose or joints (never its name or id, which the
    /// indices were built from).
    pub fn module_mut(&mut self, index: usize) -> Option<&mut M> {
        self.modules.get_mut(index)
    }

    /// Index of the module called `name`.
    pub fn module_index(&self, name: &str) -> Option<usize> {
        let name_of = |i: &u32| self.modules.get(*i as usize).map_or("", |m| m.name());
        let k = self
            .by_name
            .binary_search_by(|i| name_of(i).cmp(name))
            .ok()?;
        self.by_name.get(k).map(|i| *i as usize)
    }

    /// Index of the module with numeric ID `id`.
    pub fn module_index_by_id(&self, id: u32) -> Option<usize> {
        self.by_id.get(&id).copied()
    }

    /// The label of the module at `index` (empty when there is none).
    pub fn module_name(&self, index: usize) -> String {
        self.modules
            .get(index)
            .map_or_else(String::new, |m| m.name().to_string())
    }

    /// The labels of the modules at `indices`, in index order.
    pub fn module_names(&self, indices: &BTreeSet<usize>) -> Vec<String> {
        indices.iter().map(|i| self.module_name(*i)).collect()
    }

    /// The latches, ordered by male port.
    pub fn latches(&self) -> &BTreeSet<Latch> {
        &self.latches
    }

    /// The port latched to `port`, if any.
    pub fn latched_to(&self, port: Port) -> Option<Port> {
        let value = self.packed(port).and_then(|k| self.partners.get(k))?;
        Self::unpacked(*value)
    }

    /// Adds a latch (the caller has checked that both ends are free).
    pub fn latch(&mut self, latch: Latch) {
        self.latches.insert(latch);
        self.set_partner(latch.male, Some(latch.female));
        self.set_partner(latch.female, Some(latch.male));
    }

    /// Removes a latch, if present.
    pub fn unlatch(&mut self, latch: Latch) {
        if self.latches.remove(&latch) {
            self.set_partner(latch.male, None);
            self.set_partner(latch.female, None);
        }
    }

    /// `M3.C4` for a port (`?` for an unknown module).
    pub fn port_name(&self, port: Port) -> String {
        let name = self.modules.get(port.module).map_or("?", |m| m.name());
        format!("{name}.C{}", port.connector)
    }

    /// The latches as names, male first, in latch order.
    pub fn named_connections(&self) -> Vec<NamedConnection> {
        let name = |p: Port| self.module_name(p.module);
        self.latches
            .iter()
            .map(|l| {
                (
                    name(l.male),
                    l.male.connector,
                    name(l.female),
                    l.female.connector,
                )
            })
            .collect()
    }
}

/// The latch between two ends of a connection, which must be on two modules and of opposite
/// genders.
fn male_and_female<M: RobotModule>(
    path: &str,
    (a, la): (Port, &str),
    (b, lb): (Port, &str),
) -> Result<Latch, ConfigError> {
    if a.module == b.module {
        return Err(ConfigError::new(path, "a module cannot latch onto itself"));
    }
    match (M::is_male(a.connector), M::is_male(b.connector)) {
        (true, false) => Ok(Latch { male: a, female: b }),
        (false, true) => Ok(Latch { male: b, female: a }),
        (both_male, _) => Err(ConfigError::new(
            path,
            M::same_gender_message(la, lb, both_male),
        )),
    }
}
