//! The program driver: every caller (each command, the campaign runner, the simulator, the
//! model checker, the tests) goes from source text to lowered IR through these steps, so they
//! agree on the robot lookup, the order of diagnostics, the default sequence and its errors.
//!
//! ```text
//! let parsed = parse(&text);
//! let registry = driver::registry(robot_name(&parsed.file), plugins, |file| read_plugin_beside(file))?;
//! let program = driver::check(&parsed, &registry)?;          // Err: sorted diagnostics
//! let names = driver::select_sequences(&program, &wanted)?;  // the first one by default
//! let plans = driver::plans(&program, &names)?;
//! let ir = driver::lower(&program, &plans, Shape::Flat)?;    // Err: one diagnostic
//! ```
//!
//! Nothing here reads a file or prints: plugin files come in through the caller's lookup,
//! and errors go out as values.

use crate::ast::{Item, SourceFile};
use crate::check::{analyze, Program};
use crate::diagnostic::{has_errors, Diagnostic, DiagnosticKind};
use crate::expand::Plan;
use crate::lower::{Ir, LimitError};
use crate::parser::Parsed;
use crate::robot::{RobotApi, RobotRegistry};

impl From<LimitError> for Diagnostic {
    /// A limit of the target is reported at the statement that exceeds it.
    fn from(e: LimitError) -> Diagnostic {
        Diagnostic::new(DiagnosticKind::TargetLimit { message: e.message }, e.span)
    }
}

/// The name in the file's first `robot NAME;`, if any.
pub fn robot_name(file: &SourceFile) -> Option<&str> {
    file.items.iter().find_map(|item| match item {
        Item::Robot(decl) => Some(decl.name.name.as_str()),
        _ => None,
    })
}

/// The file, beside the source, of the plugin a `robot NAME;` loads when no other names it.
pub fn plugin_file_name(robot: &str) -> String {
    format!("{robot}.robot.toml")
}

/// The robots a file whose `robot NAME;` is `robot` ([`robot_name`]) can name: those of
/// `built_in` (the robot kinds the program was built with), then `plugins` in order, then, for
/// a `robot` still unknown, what `beside` finds for [`plugin_file_name`] (`Ok(None)` when
/// there is no such file).
pub fn registry<E>(
    built_in: RobotRegistry,
    robot: Option<&str>,
    plugins: impl IntoIterator<Item = RobotApi>,
    beside: impl FnOnce(&str) -> Result<Option<RobotApi>, E>,
) -> Result<RobotRegistry, E> {
    let mut registry = built_in;
    for plugin in plugins {
        registry.add(plugin);
    }
    if let Some(name) = robot {
        if registry.get(name).is_none() {
            if let Some(plugin) = beside(&plugin_file_name(name))? {
                registry.add(plugin);
            }
        }
    }
    Ok(registry)
}

/// Every diagnostic of `parsed` (syntax and checking) in source order, and the program when
/// there is one.
pub fn analyze_all<'f>(
    parsed: &'f Parsed,
    registry: &RobotRegistry,
) -> (Option<Program<'f>>, Vec<Diagnostic>) {
    let (program, mut diagnostics) = analyze(&parsed.file, registry);
    diagnostics.extend(parsed.diagnostics.iter().cloned());
    diagnostics.sort_by_key(|d| d.span);
    (program, diagnostics)
}

/// The checked program, or every diagnostic (in source order) when there is an error.
pub fn check<'f>(
    parsed: &'f Parsed,
    registry: &RobotRegistry,
) -> Result<Program<'f>, Vec<Diagnostic>> {
    let (program, diagnostics) = analyze_all(parsed, registry);
    match program.filter(|_| !has_errors(&diagnostics)) {
        Some(program) => Ok(program),
        None => Err(diagnostics),
    }
}

/// Checks text written for `robot`, a robot already loaded (a sequence the tools rewrote,
/// checked again before it is handed out).
pub fn check_for<'f>(parsed: &'f Parsed, robot: &RobotApi) -> Result<Program<'f>, Vec<Diagnostic>> {
    let mut registry = RobotRegistry::default();
    registry.add(robot.clone());
    check(parsed, &registry)
}

/// Why the sequences asked for cannot be run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SelectError {
    /// The file declares no sequence at all.
    NoSequence,
    /// `wanted[index]` names no sequence of the file.
    Unknown {
        index: usize,
        name: String,
        /// `did you mean `x`?`, when a declared name is close.
        hint: Option<String>,
        /// The file's sequences, in order.
        declared: Vec<String>,
    },
}

impl SelectError {
    /// The message, naming the source as `display`: `no sequence `x` in FILE; did you mean
    /// `y`? sequences in FILE: a, b`.
    pub fn message(&self, display: &str) -> String {
        match self {
            SelectError::NoSequence => format!(
                "{display} declares no sequence, so there is nothing to run; add `sequence NAME {{ ... }}`"
            ),
            SelectError::Unknown { name, .. } => {
                format!("no sequence `{name}` in {display}; {}", self.detail(display))
            }
        }
    }

    /// The part after the first `; `: the suggestion and the list of sequences.
    pub fn detail(&self, display: &str) -> String {
        let SelectError::Unknown { hint, declared, .. } = self else {
            return format!("{display} declares no sequence");
        };
        let mut detail = hint.as_ref().map(|h| format!("{h} ")).unwrap_or_default();
        if declared.is_empty() {
            detail.push_str(&format!("{display} declares no sequence"));
        } else {
            detail.push_str(&format!("sequences in {display}: {}", declared.join(", ")));
        }
        detail
    }
}

/// The sequences a command runs: `wanted`, or the first one the file declares when `wanted`
/// is empty.
pub fn select_sequences(program: &Program, wanted: &[String]) -> Result<Vec<String>, SelectError> {
    let declared = declared(program);
    let Some(first) = declared.first() else {
        return Err(SelectError::NoSequence);
    };
    if wanted.is_empty() {
        return Ok(vec![first.to_string()]);
    }
    let mut asked = wanted.iter().enumerate();
    match asked.find(|(_, w)| !declared.contains(&w.as_str())) {
        Some((index, name)) => Err(unknown_sequence(program, index, name)),
        None => Ok(wanted.to_vec()),
    }
}

/// The expanded plans of `names`, run in turn.
pub fn plans(program: &Program, names: &[String]) -> Result<Vec<Plan>, SelectError> {
    names
        .iter()
        .enumerate()
        .map(|(index, name)| {
            program
                .expand(name)
                .ok_or_else(|| unknown_sequence(program, index, name))
        })
        .collect()
}

/// The error for `name`, the `index`-th sequence asked for, which the file does not declare.
pub fn unknown_sequence(program: &Program, index: usize, name: &str) -> SelectError {
    let declared = declared(program);
    SelectError::Unknown {
        index,
        name: name.to_string(),
        hint: crate::suggest::did_you_mean(name, declared.iter().copied()),
        declared: declared.iter().map(|s| s.to_string()).collect(),
    }
}

fn declared<'p>(program: &'p Program) -> Vec<&'p str> {
    program
        .file
        .sequences()
        .map(|d| d.name.name.as_str())
        .collect()
}

/// What a protocol's code can run of an expanded sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// Any sequence the language accepts (nested blocks and synchronous groups included).
    Nested,
    /// Nested blocks, but statements one at a time: no synchronous start (the token
    /// baseline's).
    NestedInTurn,
    /// One pending set at a time, no nested blocks (the paper's protocol).
    Flat,
}

/// Lowers `plans` (run in turn) for a protocol of `shape`; the error is the first statement
/// that the protocol cannot run or that exceeds what the runtime encodes.
pub fn lower(program: &Program, plans: &[Plan], shape: Shape) -> Result<Ir, Diagnostic> {
    if shape == Shape::NestedInTurn {
        if let Some(span) = plans.iter().find_map(Plan::first_synchronous) {
            let kind = crate::DiagnosticKind::SynchronousNotSupported;
            return Err(Diagnostic::new(kind, span));
        }
    }
    if shape == Shape::Flat {
        for plan in plans {
            plan.flatten_for_paper()?;
        }
    }
    Ok(program.lower(plans)?)
}
