//! Every message the language core can give, as plain data, and the one table that words them.
//!
//! A [`Diagnostic`] is a kind plus where it happened. [`Diagnostic::describe`] is the single
//! exhaustive `match` that turns a kind into a title, a label, a hint and extra labels, so a new
//! kind does not compile until it has a message. Rendering (colours, snippets) is the CLI's job.

use crate::span::Span;
use strum::{EnumDiscriminants, EnumIter, IntoStaticStr};

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    Warning,
    Error,
}

/// One problem found in a source file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    pub kind: DiagnosticKind,
    /// Where the problem is; the caret of the rendered snippet.
    pub span: Span,
}

/// A diagnostic in words, ready for a renderer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Description {
    /// Stable kebab-case name of the kind, such as `unknown-label`.
    pub code: &'static str,
    pub severity: Severity,
    pub title: String,
    /// Text under the caret at the primary span.
    pub label: String,
    /// Other places that explain the problem.
    pub secondary: Vec<(Span, String)>,
    pub hint: Option<String>,
}

/// What went wrong. Payloads hold only what the message needs.
#[derive(Clone, Debug, PartialEq, Eq, EnumDiscriminants)]
#[strum_discriminants(name(DiagnosticCode))]
#[strum_discriminants(derive(EnumIter, IntoStaticStr, PartialOrd, Ord, Hash))]
#[strum_discriminants(strum(serialize_all = "kebab-case"))]
pub enum DiagnosticKind {
    // ---- syntax ----
    /// A run of `count` characters that are not part of the language, starting with `found`.
    UnknownCharacter {
        found: char,
        count: usize,
    },
    UnterminatedComment,
    UnexpectedToken {
        expected: String,
        found: String,
    },
    /// `&` inside a role predicate.
    SingleAmpersand,
    /// `|` inside a role predicate.
    SinglePipe,
    /// `=` where a comparison was expected.
    AssignmentInPredicate,
    IntegerTooLarge,
    /// `$CONNECTOR 4`: a constant split by a space (an OCR slip in the paper).
    SpaceInConstant {
        joined: String,
    },
    MissingSeparator,
    UnclosedParallelGroup,
    NestingTooDeep {
        limit: usize,
    },
    PredicateTooLong {
        limit: usize,
    },
    EmptySequence {
        name: String,
    },
    /// Expanded, the sequence would have more statements than a program can.
    SequenceTooLong {
        name: String,
        /// At least this many (the count saturates).
        statements: usize,
        limit: usize,
    },
    /// All the sequences of the file, expanded, have more statements than checking accepts.
    FileTooLong {
        /// At least this many (the count saturates).
        statements: usize,
        limit: usize,
    },
    /// Sequences using sequences, deeper than expansion accepts.
    CompositionTooDeep {
        name: String,
        limit: usize,
    },
    /// The file is too large or too broken to read further.
    InputTooLarge {
        what: String,
    },
    /// More errors than a report shows; the rest are counted.
    TooManyErrors {
        more: usize,
    },
    // ---- names ----
    MissingRobot {
        known: Vec<String>,
    },
    DuplicateRobot {
        first: Span,
    },
    UnknownRobot {
        name: String,
        known: Vec<String>,
    },
    DuplicateDefinition {
        name: String,
        what: &'static str,
        first: Span,
    },
    UnknownLabel {
        name: String,
        suggestion: Option<String>,
    },
    RoleShadowsModuleLabel {
        name: String,
    },
    UnknownSequence {
        name: String,
        suggestion: Option<String>,
    },
    UnknownPart {
        part: String,
        robot: String,
        known: Vec<String>,
        suggestion: Option<String>,
    },
    UnknownMethod {
        part: String,
        method: String,
        known: Vec<String>,
        suggestion: Option<String>,
    },
    UnknownConstant {
        name: String,
        suggestion: Option<String>,
    },
    UnknownQuery {
        name: String,
        known: Vec<String>,
        suggestion: Option<String>,
    },
    CompositionCycle {
        path: Vec<String>,
        uses: Vec<Span>,
    },
    // ---- types and values ----
    MissingIndex {
        part: String,
        example: String,
    },
    UnexpectedIndex {
        part: String,
    },
    WrongArity {
        method: String,
        signature: String,
        expected: usize,
        found: usize,
    },
    WrongArgumentType {
        param: String,
        expected: String,
        found: String,
    },
    IndexOutOfRange {
        part: String,
        index: i64,
        count: u32,
    },
    ArgumentOutOfRange {
        param: String,
        value: i64,
        allowed: String,
    },
    /// A number in a role predicate that the generated code cannot hold or compare.
    NumberOutOfRange {
        value: i64,
        allowed: String,
        reason: String,
    },
    FemaleConnector {
        part: String,
        method: String,
        index: i64,
        males: String,
    },
    NotInvertible {
        method: String,
        sequence: String,
        reversed_at: Span,
    },
    TypeMismatch {
        context: String,
        expected: String,
        found: String,
    },
    PredicateNotBoolean {
        role: String,
        found: String,
    },
    QueryArity {
        name: String,
        expected: usize,
        found: usize,
    },
    // ---- on a configuration (replay and `check --from`) ----
    /// A step the robot cannot do from the configuration it is in.
    StepRejected {
        step: String,
        reason: String,
    },
    /// A step that can be done but probably does not do what was meant.
    StepSuspicious {
        step: String,
        reason: String,
    },
    /// Two statements joined by `&` that are not independent.
    NotIndependent {
        step: String,
        other_step: String,
        reason: String,
        other: Span,
    },
    /// A role that does not pick exactly one module of the configuration.
    RoleNotUnique {
        role: String,
        modules: Vec<String>,
    },
    /// `M<k>` with no module whose ID is k.
    NoModuleWithId {
        id: u32,
    },
    // ---- synchronous groups ----
    /// `sync { ... }` that is not one parallel group of statements.
    SynchronousGroupShape {
        problem: SyncProblem,
    },
    /// A statement of a synchronous group that does not turn a joint.
    SynchronousNotATurn {
        step: String,
    },
    /// A synchronous group, which the protocol's code cannot start at one instant.
    SynchronousNotSupported,
    // ---- protocol limits ----
    /// The sequence does not fit what the generated code can encode.
    TargetLimit {
        message: String,
    },
    NotSupportedByPaperProtocol {
        reason: String,
    },
    /// The token baseline cannot route a hand-over on the configuration.
    TokenRoute {
        message: String,
    },
}

/// How a `sync { ... }` fails to be one parallel group of statements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SyncProblem {
    Empty,
    /// A `;` before the last element.
    SequentialInside,
    /// A block or a use of a sequence.
    NotAStatement,
}

impl Diagnostic {
    pub fn new(kind: DiagnosticKind, span: Span) -> Diagnostic {
        Diagnostic { kind, span }
    }

    pub fn severity(&self) -> Severity {
        self.describe().severity
    }

    pub fn code(&self) -> DiagnosticCode {
        DiagnosticCode::from(&self.kind)
    }

    /// The one table of messages.
    pub fn describe(&self) -> Description {
        use DiagnosticKind as K;
        let d = Description::error(self.code());
        match &self.kind {
            K::UnknownCharacter { found, count: 1 } => d
                .title(format!("unexpected character `{}`", found.escape_debug()))
                .label("not part of the language"),
            K::UnknownCharacter { found, count } => d
                .title(format!("{count} unexpected characters, from `{}`", found.escape_debug()))
                .label("not part of the language"),
            K::UnterminatedComment => d
                .title("unterminated block comment")
                .label("this `/*` is never closed")
                .hint("close the comment with `*/`"),
            K::UnexpectedToken { expected, found } => d
                .title(format!("expected {expected}, found {found}"))
                .label(format!("expected {expected} here")),
            K::SingleAmpersand => d
                .title("`&` in a role predicate")
                .label("`&` separates parallel statements")
                .hint("write `&&` for \"and\""),
            K::SinglePipe => d
                .title("`|` in a role predicate")
                .label("not an operator")
                .hint("write `||` for \"or\""),
            K::AssignmentInPredicate => d
                .title("`=` in a role predicate")
                .label("predicates compare, they do not assign")
                .hint("write `==` to compare"),
            K::IntegerTooLarge => d
                .title("number too large")
                .label("does not fit in 64 bits"),
            K::SpaceInConstant { joined } => d
                .title("space inside a constant name")
                .label("constant names contain no spaces")
                .hint(format!("write `${joined}`")),
            K::MissingSeparator => d
                .title("missing `;` or `&` after this statement")
                .label("every statement ends with `;` (sequential) or `&` (parallel)")
                .hint("add `;` if the next statement depends on this one, `&` if it does not"),
            K::UnclosedParallelGroup => d
                .title("parallel group is never closed")
                .label("the last element of a body ends with `&`")
                .hint("end the last statement with `;`: a parallel group is closed by a sequential statement"),
            K::NestingTooDeep { limit } => d
                .title(format!("nesting deeper than {limit} levels"))
                .label("too deep")
                .hint("flatten the blocks or the expression"),
            K::PredicateTooLong { limit } => d
                .title(format!("role predicate with more than {limit} operators"))
                .label("the limit is reached here")
                .hint("split the condition, or give the modules a property the predicate can test directly"),
            K::EmptySequence { name } => d
                .warning()
                .title(format!("sequence `{name}` has no statements"))
                .label("empty body"),
            K::SequenceTooLong { name, statements, limit } => d
                .title(format!("sequence `{name}` would have {statements} statements once expanded (limit {limit})"))
                .label("expanded here")
                .hint("the sequences it uses are inlined: one used twice counts twice; split the work into sequences that run one after another"),
            K::FileTooLong { statements, limit } => d
                .title(format!("the sequences of this file expand to {statements} statements together (limit {limit})"))
                .label("the total passes the limit with this sequence")
                .hint("each sequence is expanded and checked on its own, so one used by many counts once per use; split the file"),
            K::CompositionTooDeep { name, limit } => d
                .title(format!("sequence `{name}` uses sequences more than {limit} levels deep"))
                .label("the chain of sequences using sequences ends here")
                .hint("use the inner sequences side by side in one body instead of each inside the next"),
            K::InputTooLarge { what } => d
                .title(format!("{what}: the rest of the file is not read"))
                .label("reading stops here")
                .hint("fix the errors above, or split the file (docs/limits.md gives every limit)"),
            K::TooManyErrors { more } => d
                .warning()
                .title(format!("{more} more diagnostic{} not shown", plural(*more)))
                .label("the next one is here")
                .hint("fix the errors above and run again"),
            K::MissingRobot { known } => d
                .title("the file does not say which robot it is for")
                .label("expected a `robot` declaration")
                .hint(start_with_a_robot(known)),
            K::DuplicateRobot { first } => d
                .title("more than one `robot` declaration")
                .label("second declaration")
                .secondary(*first, "first declared here"),
            K::UnknownRobot { name, known } => d
                .title(format!("unknown robot `{name}`"))
                .label("no API plugin has this name")
                .hint(format!(
                    "{}known robots: {}; describe another robot in `{name}.robot.toml` beside the file, or pass it with `--plugin FILE`",
                    crate::suggest::did_you_mean(name, known.iter().map(String::as_str))
                        .map_or_else(String::new, |hint| format!("{hint} ")),
                    known.join(", ")
                )),
            K::DuplicateDefinition { name, what, first } => d
                .title(format!("{what} `{name}` is defined twice"))
                .label("defined again here")
                .secondary(*first, "first defined here")
                .hint("rename one of them"),
            K::UnknownLabel { name, suggestion } => d
                .title(format!("unknown label `{name}`"))
                .label("not a role and not a module label of the form M<id>")
                .hint(suggestion.as_ref().map_or_else(
                    || format!("declare it with `role {name} requires ...;`, or use `M<id>` for the module with that ID"),
                    |s| format!("did you mean `{s}`?"),
                )),
            K::RoleShadowsModuleLabel { name } => d
                .warning()
                .title(format!("role `{name}` hides the module label `{name}`"))
                .label("statements labelled with this name use the role, not the module ID")
                .hint("rename the role unless this is intended"),
            K::UnknownSequence { name, suggestion } => d
                .title(format!("unknown sequence `{name}`"))
                .label("no sequence has this name")
                .hint_opt(suggestion.as_ref().map(|s| format!("did you mean `{s}`?"))),
            K::UnknownPart { part, robot, known, suggestion } => d
                .title(format!("robot `{robot}` has no part `{part}`"))
                .label("unknown part")
                .hint(did_you_mean(suggestion, "parts", known)),
            K::UnknownMethod { part, method, known, suggestion } => d
                .title(format!("`{part}` has no operation `{method}`"))
                .label("unknown operation")
                .hint(did_you_mean(suggestion, "operations", known)),
            K::UnknownConstant { name, suggestion } => d
                .title(format!("unknown constant `${name}`"))
                .label("the robot plugin defines no such constant")
                .hint_opt(suggestion.as_ref().map(|s| format!("did you mean `${s}`?"))),
            K::UnknownQuery { name, known, suggestion } => d
                .title(format!("unknown query `{name}` in role predicate"))
                .label("not something a module knows about itself")
                .hint(did_you_mean(suggestion, "queries", known)),
            K::CompositionCycle { path, uses } => {
                let mut d = d
                    .title(format!("sequences use each other in a cycle: {}", path.join(" -> ")))
                    .label("this use closes the cycle")
                    .hint("a sequence cannot run itself, directly or through others");
                for span in uses {
                    d = d.secondary(*span, "part of the cycle");
                }
                d
            }
            K::MissingIndex { part, example } => d
                .title(format!("`{part}` needs an index"))
                .label("which one?")
                .hint(format!("write `{example}`")),
            K::UnexpectedIndex { part } => d
                .title(format!("`{part}` takes no index"))
                .label("remove this index")
                .hint(format!("write `.{part}.` without brackets")),
            K::WrongArity { method, signature, expected, found } => d
                .title(format!(
                    "`{method}` takes {expected} argument{}, found {found}",
                    plural(*expected)
                ))
                .label(format!("expected {expected}"))
                .hint(format!("the operation is `{signature}`")),
            K::WrongArgumentType { param, expected, found } => d
                .title(format!("wrong type for `{param}`: expected {expected}, found {found}"))
                .label(format!("expected {expected}")),
            K::IndexOutOfRange { part, index, count } => d
                .title(format!("{part} index {index} is out of range"))
                .label(format!("this module has {count} ({part} 0 to {})", count.saturating_sub(1)))
                .hint(format!("use an index from 0 to {}", count.saturating_sub(1))),
            K::ArgumentOutOfRange { param, value, allowed } => d
                .title(format!("`{param}` = {value} is out of range"))
                .label(format!("allowed: {allowed}")),
            K::NumberOutOfRange { value, allowed, reason } => d
                .title(format!("{value} is out of range here"))
                .label(format!("expected {allowed}"))
                .hint(reason.clone()),
            K::FemaleConnector { part, method, index, males } => d
                .title(format!("`{method}` on female {part} {index}"))
                .label("only male connectors can extend or retract")
                .hint(format!("the male connectors are {males}; the module on the other side must act")),
            K::NotInvertible { method, sequence, reversed_at } => d
                .title(format!("`{method}` has no inverse, so `{sequence}` cannot be reversed"))
                .label("this operation cannot be undone by the robot API")
                .secondary(*reversed_at, "reversed here")
                .hint("use an operation that states enough to be undone, e.g. `rotateFromToBy` instead of `rotateToBy`"),
            K::TypeMismatch { context, expected, found } => d
                .title(format!("{context} expects {expected}, found {found}"))
                .label(format!("this is {found}")),
            K::PredicateNotBoolean { role, found } => d
                .title(format!("the predicate of role `{role}` is {found}, not a boolean"))
                .label("expected a condition")
                .hint("compare it, e.g. `id == 3`"),
            K::QueryArity { name, expected, found } => d
                .title(format!(
                    "`{name}` takes {expected} argument{}, found {found}",
                    plural(*expected)
                ))
                .label(format!("expected {expected}")),
            K::StepRejected { step, reason } => d
                .title(format!("`{step}` cannot be done: {reason}"))
                .label("rejected by the robot model; the configuration is left as it was"),
            K::StepSuspicious { step, reason } => d
                .warning()
                .title(format!("`{step}`: {reason}"))
                .label("done, but probably not what was meant"),
            K::NotIndependent { step, other_step, reason, other } => d
                .warning()
                .title(format!("`{step}` and `{other_step}` are joined by `&` but are not independent: {reason}"))
                .label("this statement")
                .secondary(*other, "and this one")
                .hint("separate them with `;` so that one waits for the other"),
            K::RoleNotUnique { role, modules } if modules.is_empty() => d
                .title(format!("no module of the configuration is a `{role}`"))
                .label("its predicate holds for no module")
                .hint("check the predicate against the configuration given with --from"),
            K::RoleNotUnique { role, modules } => d
                .title(format!("several modules are a `{role}`: {}", modules.join(", ")))
                .label("a statement label must pick exactly one module")
                .hint("make the predicate more specific"),
            K::NoModuleWithId { id } => d
                .title(format!("no module of the configuration has ID {id}"))
                .label(format!("`M{id}` means the module whose ID is {id}")),
            K::TargetLimit { message } => d
                .title("the sequence exceeds a limit of the generated code")
                .label(message.clone())
                .hint("compile fewer sequences at once (the paper protocol numbers states in one byte), or renumber the modules (IDs at most 253)"),
            K::TokenRoute { message } => d
                .title("the token baseline cannot run this sequence on this configuration")
                .label(message.clone())
                .hint("the token travels over latched connectors only: keep the modules of consecutive statements joined, or use the lattice protocol (the default), which needs no route"),
            K::SynchronousGroupShape { problem } => {
                let label = match problem {
                    SyncProblem::Empty => "a synchronous group with no statements",
                    SyncProblem::SequentialInside => "`;` inside a synchronous group",
                    SyncProblem::NotAStatement => "a block or a sequence inside a synchronous group",
                };
                d.title("a synchronous group is one parallel group of statements")
                    .label(label)
                    .hint("write `sync { A & B; }`: its statements joined by `&`, the last closed by `;`; what must happen before or after goes outside it")
            }
            K::SynchronousNotATurn { step } => d
                .title(format!("`{step}` cannot move in lock-step"))
                .label("not a turn from a stated angle")
                .hint("a synchronous group holds turns that state where they start (an operation of kind `turn`): the modules start them at one instant and move them at the pace of the longest, which every module must know; put a connector or any other operation outside it"),
            K::SynchronousNotSupported => d
                .title("the token baseline cannot run a synchronous group")
                .label("it runs one statement at a time, so these turns cannot start together")
                .hint("use the `lattice` protocol (the default), which starts a synchronous group at one agreed instant"),
            K::NotSupportedByPaperProtocol { reason } => d
                .title("not supported by the paper protocol")
                .label(reason.clone())
                .hint("use the `lattice` protocol, which runs nested blocks"),
        }
    }
}

/// `start the file with `robot a;` or `robot b;``: the declarations the known robots allow.
fn start_with_a_robot(known: &[String]) -> String {
    let declarations: Vec<String> = known.iter().map(|n| format!("`robot {n};`")).collect();
    match declarations.split_last() {
        None => "start the file with `robot NAME;`, NAME a robot plugin".to_string(),
        Some((last, [])) => format!("start the file with {last}"),
        Some((last, rest)) => format!("start the file with {} or {last}", rest.join(", ")),
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

fn did_you_mean(suggestion: &Option<String>, what: &str, known: &[String]) -> String {
    match suggestion {
        Some(s) => format!("did you mean `{s}`?"),
        None => format!("known {what}: {}", known.join(", ")),
    }
}

impl Description {
    fn error(code: DiagnosticCode) -> Description {
        Description {
            code: code.into(),
            severity: Severity::Error,
            title: String::new(),
            label: String::new(),
            secondary: Vec::new(),
            hint: None,
        }
    }

    fn warning(mut self) -> Self {
        self.severity = Severity::Warning;
        self
    }

    fn title(mut self, title: impl Into<String>) -> Self {
        self.title = title.into();
        self
    }

    fn label(mut self, label: impl Into<String>) -> Self {
        self.label = label.into();
        self
    }

    fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    fn hint_opt(mut self, hint: Option<String>) -> Self {
        self.hint = hint;
        self
    }

    fn secondary(mut self, span: Span, text: impl Into<String>) -> Self {
        self.secondary.push((span, text.into()));
        self
    }
}

impl DiagnosticCode {
    pub fn name(self) -> &'static str {
        self.into()
    }
}

/// True when any diagnostic is an error (warnings do not fail a check).
/// Most diagnostics shown for one file; the rest are counted in one [`DiagnosticKind::TooManyErrors`].
pub const MAX_SHOWN: usize = 50;

/// The diagnostics a report shows: the first [`MAX_SHOWN`], then one that counts the rest,
/// so that the output stays bounded whatever the input; a file that was not read to its end
/// says so whatever its place in the list.
pub fn shown(diagnostics: &[Diagnostic]) -> Vec<Diagnostic> {
    let mut out: Vec<Diagnostic> = diagnostics.iter().take(MAX_SHOWN).cloned().collect();
    let rest = diagnostics.get(MAX_SHOWN..).unwrap_or(&[]);
    let (stops, others): (Vec<&Diagnostic>, Vec<&Diagnostic>) = rest
        .iter()
        .partition(|d| matches!(d.kind, DiagnosticKind::InputTooLarge { .. }));
    if let Some(next) = others.first() {
        let more = others.len();
        out.push(Diagnostic::new(
            DiagnosticKind::TooManyErrors { more },
            next.span,
        ));
    }
    out.extend(stops.into_iter().cloned());
    out
}

pub fn has_errors(diagnostics: &[Diagnostic]) -> bool {
    diagnostics.iter().any(|d| d.severity() == Severity::Error)
}

/// Every diagnostic code, for tests that check each one is exercised.
pub fn all_codes() -> impl Iterator<Item = DiagnosticCode> {
    <DiagnosticCode as strum::IntoEnumIterator>::iter()
}
