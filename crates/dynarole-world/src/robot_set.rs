//! A set of robot kinds ([`Robots`]): the registry crate lists the built-in ones, and a
//! program may add its own. Reading a configuration file picks the kind by the file's `robot`
//! field here, and nowhere else.

use crate::api::{Configuration, ImportOptions, ImportedPlan, PlanError, RobotKind};
use crate::common::ConfigError;
use crate::file_format::deserialize;
use serde::Deserialize;

/// A set of robot kinds, by name, in the order given.
#[derive(Clone, Default)]
pub struct Robots {
    kinds: Vec<&'static dyn RobotKind>,
}

impl Robots {
    /// The kinds given, a later one replacing an earlier one of the same name.
    pub fn new(kinds: impl IntoIterator<Item = &'static dyn RobotKind>) -> Robots {
        kinds.into_iter().fold(Robots::default(), Robots::with)
    }

    /// This set with `kind` added (replacing one of the same name).
    pub fn with(mut self, kind: &'static dyn RobotKind) -> Robots {
        self.kinds.retain(|k| k.name() != kind.name());
        self.kinds.push(kind);
        self
    }

    /// The kinds, in order.
    pub fn kinds(&self) -> impl Iterator<Item = &'static dyn RobotKind> + '_ {
        self.kinds.iter().copied()
    }

    /// The kind whose plugin is called `name`.
    pub fn get(&self, name: &str) -> Option<&'static dyn RobotKind> {
        self.kinds().find(|k| k.name() == name)
    }

    /// The plugin names, in order.
    pub fn names(&self) -> Vec<&'static str> {
        self.kinds().map(|k| k.name()).collect()
    }

    /// Parses and validates a configuration in the data-file format of the kind its `robot`
    /// field names.
    /// A file without a `robot` field is read by the kind whose own tools' format it is
    /// (`RobotKind::read_native`), if any.
    pub fn read_configuration(&self, text: &str) -> Result<Configuration, ConfigError> {
        if let Err(e) = not_an_object(text) {
            return self.read_native(text).unwrap_or(Err(e));
        }
        let probe: Probe = match deserialize(text) {
            Ok(probe) => probe,
            Err(e) => return self.read_native(text).unwrap_or(Err(e)),
        };
        let expected = self.expected_tags();
        let Some(tag) = probe.robot else {
            let missing = ConfigError::new("robot", format!("missing field; expected {expected}"));
            return self.read_native(text).unwrap_or(Err(missing));
        };
        match self.kinds().find(|k| k.file_tag() == tag) {
            Some(kind) => kind.read_configuration(text),
            None => Err(ConfigError::new(
                "robot",
                format!("unknown robot \"{tag}\"; expected {expected}"),
            )),
        }
    }

    /// The configuration read by the first kind that recognises `text` as its own tools'.
    fn read_native(&self, text: &str) -> Option<Result<Configuration, ConfigError>> {
        self.kinds().find_map(|k| k.read_native(text))
    }

    /// The plan read by the first kind that recognises `text` as its planners' (`dynarole
    /// import`), its sequence called `sequence`, read as `options` say.
    pub fn import_plan(
        &self,
        text: &str,
        sequence: &str,
        options: &ImportOptions,
    ) -> Option<Result<ImportedPlan, PlanError>> {
        self.kinds()
            .find_map(|k| k.import_plan(text, sequence, options))
    }

    /// Each kind's plan formats, as `kind: formats`, for the message of a file that is none.
    pub fn plan_formats(&self) -> Vec<String> {
        (self.kinds())
            .filter_map(|k| k.plan_formats().map(|f| format!("{}: {f}", k.name())))
            .collect()
    }

    /// `"A", "B" or "C"`: the `robot` fields a file may have.
    fn expected_tags(&self) -> String {
        let tags: Vec<String> = self
            .kinds()
            .map(|k| format!("\"{}\"", k.file_tag()))
            .collect();
        match tags.split_last() {
            None => "no robot (none is known)".to_string(),
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        }
    }
}

/// The top-level field read first to pick the robot.
#[derive(Deserialize)]
struct Probe {
    robot: Option<String>,
}

/// A file that does not start as a JSON object is not a configuration at all (a program given
/// as `--from`, say): said as such, where JSON's own message would be "expected value".
fn not_an_object(text: &str) -> Result<(), ConfigError> {
    let Some((offset, found)) = text.char_indices().find(|(_, c)| !c.is_whitespace()) else {
        return Err(ConfigError::new(
            "document",
            "the file is empty; expected a configuration (a JSON object)",
        ));
    };
    if found == '{' {
        return Ok(());
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    let program = text[offset..].starts_with("robot") || text.contains("sequence ");
    let hint = if program {
        "; this looks like a DynaRole program (.dr), not a configuration (.json)"
    } else {
        ""
    };
    Err(ConfigError::new(
        "document",
        format!(
            "expected a configuration (a JSON object, starting with `{{`), found `{}` at line \
             {line}, column {column}{hint}",
            found.escape_debug()
        ),
    ))
}
