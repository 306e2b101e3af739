//! Loads and validates a robot plugin from its TOML text; errors name the offending field.

use super::*;
use crate::lexer::{lex, Token};
use serde::Deserialize;
use std::collections::BTreeSet;

/// A plugin that cannot be used: the field that is wrong, the message, where in the text.
pub type PluginError = crate::toml_error::TomlError;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPlugin {
    name: String,
    #[serde(default)]
    description: String,
    connectors: Option<String>,
    joints: Option<String>,
    joint_angle: Option<RawJointAngle>,
    #[serde(default)]
    timing: Vec<RawTiming>,
    #[serde(default)]
    part: Vec<RawPart>,
    /// Names of argument values (`$PLUS_X`), beside the parts' index names.
    #[serde(default)]
    values: std::collections::BTreeMap<String, i64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawJointAngle {
    quarter: i64,
    #[serde(default)]
    wraps: bool,
}

/// The largest quarter turn a plugin may count in (its angles stay far inside `i64`).
const MAX_QUARTER_UNITS: i64 = 1 << 20;

/// `[joint_angle]`, or the default (degrees, end stops) when the plugin has none.
fn joint_angle(raw: Option<&RawJointAngle>) -> Result<JointAngle, PluginError> {
    let Some(raw) = raw else {
        return Ok(JointAngle::default());
    };
    if !(1..=MAX_QUARTER_UNITS).contains(&raw.quarter) {
        return Err(error(
            "joint_angle.quarter",
            format!(
                "expected the units of a quarter turn, from 1 to {MAX_QUARTER_UNITS}, found {}",
                raw.quarter
            ),
        ));
    }
    Ok(JointAngle {
        quarter: raw.quarter,
        wraps: raw.wraps,
    })
}

/// One `[[timing]]` table: a timing preset. A duration may be left out only where the robot
/// has no operation of its kind (`timing_presets` checks).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTiming {
    name: String,
    #[serde(default)]
    doc: String,
    extend_ms: Option<u64>,
    retract_ms: Option<u64>,
    turn_first_quarter_ms: Option<u64>,
    turn_further_quarter_ms: Option<u64>,
    move_ms: Option<u64>,
}

/// The plugin's `[[timing]]` presets, in their order (the first is the default), each named
/// once and giving every duration the robot's operations (`parts`) need.
fn timing_presets(raw: &[RawTiming], parts: &[Part]) -> Result<Vec<TimingPreset>, PluginError> {
    let mut names = BTreeSet::new();
    let mut presets = Vec::new();
    for (i, raw) in raw.iter().enumerate() {
        let field = format!("timing[{i}]");
        if raw.name.trim().is_empty() {
            return Err(error(
                format!("{field}.name"),
                "a timing preset needs a name (what a scenario's `timing.preset` gives)",
            ));
        }
        if !names.insert(raw.name.as_str()) {
            return Err(error(
                format!("{field}.name"),
                format!("timing preset `{}` is defined twice", raw.name),
            ));
        }
        presets.push(TimingPreset {
            name: raw.name.clone(),
            doc: raw.doc.clone(),
            durations: durations(raw, parts, &field)?,
        });
    }
    Ok(presets)
}

/// A preset's durations: each one given (at most [`MAX_OPERATION_MS`]), or left out where no
/// operation of the robot is of its kind (then 0, never used).
fn durations(raw: &RawTiming, parts: &[Part], field: &str) -> Result<Durations, PluginError> {
    let given = |name: &'static str, value: Option<u64>, kinds: &[OperationKind]| {
        duration(Given { name, value, kinds }, raw, parts, field)
    };
    let turns = [OperationKind::Turn, OperationKind::TurnTo];
    Ok(Durations {
        extend_ms: given("extend_ms", raw.extend_ms, &[OperationKind::Extend])?,
        retract_ms: given("retract_ms", raw.retract_ms, &[OperationKind::Retract])?,
        turn_first_quarter_ms: given("turn_first_quarter_ms", raw.turn_first_quarter_ms, &turns)?,
        turn_further_quarter_ms: given(
            "turn_further_quarter_ms",
            raw.turn_further_quarter_ms,
            &turns,
        )?,
        move_ms: given("move_ms", raw.move_ms, &[OperationKind::Move])?,
    })
}

/// One duration field of a preset as written, and the kinds of operation that take it.
struct Given<'a> {
    name: &'static str,
    value: Option<u64>,
    kinds: &'a [OperationKind],
}

/// The value of `given` in preset `raw` (at `field`): refused above [`MAX_OPERATION_MS`], or
/// when left out and an operation of the robot (`parts`) is of its kinds.
fn duration(
    given: Given,
    raw: &RawTiming,
    parts: &[Part],
    field: &str,
) -> Result<u64, PluginError> {
    let name = given.name;
    let Some(ms) = given.value else {
        let Some((part, op)) = operation_of_kind(parts, given.kinds) else {
            return Ok(0);
        };
        let message = format!(
            "timing preset `{}` gives no `{name}`, which operation `{}` of part `{}` (kind `{}`) \
             needs",
            raw.name,
            op.name,
            part.name,
            op.kind.name()
        );
        return Err(error(field, message));
    };
    if ms > MAX_OPERATION_MS {
        return Err(error(
            format!("{field}.{name}"),
            format!(
                "expected at most {MAX_OPERATION_MS} ms (the simulator's longest run), found {ms}"
            ),
        ));
    }
    Ok(ms)
}

/// The first operation (and its part) of one of `kinds`.
fn operation_of_kind<'a>(
    parts: &'a [Part],
    kinds: &[OperationKind],
) -> Option<(&'a Part, &'a Operation)> {
    parts.iter().find_map(|part| {
        let op = part.operations.iter().find(|op| kinds.contains(&op.kind))?;
        Some((part, op))
    })
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPart {
    name: String,
    count: Option<u32>,
    constant_prefix: Option<String>,
    constants: Option<Vec<String>>,
    #[serde(default)]
    male: Vec<u32>,
    #[serde(default)]
    operation: Vec<RawOperation>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawOperation {
    name: String,
    #[serde(default)]
    doc: String,
    #[serde(default)]
    params: Vec<RawParam>,
    #[serde(default)]
    requires_male: bool,
    inverse: Option<String>,
    /// An unknown one is refused by the TOML reader at its place, with the closest name.
    kind: Option<OperationKind>,
    /// Planner steps a `move` is made of (1 when left out).
    steps: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawParam {
    name: String,
    #[serde(rename = "type")]
    ty: String,
    min: Option<i64>,
    max: Option<i64>,
    values: Option<Vec<i64>>,
}

fn error(field: impl Into<String>, message: impl Into<String>) -> PluginError {
    PluginError::new(field, message)
}

/// Longest `inverse` text; it is parsed recursively, so its length bounds the depth.
const MAX_INVERSE_LEN: usize = 500;

/// Largest index count; indices travel in one byte on the modules.
const MAX_COUNT: u32 = 255;

impl RobotApi {
    /// Reads a plugin; an error carries the span of the field it is about.
    pub fn from_toml(text: &str) -> Result<RobotApi, PluginError> {
        let raw: RawPlugin = toml::from_str(text).map_err(|e| PluginError::from_de(&e))?;
        RobotApi::from_raw(raw).map_err(|e| e.locate(text))
    }

    fn from_raw(raw: RawPlugin) -> Result<RobotApi, PluginError> {
        check_name("name", &raw.name)?;
        let mut parts = Vec::new();
        let mut constants = Vec::new();
        let mut part_names = BTreeSet::new();
        for (i, raw_part) in raw.part.iter().enumerate() {
            let field = format!("part[{i}]");
            if !part_names.insert(raw_part.name.as_str()) {
                return Err(error(
                    format!("{field}.name"),
                    format!("part `{}` is defined twice", raw_part.name),
                ));
            }
            // The part (and its `count`) is checked before its constants are built from it.
            parts.push(convert_part(raw_part, &field)?);
            constants.extend(part_constants(raw_part, i, &field)?);
        }
        for (i, raw_part) in raw.part.iter().enumerate() {
            resolve_inverses(&mut parts, i, raw_part)?;
        }
        constants.extend(value_constants(&raw.values)?);
        check_unique_constants(&constants)?;
        let find = |field: &str, name: &Option<String>| -> Result<Option<usize>, PluginError> {
            let Some(name) = name else { return Ok(None) };
            match parts.iter().position(|p| &p.name == name) {
                Some(i) => Ok(Some(i)),
                None => Err(error(field, format!("no part is named `{name}`"))),
            }
        };
        let connector_part = find("connectors", &raw.connectors)?;
        let joint_part = find("joints", &raw.joints)?;
        if let Some(i) = connector_part {
            if parts[i].count.is_none() {
                return Err(error(
                    "connectors",
                    "the connector part must have a `count`",
                ));
            }
        }
        Ok(RobotApi {
            joint_angle: joint_angle(raw.joint_angle.as_ref())?,
            timing: timing_presets(&raw.timing, &parts)?,
            name: raw.name,
            description: raw.description,
            parts,
            constants,
            connector_part,
            joint_part,
        })
    }
}

fn check_name(field: &str, name: &str) -> Result<(), PluginError> {
    let mut chars = name.chars();
    let first_ok = chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    if first_ok && chars.all(|c| c.is_ascii_alphanumeric() || c == '_') {
        Ok(())
    } else {
        Err(error(
            field,
            format!(
                "`{name}` is not a valid name (letters, digits and `_`, not starting with a digit)"
            ),
        ))
    }
}

fn part_constants(raw: &RawPart, part: usize, field: &str) -> Result<Vec<Constant>, PluginError> {
    let count = raw.count.unwrap_or(0);
    let names: Vec<String> = match (&raw.constant_prefix, &raw.constants) {
        (Some(_), Some(_)) => {
            return Err(error(
                format!("{field}.constants"),
                "give `constant_prefix` or `constants`, not both",
            ))
        }
        (Some(prefix), None) => (0..count).map(|i| format!("{prefix}{i}")).collect(),
        (None, Some(names)) => {
            if names.len() != count as usize {
                return Err(error(
                    format!("{field}.constants"),
                    format!(
                        "expected {count} names (one per index), found {}",
                        names.len()
                    ),
                ));
            }
            names.clone()
        }
        (None, None) => Vec::new(),
    };
    names
        .into_iter()
        .enumerate()
        .map(|(value, name)| {
            check_name(&format!("{field}.constants"), &name)?;
            Ok(Constant {
                name,
                value: value as i64,
                part: Some(part),
            })
        })
        .collect()
}

/// `[values]`: names of argument values, which index no part.
fn value_constants(
    values: &std::collections::BTreeMap<String, i64>,
) -> Result<Vec<Constant>, PluginError> {
    (values.iter())
        .map(|(name, value)| {
            check_name(&format!("values.{name}"), name)?;
            Ok(Constant {
                name: name.clone(),
                value: *value,
                part: None,
            })
        })
        .collect()
}

fn check_unique_constants(constants: &[Constant]) -> Result<(), PluginError> {
    let mut seen = BTreeSet::new();
    for c in constants {
        if !seen.insert(c.name.as_str()) {
            return Err(error(
                "part",
                format!("constant `${}` is defined twice", c.name),
            ));
        }
    }
    Ok(())
}

fn convert_part(raw: &RawPart, field: &str) -> Result<Part, PluginError> {
    check_name(&format!("{field}.name"), &raw.name)?;
    if let Some(count) = raw.count {
        if count == 0 || count > MAX_COUNT {
            return Err(error(
                format!("{field}.count"),
                format!("expected 1 to {MAX_COUNT}, found {count}"),
            ));
        }
    }
    let count = raw.count.unwrap_or(0);
    if let Some(bad) = raw.male.iter().find(|&&m| m >= count) {
        return Err(error(
            format!("{field}.male"),
            format!("index {bad} is out of range (the part has {count})"),
        ));
    }
    let mut operations = Vec::new();
    let mut names = BTreeSet::new();
    for (j, raw_op) in raw.operation.iter().enumerate() {
        let op_field = format!("{field}.operation[{j}]");
        if !names.insert(raw_op.name.as_str()) {
            return Err(error(
                format!("{op_field}.name"),
                format!("operation `{}` is defined twice", raw_op.name),
            ));
        }
        if raw_op.requires_male && raw.male.is_empty() {
            return Err(error(
                format!("{op_field}.requires_male"),
                "the part lists no `male` indices",
            ));
        }
        let operation = convert_operation(raw_op, &op_field)?;
        check_kind(&operation, raw.count, &op_field)?;
        operations.push(operation);
    }
    Ok(Part {
        name: raw.name.clone(),
        count: raw.count,
        male: raw.male.clone(),
        operations,
    })
}

fn convert_operation(raw: &RawOperation, field: &str) -> Result<Operation, PluginError> {
    check_name(&format!("{field}.name"), &raw.name)?;
    let mut params: Vec<Param> = Vec::new();
    for (k, p) in raw.params.iter().enumerate() {
        let p_field = format!("{field}.params[{k}]");
        check_name(&format!("{p_field}.name"), &p.name)?;
        if params.iter().any(|q| q.name == p.name) {
            return Err(error(
                format!("{p_field}.name"),
                format!("parameter `{}` is defined twice", p.name),
            ));
        }
        params.push(Param {
            name: p.name.clone(),
            ty: convert_type(p, &p_field)?,
        });
    }
    Ok(Operation {
        name: raw.name.clone(),
        doc: raw.doc.clone(),
        params,
        requires_male: raw.requires_male,
        inverse: None,
        kind: raw.kind.unwrap_or_default(),
        steps: steps(raw, field)?,
    })
}

/// The most planner steps one move is made of: its duration stays far inside the simulator's
/// longest run.
const MAX_MOVE_STEPS: u64 = 64;

/// `steps`: only a `move` has them, from 1 to [`MAX_MOVE_STEPS`].
fn steps(raw: &RawOperation, field: &str) -> Result<u64, PluginError> {
    let Some(steps) = raw.steps else {
        return Ok(1);
    };
    let field = format!("{field}.steps");
    if raw.kind != Some(OperationKind::Move) {
        return Err(error(field, "only an operation of kind `move` has `steps`"));
    }
    if !(1..=MAX_MOVE_STEPS).contains(&steps) {
        let message = format!("expected 1 to {MAX_MOVE_STEPS} steps, found {steps}");
        return Err(error(field, message));
    }
    Ok(steps)
}

/// The parameters each kind starts with: what the models read.
fn kind_params(kind: OperationKind) -> (&'static [ParamShape], &'static str) {
    match kind {
        OperationKind::None => (&[], ""),
        OperationKind::Extend | OperationKind::Retract => (&[], "no parameters"),
        OperationKind::Turn => (
            &[ParamShape::Int, ParamShape::Int, ParamShape::Bool],
            "parameters `from` (int), `to` (int) and the direction (bool) first",
        ),
        OperationKind::TurnTo => (
            &[ParamShape::Int, ParamShape::Bool],
            "parameters `to` (int) and the direction (bool) first",
        ),
        OperationKind::Move => (&[], "at most 4 parameters, all integers"),
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum ParamShape {
    Int,
    Bool,
}

/// An operation's index and parameters must be what its kind's models read.
fn check_kind(op: &Operation, count: Option<u32>, field: &str) -> Result<(), PluginError> {
    let kind = op.kind;
    let name = kind.name();
    let field = format!("{field}.kind");
    if kind.is_latch() && count.is_none() {
        return Err(error(
            field,
            format!("kind `{name}` needs its part to have a `count` (the connectors)"),
        ));
    }
    let (shape, words) = kind_params(kind);
    let fits = op.params.len() >= shape.len()
        && op.params.iter().zip(shape).all(|(p, s)| {
            matches!(
                (&p.ty, s),
                (ParamType::Int { .. }, ParamShape::Int) | (ParamType::Bool, ParamShape::Bool)
            )
        });
    let exact = match kind {
        OperationKind::Extend | OperationKind::Retract => op.params.is_empty(),
        OperationKind::Move => {
            op.params.len() <= MAX_MOVE_PARAMS
                && op
                    .params
                    .iter()
                    .all(|p| matches!(p.ty, ParamType::Int { .. }))
        }
        _ => true,
    };
    if fits && exact {
        Ok(())
    } else {
        Err(error(
            field,
            format!("kind `{name}` takes {words}; `{}` does not", op.signature()),
        ))
    }
}

fn convert_type(raw: &RawParam, field: &str) -> Result<ParamType, PluginError> {
    match raw.ty.as_str() {
        "bool" if raw.min.is_none() && raw.max.is_none() && raw.values.is_none() => {
            Ok(ParamType::Bool)
        }
        "bool" => Err(error(
            field,
            "a `bool` parameter takes no `min`, `max` or `values`",
        )),
        "int" => {
            let min = raw.min.unwrap_or(i64::from(i32::MIN));
            let max = raw.max.unwrap_or(i64::from(i32::MAX));
            if min > max {
                return Err(error(
                    format!("{field}.min"),
                    format!("min {min} is greater than max {max}"),
                ));
            }
            if let Some(values) = &raw.values {
                if values.is_empty() {
                    return Err(error(format!("{field}.values"), "the list is empty"));
                }
                if let Some(bad) = values.iter().find(|v| !(min..=max).contains(*v)) {
                    return Err(error(
                        format!("{field}.values"),
                        format!("{bad} is outside {min} to {max}"),
                    ));
                }
            }
            Ok(ParamType::Int {
                min,
                max,
                values: raw.values.clone(),
            })
        }
        other => Err(error(
            format!("{field}.type"),
            format!("unknown type `{other}`; expected `int` or `bool`"),
        )),
    }
}

/// Parses every `inverse` of part `i` and checks that undoing twice gives the original back.
fn resolve_inverses(parts: &mut [Part], i: usize, raw: &RawPart) -> Result<(), PluginError> {
    for (j, raw_op) in raw.operation.iter().enumerate() {
        let Some(text) = &raw_op.inverse else {
            continue;
        };
        let field = format!("part[{i}].operation[{j}].inverse");
        let inverse = parse_inverse(text, &parts[i], j, &field)?;
        parts[i].operations[j].inverse = Some(inverse);
    }
    for (j, op) in parts[i].operations.iter().enumerate() {
        let Some(inverse) = &op.inverse else { continue };
        let field = format!("part[{i}].operation[{j}].inverse");
        check_round_trip(&parts[i], j, inverse, &field)?;
    }
    Ok(())
}

/// `name(arg, ...)` where each arg is a parameter name, `!param`, `-param` or a literal.
fn parse_inverse(text: &str, part: &Part, op: usize, field: &str) -> Result<Inverse, PluginError> {
    if text.len() > MAX_INVERSE_LEN {
        return Err(error(
            field,
            format!("longer than {MAX_INVERSE_LEN} characters"),
        ));
    }
    let tokens: Vec<Token> = lex(text).tokens.into_iter().map(|(t, _)| t).collect();
    let bad = |what: &str| {
        error(
            field,
            format!("cannot read `{text}`: {what}; expected `operation(arg, ...)`"),
        )
    };
    let [Token::Ident(name), Token::LParen, rest @ ..] = tokens.as_slice() else {
        return Err(bad("no operation name and `(`"));
    };
    let (target, target_op) = part.operation(name).ok_or_else(|| {
        error(
            field,
            format!("part `{}` has no operation `{name}`", part.name),
        )
    })?;
    let params = &part.operations[op].params;
    let mut args = Vec::new();
    let mut rest = rest;
    while let Some((template, tail)) = parse_template(rest, params) {
        args.push(template.map_err(|e| error(field, e.message))?);
        rest = match tail {
            [Token::Comma, tail @ ..] => tail,
            _ => tail,
        };
    }
    if rest != [Token::RParen, Token::Eof] {
        return Err(bad("unexpected text"));
    }
    if args.len() != target_op.params.len() {
        return Err(error(
            field,
            format!(
                "`{name}` takes {} arguments, the inverse gives {}",
                target_op.params.len(),
                args.len()
            ),
        ));
    }
    if part.operations[op].requires_male != target_op.requires_male {
        return Err(error(
            field,
            "an operation and its inverse must agree on `requires_male`",
        ));
    }
    for (k, (template, param)) in args.iter().zip(&target_op.params).enumerate() {
        check_template_type(template, params, &param.ty)
            .map_err(|m| error(field, format!("argument {} of `{name}`: {m}", k + 1)))?;
    }
    Ok(Inverse {
        operation: target,
        args,
    })
}

type TemplateParse<'a> = Option<(Result<Template, PluginError>, &'a [Token])>;

fn parse_template<'a>(tokens: &'a [Token], params: &[Param]) -> TemplateParse<'a> {
    let (first, rest) = tokens.split_first()?;
    let template = match first {
        Token::Bang | Token::Minus => {
            let (inner, rest) = parse_template(rest, params)?;
            let wrap = if *first == Token::Bang {
                Template::Not
            } else {
                Template::Negate
            };
            return Some((inner.map(|t| wrap(Box::new(t))), rest));
        }
        Token::Ident(name) => match params.iter().position(|p| &p.name == name) {
            Some(k) => Ok(Template::Param(k)),
            None => Err(error("", format!("`{name}` is not a parameter"))),
        },
        Token::Int(Some(n)) => Ok(Template::Int(*n)),
        Token::True => Ok(Template::Bool(true)),
        Token::False => Ok(Template::Bool(false)),
        _ => return None,
    };
    Some((template, rest))
}

fn check_template_type(
    template: &Template,
    params: &[Param],
    target: &ParamType,
) -> Result<(), String> {
    let want_bool = *target == ParamType::Bool;
    match template {
        Template::Param(k) => {
            let source = &params[*k].ty;
            match (source, target) {
                (ParamType::Bool, ParamType::Bool) => Ok(()),
                (ParamType::Int { .. }, ParamType::Int { .. }) => int_fits(source, target, false),
                _ => Err(format!(
                    "`{}` is {}, expected {}",
                    params[*k].name,
                    source.describe(),
                    target.describe()
                )),
            }
        }
        Template::Not(inner) if want_bool => check_template_type(inner, params, target),
        Template::Negate(inner) => match (inner.as_ref(), target) {
            (Template::Param(k), ParamType::Int { .. }) => int_fits(&params[*k].ty, target, true),
            _ => Err("`-` applies to a number parameter only".into()),
        },
        Template::Int(n) if target.allows(*n) => Ok(()),
        Template::Bool(_) if want_bool => Ok(()),
        _ => Err(format!("expected {}", target.describe())),
    }
}

/// Every value `source` allows (negated if asked) must be allowed by `target`.
fn int_fits(source: &ParamType, target: &ParamType, negate: bool) -> Result<(), String> {
    let ParamType::Int { min, max, values } = source else {
        return Err("expected a number parameter".into());
    };
    let sign = if negate { -1 } else { 1 };
    let fits = match values {
        Some(values) => values.iter().all(|v| target.allows(sign * v)),
        None => {
            target.allows(sign * min) && target.allows(sign * max) && target_is_interval(target)
        }
    };
    if fits {
        Ok(())
    } else {
        Err(format!(
            "its values do not all fit the target's range ({})",
            target.allowed()
        ))
    }
}

fn target_is_interval(target: &ParamType) -> bool {
    matches!(target, ParamType::Int { values: None, .. })
}

/// Undoing the undo must give the original operation and arguments back, for any arguments.
fn check_round_trip(
    part: &Part,
    op: usize,
    inverse: &Inverse,
    field: &str,
) -> Result<(), PluginError> {
    let target = &part.operations[inverse.operation];
    let Some(back) = &target.inverse else {
        return Err(error(
            field,
            format!(
                "`{}` has no inverse, so `{}` cannot be undone twice",
                target.name, part.operations[op].name
            ),
        ));
    };
    if back.operation != op {
        return Err(error(
            field,
            format!(
                "the inverse of `{}` is not `{}`",
                target.name, part.operations[op].name
            ),
        ));
    }
    for (k, outer) in back.args.iter().enumerate() {
        let composed = substitute(outer, &inverse.args);
        if simplify(composed) != Template::Param(k) {
            return Err(error(
                field,
                format!(
                    "undoing twice does not give argument `{}` back",
                    part.operations[op].params[k].name
                ),
            ));
        }
    }
    Ok(())
}

fn substitute(template: &Template, args: &[Template]) -> Template {
    match template {
        Template::Param(k) => args.get(*k).cloned().unwrap_or(Template::Int(0)),
        Template::Not(inner) => Template::Not(Box::new(substitute(inner, args))),
        Template::Negate(inner) => Template::Negate(Box::new(substitute(inner, args))),
        other => other.clone(),
    }
}

fn simplify(template: Template) -> Template {
    match template {
        Template::Not(inner) => match simplify(*inner) {
            Template::Not(x) => *x,
            other => Template::Not(Box::new(other)),
        },
        Template::Negate(inner) => match simplify(*inner) {
            Template::Negate(x) => *x,
            other => Template::Negate(Box::new(other)),
        },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GRIPPER: &str = "name = \"g\"\n[[part]]\nname = \"Grip\"\ncount = 2\nmale = [0]\n";

    fn with_ops(ops: &str) -> Result<RobotApi, PluginError> {
        RobotApi::from_toml(&format!("{GRIPPER}{ops}"))
    }

    #[test]
    fn an_inverse_that_does_not_undo_itself_is_refused() {
        let ops = "[[part.operation]]\nname = \"a\"\nparams = [{ name = \"x\", type = \"int\", min = 0, max = 9 }]\ninverse = \"b(x)\"\n\
                   [[part.operation]]\nname = \"b\"\nparams = [{ name = \"y\", type = \"int\", min = 0, max = 9 }]\ninverse = \"a(0)\"\n";
        let err = with_ops(ops).expect_err("b(a(x)) is not x");
        assert_eq!(err.field, "part[0].operation[0].inverse");
        assert!(err.message.contains("undoing twice"), "{err}");
    }

    #[test]
    fn inverse_errors_name_the_field() {
        let unknown = with_ops("[[part.operation]]\nname = \"a\"\ninverse = \"zap()\"\n")
            .expect_err("unknown op");
        assert_eq!(
            unknown.to_string(),
            "field `part[0].operation[0].inverse`: part `Grip` has no operation `zap`"
        );
        let one_way = with_ops("[[part.operation]]\nname = \"a\"\ninverse = \"b()\"\n[[part.operation]]\nname = \"b\"\n").expect_err("no way back");
        assert!(one_way.message.contains("has no inverse"), "{one_way}");
        let bad_type = with_ops("[[part.operation]]\nname = \"a\"\nparams = [{ name = \"on\", type = \"bool\" }]\ninverse = \"a(-on)\"\n").expect_err("type");
        assert!(bad_type.message.contains("number parameter"), "{bad_type}");
    }

    #[test]
    fn unknown_fields_and_bad_values_are_named() {
        let typo = RobotApi::from_toml("name = \"g\"\nconectors = \"x\"\n").expect_err("typo");
        assert!(typo.message.contains("unknown field `conectors`"), "{typo}");
        let male = with_ops("").and_then(|_| {
            RobotApi::from_toml("name = \"g\"\n[[part]]\nname = \"P\"\ncount = 2\nmale = [5]\n")
        });
        assert_eq!(male.expect_err("range").field, "part[0].male");
        let ty = RobotApi::from_toml("name = \"g\"\n[[part]]\nname = \"P\"\n[[part.operation]]\nname = \"a\"\nparams = [{ name = \"x\", type = \"float\" }]\n");
        assert_eq!(
            ty.expect_err("type").field,
            "part[0].operation[0].params[0].type"
        );
    }

    #[test]
    fn moves_take_integers_their_steps_and_a_duration() {
        let plugin = |op: &str, timing: &str| {
            RobotApi::from_toml(&format!(
                "name = \"c\"\n[values]\nUP = 3\n{timing}[[part]]\nname = \"Cube\"\n\
                 [[part.operation]]\nname = \"go\"\nkind = \"move\"\n{op}"
            ))
        };
        let int = "params = [{ name = \"d\", type = \"int\", min = -3, max = 3 }]\n";
        let api = plugin(&format!("{int}steps = 2\n"), "").expect("a move");
        let op = &api.parts[0].operations[0];
        assert_eq!((op.kind, op.steps), (OperationKind::Move, 2));
        let up = api.constant("UP").expect("a value name");
        assert_eq!((up.value, up.part), (3, None));
        let boolean = plugin("params = [{ name = \"b\", type = \"bool\" }]\n", "");
        assert_eq!(
            boolean.expect_err("a bool").field,
            "part[0].operation[0].kind"
        );
        let steps = plugin(&format!("{int}steps = 0\n"), "").expect_err("no steps");
        assert_eq!(steps.field, "part[0].operation[0].steps");
        let untimed = plugin(int, "[[timing]]\nname = \"t\"\n").expect_err("no move_ms");
        assert!(untimed.message.contains("`move_ms`"), "{untimed}");
        let timed = plugin(int, "[[timing]]\nname = \"t\"\nmove_ms = 700\n").expect("timed");
        assert_eq!(timed.timing[0].durations.move_ms, 700);
        let turn_steps = RobotApi::from_toml(
            "name = \"g\"\n[[part]]\nname = \"P\"\n[[part.operation]]\nname = \"a\"\nsteps = 2\n",
        );
        assert_eq!(
            turn_steps.expect_err("steps of a none").field,
            "part[0].operation[0].steps"
        );
    }

    #[test]
    fn a_huge_count_is_refused_before_anything_is_built() {
        let huge = RobotApi::from_toml(
            "name = \"g\"\n[[part]]\nname = \"P\"\ncount = 1000000000\nconstant_prefix = \"P_\"\n",
        )
        .expect_err("count");
        assert_eq!(huge.field, "part[0].count");
        assert!(huge.message.contains("expected 1 to 255"), "{huge}");
    }

    #[test]
    fn an_unknown_kind_is_refused_at_its_place_with_the_closest_name() {
        let text = format!("{GRIPPER}[[part.operation]]\nname = \"close\"\nkind = \"extnd\"\n");
        let err = RobotApi::from_toml(&text).expect_err("unknown kind");
        assert!(err.message.contains("unknown variant `extnd`"), "{err}");
        assert_eq!(err.hint.as_deref(), Some("did you mean `extend`?"));
        let span = err.span.expect("located");
        assert_eq!(&text[span], "\"extnd\"");
    }

    #[test]
    fn a_kind_whose_parameters_do_not_fit_is_refused_at_the_kind() {
        let text = format!(
            "{GRIPPER}[[part.operation]]\nname = \"bend\"\nkind = \"turn\"\n\
             params = [{{ name = \"to\", type = \"int\" }}, {{ name = \"up\", type = \"bool\" }}]\n"
        );
        let err = RobotApi::from_toml(&text).expect_err("turn needs from, to, direction");
        assert_eq!(err.field, "part[0].operation[0].kind");
        assert!(err.message.contains("`from` (int), `to` (int)"), "{err}");
        assert_eq!(&text[err.span.expect("located")], "\"turn\"");
        let turn_to = text.replace("\"turn\"", "\"turn_to\"");
        assert!(
            RobotApi::from_toml(&turn_to).is_ok(),
            "to, direction fit turn_to"
        );
        let latch = "name = \"g\"\n[[part]]\nname = \"Arm\"\n[[part.operation]]\nname = \"grab\"\nkind = \"extend\"\n";
        let err = RobotApi::from_toml(latch).expect_err("extend needs connectors");
        assert!(err.message.contains("`count`"), "{err}");
        let with_args = with_ops("[[part.operation]]\nname = \"close\"\nkind = \"retract\"\nparams = [{ name = \"x\", type = \"bool\" }]\n")
            .expect_err("retract takes no parameters");
        assert!(with_args.message.contains("no parameters"), "{with_args}");
    }

    /// A gripper that latches and a hinge that turns, before its `[[timing]]` tables.
    const LATCH_AND_TURN: &str = "name = \"g\"\n\
        [[part]]\nname = \"Grip\"\ncount = 2\nmale = [0]\n\
        [[part.operation]]\nname = \"close\"\nkind = \"extend\"\n\
        [[part.operation]]\nname = \"open\"\nkind = \"retract\"\n\
        [[part]]\nname = \"Hinge\"\n\
        [[part.operation]]\nname = \"bend\"\nkind = \"turn_to\"\n\
        params = [{ name = \"to\", type = \"int\" }, { name = \"up\", type = \"bool\" }]\n";

    const FULL: &str = "extend_ms = 1000\nretract_ms = 500\n\
        turn_first_quarter_ms = 800\nturn_further_quarter_ms = 600\n";

    fn with_timing(tables: &str) -> Result<RobotApi, PluginError> {
        RobotApi::from_toml(&format!("{LATCH_AND_TURN}{tables}"))
    }

    #[test]
    fn timing_presets_are_read_in_order_and_a_turn_adds_its_further_quarters() {
        let api = with_timing(&format!(
            "[[timing]]\nname = \"servo\"\ndoc = \"quick\"\n{FULL}\
             [[timing]]\nname = \"slow\"\n{}",
            FULL.replace("= 800", "= 2000")
        ))
        .expect("two presets");
        let names: Vec<&str> = api.timing.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["servo", "slow"]);
        assert_eq!(api.timing[0].doc, "quick");
        let servo = api.timing[0].durations;
        assert_eq!((servo.extend_ms, servo.retract_ms), (1000, 500));
        assert_eq!([0, 1, 2, 4].map(|q| servo.turn_ms(q)), [0, 800, 1400, 2600]);
        assert_eq!(api.timing[1].durations.turn_ms(1), 2000);
        assert_eq!(servo.turn_ms(u64::MAX), u64::MAX, "saturates");
        assert!(with_timing("").expect("none").timing.is_empty());
    }

    #[test]
    fn a_timing_preset_named_twice_or_not_at_all_is_refused_at_its_name() {
        let text = format!(
            "{LATCH_AND_TURN}[[timing]]\nname = \"servo\"\n{FULL}[[timing]]\nname = \"servo\"\n{FULL}"
        );
        let twice = RobotApi::from_toml(&text).expect_err("twice");
        assert_eq!(
            twice.to_string(),
            "field `timing[1].name`: timing preset `servo` is defined twice"
        );
        let span = twice.span.expect("located");
        assert_eq!(&text[span.clone()], "\"servo\"");
        assert!(
            span.start > text.find("servo").unwrap_or(0),
            "the second one"
        );
        let empty = with_timing(&format!("[[timing]]\nname = \"\"\n{FULL}")).expect_err("empty");
        assert_eq!(empty.field, "timing[0].name");
        assert!(empty.message.contains("needs a name"), "{empty}");
    }

    #[test]
    fn a_timing_preset_must_give_every_duration_the_robots_operations_take() {
        let no_turn = FULL.replace("turn_further_quarter_ms = 600\n", "");
        let text = format!("{LATCH_AND_TURN}[[timing]]\nname = \"servo\"\n{no_turn}");
        let err = RobotApi::from_toml(&text).expect_err("the hinge turns");
        assert_eq!(
            err.to_string(),
            "field `timing[0]`: timing preset `servo` gives no `turn_further_quarter_ms`, \
             which operation `bend` of part `Hinge` (kind `turn_to`) needs"
        );
        let table = &text[err.span.expect("located")];
        assert!(
            table.starts_with("[[timing]]\nname = \"servo\""),
            "the table: {table}"
        );
        let no_extend = FULL.replace("extend_ms = 1000\n", "");
        let err = with_timing(&format!("[[timing]]\nname = \"servo\"\n{no_extend}"))
            .expect_err("the gripper latches");
        assert!(
            err.message
                .contains("no `extend_ms`, which operation `close`"),
            "{err}"
        );
        // A robot that only latches needs no turn durations: they are 0, never used.
        let latches = "name = \"g\"\n[[part]]\nname = \"Grip\"\ncount = 2\nmale = [0]\n\
                       [[part.operation]]\nname = \"close\"\nkind = \"extend\"\n\
                       [[timing]]\nname = \"servo\"\nextend_ms = 1000\n";
        let api = RobotApi::from_toml(latches).expect("no turn, no retract");
        assert_eq!(api.timing[0].durations.turn_ms(1), 0);
        assert_eq!(api.timing[0].durations.retract_ms, 0);
    }

    #[test]
    fn a_timing_presets_unknown_field_or_absurd_value_is_named() {
        let text = format!("{LATCH_AND_TURN}[[timing]]\nname = \"servo\"\n{FULL}extnd_ms = 1\n");
        let typo = RobotApi::from_toml(&text).expect_err("typo");
        assert!(typo.message.contains("unknown field `extnd_ms`"), "{typo}");
        assert_eq!(typo.hint.as_deref(), Some("did you mean `extend_ms`?"));
        assert_eq!(&text[typo.span.expect("located")], "extnd_ms");
        let long = FULL.replace("= 1000", "= 1000000001");
        let err = with_timing(&format!("[[timing]]\nname = \"servo\"\n{long}")).expect_err("long");
        assert_eq!(err.field, "timing[0].extend_ms");
        assert!(err.message.contains("at most 1000000000 ms"), "{err}");
        let negative = FULL.replace("= 500", "= -500");
        let err = with_timing(&format!("[[timing]]\nname = \"servo\"\n{negative}"))
            .expect_err("negative");
        assert!(err.span.is_some(), "{err}");
    }
}
