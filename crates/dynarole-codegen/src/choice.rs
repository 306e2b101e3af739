//! Closed sets of named values (protocols, merges, dissemination modes, the simulator's
//! stepping): each set lists its values once, and every caller (command line, campaign and
//! scenario files, reports) names and parses them through [`Choice`], with one error wording.

use dynarole_core::suggest::did_you_mean;
use std::fmt;

/// A closed set of values users name: the names, their order and their help are the set's,
/// the parsing and the error are shared.
pub trait Choice: Copy + PartialEq + 'static {
    /// What one value is, for messages ("protocol", "merge").
    const WHAT: &'static str;
    /// Every value, in the order listings show them (the default first where there is one).
    const ALL: &'static [Self];

    /// The name users write, on the command line and in files.
    fn name(self) -> &'static str;

    /// One line for the command line's help (empty: none).
    fn help(self) -> &'static str {
        ""
    }
}

/// The value of `T` called `text`, or an error listing the names there are.
pub fn parse<T: Choice>(text: &str) -> Result<T, UnknownName> {
    T::ALL
        .iter()
        .copied()
        .find(|v| v.name() == text)
        .ok_or_else(|| UnknownName {
            what: T::WHAT,
            found: text.to_string(),
            expected: names::<T>(),
        })
}

/// Every name of `T`, in order.
pub fn names<T: Choice>() -> Vec<&'static str> {
    T::ALL.iter().map(|v| v.name()).collect()
}

/// A name that is none of a set's.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownName {
    /// What was looked for ("protocol").
    pub what: &'static str,
    /// The name as written.
    pub found: String,
    /// The names there are, in order.
    pub expected: Vec<&'static str>,
}

impl UnknownName {
    /// "did you mean `x`?" when the name is a likely typo of one there is.
    pub fn hint(&self) -> Option<String> {
        did_you_mean(&self.found, self.expected.iter().copied())
    }
}

/// ``unknown protocol `x`, expected one of `a`, `b`, `c` `` (``expected `a` or `b` `` for two):
/// the shape of serde's own message for an unknown name, so that TOML errors give their hint the
/// same way (`dynarole_core::toml_error`).
impl fmt::Display for UnknownName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let quoted: Vec<String> = self.expected.iter().map(|n| format!("`{n}`")).collect();
        write!(f, "unknown {} `{}`, expected ", self.what, self.found)?;
        match quoted.as_slice() {
            [one] => f.write_str(one),
            [a, b] => write!(f, "{a} or {b}"),
            many => write!(f, "one of {}", many.join(", ")),
        }
    }
}

impl std::error::Error for UnknownName {}

/// Reads a value of `T` from its name in a file (`#[serde(deserialize_with = ...)]`), through
/// [`parse`]: an unknown name gets the same message as on the command line, at its place.
#[cfg(feature = "serde")]
pub fn deserialize<'de, D, T>(deserializer: D) -> Result<T, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Choice,
{
    deserializer.deserialize_str(NameVisitor(std::marker::PhantomData))
}

/// [`deserialize`] for an optional field (with `#[serde(default)]`: absent is `None`).
#[cfg(feature = "serde")]
pub fn deserialize_some<'de, D, T>(deserializer: D) -> Result<Option<T>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Choice,
{
    deserialize(deserializer).map(Some)
}

/// Parses the name while the deserializer still knows where it is, so that the error gets the
/// name's own place in the file (not the enclosing list's or table's).
#[cfg(feature = "serde")]
struct NameVisitor<T>(std::marker::PhantomData<T>);

#[cfg(feature = "serde")]
impl<T: Choice> serde::de::Visitor<'_> for NameVisitor<T> {
    type Value = T;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "the name of a {}", T::WHAT)
    }

    fn visit_str<E: serde::de::Error>(self, text: &str) -> Result<T, E> {
        parse(text).map_err(E::custom)
    }
}

/// A list of names (`protocols = ["lattice", "paper"]`), each read as [`deserialize`] reads one.
#[cfg(feature = "serde")]
pub fn deserialize_list<'de, D, T>(deserializer: D) -> Result<Vec<T>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Choice,
{
    /// One element, read by its name.
    struct Named<T>(T);
    impl<'de, T: Choice> serde::Deserialize<'de> for Named<T> {
        fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            deserialize(d).map(Named)
        }
    }
    let list = <Vec<Named<T>> as serde::Deserialize>::deserialize(deserializer)?;
    Ok(list.into_iter().map(|n| n.0).collect())
}

/// Writes a value of `T` as its name (`#[serde(serialize_with = ...)]`).
#[cfg(feature = "serde")]
pub fn serialize<S, T>(value: &T, serializer: S) -> Result<S::Ok, S::Error>
where
    S: serde::Serializer,
    T: Choice,
{
    serializer.serialize_str(value.name())
}
