//! Equality of two configurations up to a rigid motion of the lattice (one of the 24 rotations
//! plus a translation), with a readable account of the differences under the best-matching
//! motion.

use crate::api::{Configuration, RobotModel};
use crate::geometry::{add, sub, Rotation, Vec3};
use crate::rigid::{Body, Shape};
use std::collections::BTreeMap;
use std::fmt;

/// A module whose pose differs under the chosen rigid motion.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Misplaced {
    /// The module.
    pub module: String,
    /// Where the first configuration puts it, mapped by the rigid motion (`[x, y, z] ORIENT`).
    pub first: String,
    /// Where the second configuration has it.
    pub second: String,
}

/// What the two compared configurations are, as the account of a difference names them: a
/// comparison against an expected result must not call the reached one "expected".
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Sides {
    /// Two configurations of equal standing: "the first" and "the second".
    #[default]
    FirstSecond,
    /// The expected configuration first, the one a run reached second.
    ExpectedReached,
}

impl Sides {
    /// The adjectives that name the first and the second configuration.
    fn names(self) -> (&'static str, &'static str) {
        match self {
            Sides::FirstSecond => ("first", "second"),
            Sides::ExpectedReached => ("expected", "reached"),
        }
    }
}

/// A joint that differs (joint angles do not depend on the rigid motion).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JointDifference {
    /// The module.
    pub module: String,
    /// Joint value(s) in the first configuration, in the unit of its robot's plugin.
    pub first: Vec<i32>,
    /// Joint value(s) in the second configuration.
    pub second: Vec<i32>,
}

/// Why two configurations are not equal up to rigid motion.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Difference {
    /// Set when the two are for different robots (nothing else is compared).
    pub robots: Option<(String, String)>,
    /// Module names only in the first configuration.
    pub only_in_first: Vec<String>,
    /// Module names only in the second configuration.
    pub only_in_second: Vec<String>,
    /// Modules whose numeric ids differ: (name, first, second).
    pub ids: Vec<(String, Option<u32>, Option<u32>)>,
    /// The rigid motion that matches the most modules (applied to the first configuration).
    pub rotation: Option<Rotation>,
    /// Its translation, in the configuration's internal position unit (`rigid::Shape`).
    pub translation: Vec3,
    /// How many common modules that motion puts in place.
    pub matched: usize,
    /// Modules out of place under that motion.
    pub misplaced: Vec<Misplaced>,
    /// Joints that differ.
    pub joints: Vec<JointDifference>,
    /// Connections of the first configuration missing from the second (`M0.C0-M2.C1`).
    pub missing_connections: Vec<String>,
    /// Connections of the second configuration that the first lacks.
    pub extra_connections: Vec<String>,
    /// Set when one of the two names no module (its file names none) and their shapes
    /// differ, or one of them cannot be described without names: why.
    pub unnamed: Option<String>,
    /// What the two configurations are, for the account.
    pub sides: Sides,
}

impl Difference {
    fn is_empty(&self) -> bool {
        self.robots.is_none()
            && self.unnamed.is_none()
            && self.only_in_first.is_empty()
            && self.only_in_second.is_empty()
            && self.ids.is_empty()
            && self.misplaced.is_empty()
            && self.joints.is_empty()
            && self.missing_connections.is_empty()
            && self.extra_connections.is_empty()
    }

    /// True when `module` appears anywhere in the difference.
    pub fn mentions(&self, module: &str) -> bool {
        let in_connection = |c: &String| c.split(['-', '.']).any(|part| part == module);
        self.only_in_first.iter().any(|m| m == module)
            || self.only_in_second.iter().any(|m| m == module)
            || self.ids.iter().any(|(m, _, _)| m == module)
            || self.misplaced.iter().any(|m| m.module == module)
            || self.joints.iter().any(|j| j.module == module)
            || self.missing_connections.iter().any(in_connection)
            || self.extra_connections.iter().any(in_connection)
    }
}

impl fmt::Display for Difference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (first, second) = self.sides.names();
        if let Some((a, b)) = &self.robots {
            return write!(f, "different robots: {a} ({first}) and {b} ({second})");
        }
        if let Some(why) = &self.unnamed {
            return write!(f, "configurations differ: {why}");
        }
        match &self.rotation {
            Some(r) => writeln!(
                f,
                "configurations differ; moved by the rigid motion that fits best ({r}, then \
                 shift {:?}), the {first} configuration has {} module(s) in place:",
                self.translation, self.matched
            )?,
            None => writeln!(f, "configurations differ:")?,
        }
        for m in &self.only_in_first {
            writeln!(f, "  module {m} in the {first} configuration only")?;
        }
        for m in &self.only_in_second {
            writeln!(f, "  module {m} in the {second} configuration only")?;
        }
        for (m, a, b) in &self.ids {
            writeln!(f, "  module {m}: id {a:?} ({first}) vs {b:?} ({second})")?;
        }
        for m in &self.misplaced {
            writeln!(
                f,
                "  module {} misplaced: {first} {}, {second} {}",
                m.module, m.first, m.second
            )?;
        }
        for j in &self.joints {
            writeln!(
                f,
                "  joint of {}: {first} {:?}, {second} {:?}",
                j.module, j.first, j.second
            )?;
        }
        for c in &self.missing_connections {
            writeln!(f, "  connection {c} in the {first} configuration only")?;
        }
        for c in &self.extra_connections {
            writeln!(f, "  connection {c} in the {second} configuration only")?;
        }
        Ok(())
    }
}

impl std::error::Error for Difference {}

/// The comparison of two configurations of which one names no module: by their unnamed
/// forms alone (`None` when both name their modules).
#[allow(clippy::result_large_err)]
fn unnamed_difference(a: &Shape, b: &Shape) -> Option<Result<(), Difference>> {
    let anonymous = |s: &Shape| s.unnamed.as_ref().is_some_and(|u| u.anonymous);
    if !anonymous(a) && !anonymous(b) {
        return None;
    }
    let form = |s: &Shape| s.unnamed.as_ref().map(|u| u.form.clone());
    let why = match (form(a), form(b)) {
        (Some(x), Some(y)) if x == y => return Some(Ok(())),
        (Some(_), Some(_)) => {
            "one of them names no module (its file gives none), so they are \
                               compared by their shapes alone, and the shapes differ"
        }
        _ => {
            "one of them names no module (its file gives none), and the other's shape cannot \
              be told without names (a joint that is not a multiple of 90 degrees)"
        }
    };
    Some(Err(Difference {
        unnamed: Some(why.to_string()),
        ..Difference::default()
    }))
}

fn shape(config: &Configuration) -> Shape {
    config.rigid_shape()
}

/// [`compare`] of the configuration a run reached against the one it was expected to reach,
/// with the account naming each side as such (the rigid motion is the expected one's).
#[allow(clippy::result_large_err)]
pub fn compare_with_expected(
    reached: &Configuration,
    expected: &Configuration,
) -> Result<(), Difference> {
    compare(expected, reached).map_err(|difference| Difference {
        sides: Sides::ExpectedReached,
        ..difference
    })
}

/// `Ok(())` when `b` is `a` moved by one of the 24 lattice rotations and a translation: same
/// module names and ids, every module's position and orientation mapped by that one motion,
/// same joint angles and same connections. Otherwise the differences under the rigid motion
/// that puts the most modules in place.
// The difference is this function's whole answer, built once per call: its size is no cost.
#[allow(clippy::result_large_err)]
pub fn compare(a: &Configuration, b: &Configuration) -> Result<(), Difference> {
    if a.kind().file_tag() != b.kind().file_tag() {
        return Err(Difference {
            robots: Some((
                a.kind().file_tag().to_string(),
                b.kind().file_tag().to_string(),
            )),
            ..Difference::default()
        });
    }
    let (sa, sb) = (shape(a), shape(b));
    if let Some(why) = unnamed_difference(&sa, &sb) {
        return why;
    }
    let mut diff = Difference {
        only_in_first: names_missing(&sa, &sb),
        only_in_second: names_missing(&sb, &sa),
        ..Difference::default()
    };
    let common: Vec<(&String, &Body, &Body)> = sa
        .bodies
        .iter()
        .filter_map(|(name, body)| sb.bodies.get(name).map(|other| (name, body, other)))
        .collect();
    let (rotation, translation, matched) = if sa.anchored || sb.anchored {
        let in_place = common.iter().filter(|(_, x, y)| x.position == y.position);
        (Rotation::IDENTITY, [0; 3], in_place.count())
    } else {
        best_motion(&common)
    };
    diff.rotation = Some(rotation);
    diff.translation = translation;
    diff.matched = matched;
    for (name, x, y) in &common {
        if x.id != y.id {
            diff.ids.push(((*name).clone(), x.id, y.id));
        }
        let mapped = add(rotation.apply(x.position), translation);
        let mapped_frame = rotation.compose(&x.frame);
        if mapped != y.position || mapped_frame != y.frame {
            diff.misplaced.push(Misplaced {
                module: (*name).clone(),
                first: describe(&sa, mapped, mapped_frame),
                second: describe(&sb, y.position, y.frame),
            });
        }
        if x.joints != y.joints {
            diff.joints.push(JointDifference {
                module: (*name).clone(),
                first: x.joints.clone(),
                second: y.joints.clone(),
            });
        }
    }
    diff.missing_connections = sa
        .connections
        .difference(&sb.connections)
        .cloned()
        .collect();
    diff.extra_connections = sb
        .connections
        .difference(&sa.connections)
        .cloned()
        .collect();
    if diff.is_empty() {
        Ok(())
    } else {
        Err(diff)
    }
}

fn names_missing(from: &Shape, other: &Shape) -> Vec<String> {
    from.bodies
        .keys()
        .filter(|n| !other.bodies.contains_key(*n))
        .cloned()
        .collect()
}

/// `[x, y, z] ORIENTATION` in the file's unit.
fn describe(shape: &Shape, position: Vec3, frame: Rotation) -> String {
    let coordinates: Vec<String> = position
        .iter()
        .map(|c| {
            if c % shape.position_scale == 0 {
                (c / shape.position_scale).to_string()
            } else {
                format!("{}", f64::from(*c) / f64::from(shape.position_scale))
            }
        })
        .collect();
    format!("[{}] {}", coordinates.join(", "), (shape.name_frame)(frame))
}

/// The rotation and translation that map the most modules of the first configuration onto the
/// second in both position and orientation (first found wins a tie, so the result is
/// deterministic).
fn best_motion(common: &[(&String, &Body, &Body)]) -> (Rotation, Vec3, usize) {
    let mut best = (Rotation::IDENTITY, [0; 3], 0);
    if let Some((_, x, y)) = common.first() {
        best.1 = sub(y.position, x.position);
    }
    for rotation in Rotation::all() {
        let mut votes: BTreeMap<Vec3, usize> = BTreeMap::new();
        for (_, x, y) in common {
            if rotation.compose(&x.frame) == y.frame {
                *votes
                    .entry(sub(y.position, rotation.apply(x.position)))
                    .or_default() += 1;
            }
        }
        for (translation, count) in votes {
            if count > best.2 {
                best = (rotation, translation, count);
            }
        }
    }
    best
}

/// How a built-in robot's model differs from `other` (`RobotModel::difference`): `None` when
/// they are equal, compared in place first (no copy), or equal up to rigid motion.
pub fn model_difference<W>(model: &W, other: &dyn RobotModel) -> Option<String>
where
    W: RobotModel + PartialEq + 'static,
{
    if other.as_any().downcast_ref::<W>() == Some(model) {
        return None;
    }
    let mine = model.configuration()?;
    let Some(theirs) = other.configuration() else {
        let (a, b) = (other.robot(), model.robot());
        return Some(format!("the other robot is {a}, not {b}"));
    };
    compare(&mine, &theirs).err().map(|d| d.to_string())
}
