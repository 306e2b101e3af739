//! Every robot's JSON Schema (`RobotKind::schema`, `robots/NAME/NAME.schema.json`) is a valid
//! draft 2020-12 schema that every example data file meets, and it agrees with the robot's
//! reader: on documents mutated from the examples, whatever the schema refuses the reader
//! refuses too, and both refuse a missing required field or a value of the wrong type.

use dynarole_world::{RobotKind, Rotation};
use jsonschema::Validator;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The workspace's root folder.
fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `path` as from the workspace's root, for messages.
fn shown(path: &Path) -> String {
    let root = workspace();
    path.strip_prefix(&root)
        .unwrap_or(path)
        .display()
        .to_string()
}

/// A robot kind of the registry with its schema and its example data files.
struct Robot {
    kind: &'static dyn RobotKind,
    schema: Value,
    validator: Validator,
    examples: Vec<(PathBuf, Value)>,
}

impl Robot {
    /// The reader's verdict on `doc`, through the registry (which also checks `robot`).
    fn reads(&self, doc: &Value) -> Result<(), String> {
        dynarole_robots::read_configuration(&doc.to_string())
            .map(|_| ())
            .map_err(|e| e.to_string())
    }
}

/// The schema's text parsed, checked against the draft 2020-12 meta-schema, and compiled.
fn compiled(name: &str, text: &str) -> (Value, Validator) {
    let schema: Value =
        serde_json::from_str(text).unwrap_or_else(|e| panic!("{name}: the schema is JSON: {e}"));
    if let Err(e) = jsonschema::draft202012::meta::validate(&schema) {
        panic!(
            "{name}: not a valid draft 2020-12 schema: {e} at {}",
            e.instance_path()
        );
    }
    assert_eq!(
        schema["$schema"], "https://json-schema.org/draft/2020-12/schema",
        "{name}: the schema names its draft"
    );
    let validator = jsonschema::draft202012::new(&schema)
        .unwrap_or_else(|e| panic!("{name}: the schema compiles: {e}"));
    (schema, validator)
}

/// Every `.json` file under `folder` (its subfolders too) that holds an object, parsed, in path
/// order.
fn json_files(folder: &Path) -> Vec<(PathBuf, Value)> {
    let mut found = Vec::new();
    let mut folders = vec![folder.to_path_buf()];
    while let Some(dir) = folders.pop() {
        let entries = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: readable folder: {e}", dir.display()));
        for entry in entries {
            let path = entry.expect("a folder entry").path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "json") {
                let text = std::fs::read_to_string(&path)
                    .unwrap_or_else(|e| panic!("{}: readable: {e}", shown(&path)));
                let value: Value = serde_json::from_str(&text)
                    .unwrap_or_else(|e| panic!("{}: JSON: {e}", shown(&path)));
                // An array is a planner's plan of worlds (RoFI's), which `import` reads: a
                // configuration file is an object.
                if !value.is_array() {
                    found.push((path, value));
                }
            }
        }
    }
    found.sort_by(|a, b| a.0.cmp(&b.0));
    found
}

/// Every robot of the registry, each with its schema (which it must have) and the data files
/// of its folder's `examples/` (`robots/NAME/examples/`, which must hold some).
fn registered() -> Vec<Robot> {
    let robots: Vec<Robot> = dynarole_robots::robots()
        .kinds()
        .map(|kind| {
            let text = kind
                .schema()
                .unwrap_or_else(|| panic!("robot {} has no schema", kind.name()));
            let (schema, validator) = compiled(kind.name(), text);
            let folder = workspace()
                .join("robots")
                .join(kind.name())
                .join("examples");
            let examples = json_files(&folder);
            assert!(
                !examples.is_empty(),
                "{}: no example data files in {}",
                kind.name(),
                folder.display()
            );
            Robot {
                kind,
                schema,
                validator,
                examples,
            }
        })
        .collect();
    assert!(robots.len() >= 2, "the registry's robots are found");
    robots
}

/// The schema validation errors of `doc`, one per line.
fn errors(validator: &Validator, doc: &Value) -> String {
    validator
        .iter_errors(doc)
        .map(|e| format!("  {}: {e}", e.instance_path()))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `schema` with a local `$ref` (`#/$defs/...`) followed within `root`.
fn resolved<'a>(root: &'a Value, schema: &'a Value) -> &'a Value {
    match schema["$ref"].as_str() {
        Some(reference) => {
            let pointer = reference
                .strip_prefix('#')
                .unwrap_or_else(|| panic!("only local references: {reference}"));
            resolved(
                root,
                root.pointer(pointer)
                    .unwrap_or_else(|| panic!("{reference} resolves")),
            )
        }
        None => schema,
    }
}

/// The schema of a module record: that of the items of `modules`.
fn module_schema(root: &Value) -> &Value {
    resolved(root, &root["properties"]["modules"]["items"])
}

/// The `required` fields of an object schema.
fn required(schema: &Value) -> Vec<String> {
    schema["required"]
        .as_array()
        .map(|fields| {
            fields
                .iter()
                .filter_map(|f| f.as_str().map(str::to_string))
                .collect()
        })
        .unwrap_or_default()
}

/// Whether an object schema refuses fields it does not list.
fn forbids_unknown(schema: &Value) -> bool {
    schema["additionalProperties"] == json!(false)
}

/// What a mutated document must get from the schema and the reader.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Expect {
    /// A structural defect (a required field missing, a value of the wrong type, an unknown
    /// field where the schema forbids them): both refuse.
    BothRefuse,
    /// An unknown field where the schema allows them: the reader reads it exactly when the
    /// schema accepts it.
    Agree,
    /// Any other change: if the schema refuses it, so does the reader.
    RefusedBySchemaRefusedByReader,
}

/// One document derived from an example.
struct Mutant {
    what: String,
    doc: Value,
    expect: Expect,
}

/// A JSON pointer's token for `key`.
fn token(key: &str) -> String {
    key.replace('~', "~0").replace('/', "~1")
}

/// The JSON pointers of the values of `value` worth mutating: every field of every object
/// and, in arrays, every item of an array of scalars but only the first of an array of arrays
/// or objects (the others have the same shape).
fn pointers(value: &Value, at: &str, out: &mut Vec<String>) {
    match value {
        Value::Object(fields) => {
            for (key, field) in fields {
                let pointer = format!("{at}/{}", token(key));
                out.push(pointer.clone());
                pointers(field, &pointer, out);
            }
        }
        Value::Array(items) => {
            let scalars = items.iter().all(|i| !i.is_array() && !i.is_object());
            let count = if scalars { items.len() } else { 1 };
            for (k, item) in items.iter().enumerate().take(count) {
                let pointer = format!("{at}/{k}");
                out.push(pointer.clone());
                pointers(item, &pointer, out);
            }
        }
        _ => {}
    }
}

/// A value of another JSON type than `value`, which no field accepting `value` accepts.
fn wrong_type(value: &Value) -> Value {
    match value {
        Value::String(_) => json!(7),
        _ => json!("seven"),
    }
}

/// Other values of the same type: a string changed, integers moved by one either way, a
/// fraction added to a number, an array one item longer and one shorter, and null.
fn other_values(value: &Value) -> Vec<Value> {
    let mut values = vec![Value::Null];
    match value {
        Value::String(s) => values.push(json!(format!("{s}?"))),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                values.extend([json!(i + 1), json!(-i - 1)]);
            }
            if let Some(x) = n.as_f64() {
                values.push(json!(x + 0.5));
            }
        }
        Value::Array(items) => {
            if let Some(last) = items.last() {
                let mut longer = items.clone();
                longer.push(last.clone());
                values.push(Value::Array(longer));
                values.push(Value::Array(items[..items.len() - 1].to_vec()));
            }
        }
        _ => {}
    }
    values
}

/// `doc` with the field `key` of the object at `parent` removed.
fn without(doc: &Value, parent: &str, key: &str) -> Value {
    let mut doc = doc.clone();
    if let Some(object) = doc.pointer_mut(parent).and_then(Value::as_object_mut) {
        object.remove(key);
    }
    doc
}

/// `doc` with the value at `pointer` replaced by `value`.
fn with(doc: &Value, pointer: &str, value: Value) -> Value {
    let mut doc = doc.clone();
    if let Some(slot) = doc.pointer_mut(pointer) {
        *slot = value;
    }
    doc
}

/// `doc` with the field `key` added to the object at `parent`.
fn with_field(doc: &Value, parent: &str, key: &str, value: Value) -> Value {
    let mut doc = doc.clone();
    if let Some(object) = doc.pointer_mut(parent).and_then(Value::as_object_mut) {
        object.insert(key.to_string(), value);
    }
    doc
}

/// The field name no robot has.
const UNKNOWN_FIELD: &str = "not_a_field_of_this_robot";

/// The documents derived from `doc` (a valid example) under `schema`: each required field of
/// the top level and of every module dropped; each value worth mutating (`pointers`) given the
/// wrong type, or other values of its type, or dropped when it is a field; an unknown field
/// added to the top level and to the first module (refused by both where the schema forbids
/// unknown fields, and by neither otherwise).
fn mutants(schema: &Value, doc: &Value) -> Vec<Mutant> {
    let module = module_schema(schema);
    let mut out = Vec::new();
    let mut push =
        |what: String, doc: Value, expect: Expect| out.push(Mutant { what, doc, expect });
    for field in required(schema) {
        push(
            format!("without the required field {field}"),
            without(doc, "", &field),
            Expect::BothRefuse,
        );
    }
    let modules = doc["modules"].as_array().map_or(0, Vec::len);
    for i in 0..modules {
        for field in required(module) {
            push(
                format!("without modules[{i}]'s required field {field}"),
                without(doc, &format!("/modules/{i}"), &field),
                Expect::BothRefuse,
            );
        }
    }
    let mut paths = Vec::new();
    pointers(doc, "", &mut paths);
    for pointer in &paths {
        let Some(value) = doc.pointer(pointer) else {
            continue;
        };
        push(
            format!("{pointer} of the wrong type"),
            with(doc, pointer, wrong_type(value)),
            Expect::BothRefuse,
        );
        for other in other_values(value) {
            push(
                format!("{pointer} = {other}"),
                with(doc, pointer, other),
                Expect::RefusedBySchemaRefusedByReader,
            );
        }
        if let Some((parent, key)) = pointer.rsplit_once('/') {
            if doc.pointer(parent).is_some_and(Value::is_object) {
                push(
                    format!("without {pointer}"),
                    without(doc, parent, &key.replace("~1", "/").replace("~0", "~")),
                    Expect::RefusedBySchemaRefusedByReader,
                );
            }
        }
    }
    let unknown = |object: &Value| {
        if forbids_unknown(object) {
            Expect::BothRefuse
        } else {
            Expect::Agree
        }
    };
    push(
        format!("with an unknown top-level field {UNKNOWN_FIELD}"),
        with_field(doc, "", UNKNOWN_FIELD, json!(1)),
        unknown(schema),
    );
    if modules > 0 {
        push(
            format!("with an unknown field {UNKNOWN_FIELD} in modules[0]"),
            with_field(doc, "/modules/0", UNKNOWN_FIELD, json!(1)),
            unknown(module),
        );
    }
    out
}

#[test]
fn every_schema_is_a_valid_draft_2020_12_schema_of_its_robots_files() {
    for robot in registered() {
        let name = robot.kind.name();
        assert_eq!(
            robot.schema["type"], "object",
            "{name}: a file is an object"
        );
        assert_eq!(
            robot.schema["properties"]["robot"]["const"],
            robot.kind.file_tag(),
            "{name}: the `robot` field is the kind's file tag"
        );
        // A robot whose connections are implied (cubes that share a face) lists none.
        let lists_connections = robot.schema["properties"]["connections"].is_object();
        let needed = ["name", "robot", "modules", "connections"];
        for field in needed
            .iter()
            .filter(|f| **f != "connections" || lists_connections)
        {
            assert!(
                required(&robot.schema).iter().any(|f| f == field),
                "{name}: {field} is required (every reader needs it)"
            );
        }
        assert!(
            module_schema(&robot.schema)["properties"].is_object(),
            "{name}: the module record's fields are listed"
        );
    }
}

/// Every field listed in a schema (at the top level, in `$defs`, in items) has a title and a
/// description: the problems found.
fn undocumented(schema: &Value, at: &str, out: &mut Vec<String>) {
    if let Some(fields) = schema["properties"].as_object() {
        for (key, field) in fields {
            for word in ["title", "description"] {
                if field[word].as_str().is_none_or(|t| t.trim().is_empty()) {
                    out.push(format!("{at}/properties/{key} has no {word}"));
                }
            }
            undocumented(field, &format!("{at}/properties/{key}"), out);
        }
    }
    if let Some(defs) = schema["$defs"].as_object() {
        for (key, def) in defs {
            undocumented(def, &format!("{at}/$defs/{key}"), out);
        }
    }
    undocumented_items(schema, at, out);
}

fn undocumented_items(schema: &Value, at: &str, out: &mut Vec<String>) {
    if schema["items"].is_object() {
        undocumented(&schema["items"], &format!("{at}/items"), out);
    }
    for (k, item) in schema["prefixItems"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        undocumented(item, &format!("{at}/prefixItems/{k}"), out);
    }
}

#[test]
fn every_field_of_every_schema_has_a_title_and_a_description() {
    for robot in registered() {
        let mut problems = Vec::new();
        undocumented(&robot.schema, "#", &mut problems);
        assert!(
            robot.schema["title"].is_string() && robot.schema["description"].is_string(),
            "{}: the schema has a title and a description",
            robot.kind.name()
        );
        assert!(
            problems.is_empty(),
            "{}:\n{}",
            robot.kind.name(),
            problems.join("\n")
        );
    }
}

#[test]
fn every_example_of_every_robot_meets_its_schema_and_is_read() {
    let mut count = 0;
    for robot in registered() {
        for (path, doc) in &robot.examples {
            assert!(
                robot.validator.is_valid(doc),
                "{} does not meet the {} schema:\n{}",
                shown(path),
                robot.kind.name(),
                errors(&robot.validator, doc)
            );
            if let Err(e) = robot.reads(doc) {
                panic!("{}: {e}", shown(path));
            }
            count += 1;
        }
    }
    assert!(count >= 2, "examples are found");
}

#[test]
fn what_the_tools_write_meets_the_schema_in_every_lattice_rotation() {
    for robot in registered() {
        for (path, doc) in &robot.examples {
            let config = dynarole_robots::read_configuration(&doc.to_string())
                .unwrap_or_else(|e| panic!("{}: {e}", shown(path)));
            let mut written = 0;
            for rotation in Rotation::all() {
                let Ok(turned) = config.transformed(rotation, [0, 0, 0]) else {
                    continue;
                };
                let text = turned.to_json_string();
                let value: Value = serde_json::from_str(&text)
                    .unwrap_or_else(|e| panic!("{}: written JSON: {e}", shown(path)));
                assert!(
                    robot.validator.is_valid(&value),
                    "{} turned by {:?}, as written, does not meet the {} schema:\n{}",
                    shown(path),
                    rotation.rows(),
                    robot.kind.name(),
                    errors(&robot.validator, &value)
                );
                written += 1;
            }
            assert!(written >= 1, "{}: not even unturned", shown(path));
        }
    }
}

#[test]
fn the_reader_refuses_whatever_the_schema_refuses() {
    for robot in registered() {
        let name = robot.kind.name();
        let mut refused_by_both = 0;
        for (path, doc) in &robot.examples {
            for mutant in mutants(&robot.schema, doc) {
                let schema_accepts = robot.validator.is_valid(&mutant.doc);
                let reader = robot.reads(&mutant.doc);
                let context = format!("{name}: {}, {}", shown(path), mutant.what);
                match mutant.expect {
                    Expect::BothRefuse => {
                        assert!(!schema_accepts, "{context}: the schema accepts it");
                        assert!(reader.is_err(), "{context}: the reader accepts it");
                    }
                    Expect::Agree => assert_eq!(
                        schema_accepts,
                        reader.is_ok(),
                        "{context}: the schema accepts it: {schema_accepts}, the reader: {reader:?}"
                    ),
                    Expect::RefusedBySchemaRefusedByReader => {}
                }
                if !schema_accepts {
                    assert!(
                        reader.is_err(),
                        "{context}: refused by the schema but read:\n{}",
                        errors(&robot.validator, &mutant.doc)
                    );
                    refused_by_both += 1;
                }
            }
        }
        assert!(refused_by_both > 0, "{name}: no mutant was refused");
        let unknown = with_field(&robot.examples[0].1, "", UNKNOWN_FIELD, json!(1));
        assert_eq!(
            robot.validator.is_valid(&unknown),
            !forbids_unknown(&robot.schema),
            "{name}: additionalProperties says what the schema does"
        );
    }
}

/// `module` (of `doc`) with every optional field the reader does without removed, except
/// `keep`: the fields are tried one by one, in order, in a document of that module alone.
fn stripped(robot: &Robot, doc: &Value, module: &Value, keep: &str) -> Value {
    let required = required(module_schema(&robot.schema));
    let alone = |m: &Value| {
        let mut d = doc.clone();
        d["modules"] = json!([m]);
        d["connections"] = json!([]);
        d
    };
    let mut module = module.clone();
    let keys: Vec<String> = module
        .as_object()
        .map(|o| o.keys().cloned().collect())
        .unwrap_or_default();
    for key in keys {
        if key == keep || required.contains(&key) {
            continue;
        }
        let mut candidate = module.clone();
        if let Some(fields) = candidate.as_object_mut() {
            fields.remove(&key);
        }
        if robot.reads(&alone(&candidate)).is_ok() {
            module = candidate;
        }
    }
    alone(&module)
}

#[test]
fn every_value_of_a_closed_set_of_a_module_field_is_read() {
    for robot in registered() {
        let name = robot.kind.name();
        let fields = module_schema(&robot.schema)["properties"]
            .as_object()
            .cloned()
            .unwrap_or_default();
        for (field, field_schema) in &fields {
            let Some(values) = resolved(&robot.schema, field_schema)["enum"].as_array() else {
                continue;
            };
            for value in values.iter().filter(|v| !v.is_null()) {
                let read = robot.examples.iter().any(|(_, doc)| {
                    let modules = doc["modules"].as_array().cloned().unwrap_or_default();
                    modules.iter().filter(|m| m.get(field).is_some()).any(|m| {
                        let alone = stripped(&robot, doc, m, field);
                        let mutant = with(
                            &alone,
                            &format!("/modules/0/{}", token(field)),
                            value.clone(),
                        );
                        robot.validator.is_valid(&mutant) && robot.reads(&mutant).is_ok()
                    })
                });
                assert!(
                    read,
                    "{name}: modules[].{field} = {value} is in the schema, but no one-module \
                     document with it is read"
                );
            }
        }
    }
}

/// The robot kept beside the CLI's example program (not in the registry): its schema file and
/// data files, read from its folder.
#[test]
fn the_outside_robots_examples_meet_its_schema() {
    let folder = workspace().join("crates/dynarole-cli/examples/hinged_cubes");
    let path = folder.join("hinged.schema.json");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: readable: {e}", shown(&path)));
    let (schema, validator) = compiled("hinged cubes", &text);
    let mut problems = Vec::new();
    undocumented(&schema, "#", &mut problems);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    let examples = json_files(&folder);
    let names: Vec<String> = examples
        .iter()
        .filter_map(|(p, _)| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    for expected in ["line4.json", "ring4.json"] {
        assert!(names.iter().any(|n| n == expected), "{expected} is found");
    }
    for (path, doc) in examples
        .iter()
        .filter(|(p, _)| !p.to_string_lossy().ends_with(".schema.json"))
    {
        assert_eq!(
            doc["robot"],
            schema["properties"]["robot"]["const"],
            "{}",
            shown(path)
        );
        assert!(
            validator.is_valid(doc),
            "{} does not meet its schema:\n{}",
            shown(path),
            errors(&validator, doc)
        );
        // Its reader is not a dependency here: the schema alone refuses the structural defects.
        for mutant in mutants(&schema, doc) {
            if mutant.expect == Expect::BothRefuse {
                assert!(
                    !validator.is_valid(&mutant.doc),
                    "{}, {}: the schema accepts it",
                    shown(path),
                    mutant.what
                );
            }
        }
    }
}
