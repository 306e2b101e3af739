//! `dynarole reverse`: print the reverse of a sequence as a complete, checkable file.

use crate::load::{self, Failure, PluginArgs};
use crate::render;
use dynarole_core::ast::{Item, SequenceDef, SourceFile};
use dynarole_core::format::format_items;
use std::path::Path;
use std::process::ExitCode;

pub fn run(
    path: &Path,
    sequence: &str,
    name: Option<&str>,
    plugins: &PluginArgs,
) -> Result<ExitCode, Failure> {
    if let Some(name) = name.filter(|n| !dynarole_core::lexer::is_identifier(n)) {
        return Err(Failure::Usage(format!(
            "--name `{}`: expected a name (a letter or `_`, then letters, digits or `_`; not a keyword)",
            name.escape_debug()
        )));
    }
    load::with_program(path, plugins, |program, source| {
        let display = path.display().to_string();
        reverse_in(program, source, &display, sequence, name)
    })
}

fn reverse_in(
    program: &dynarole_core::Program,
    source: &str,
    display: &str,
    sequence: &str,
    name: Option<&str>,
) -> Result<ExitCode, Failure> {
    let new_name = name.map_or_else(|| program.reverse_name(sequence), str::to_string);
    let reversed = match program.reverse_sequence(sequence, &new_name) {
        None => return Err(load::unknown_sequence(program, display, sequence)),
        Some(Err(errors)) => {
            render::diagnostics(display, source, &errors);
            return Ok(ExitCode::from(1));
        }
        Some(Ok(decl)) => decl,
    };
    let mut items = context_items(program.file, &reversed.definition);
    if items
        .iter()
        .any(|i| matches!(i, Item::Sequence(d) if d.name.name == new_name))
    {
        return Err(Failure::Usage(format!("`{new_name}` is already used by a sequence the reverse needs; choose another with --name")));
    }
    items.push(Item::Sequence(reversed));
    print!("{}", format_items(items));
    Ok(ExitCode::SUCCESS)
}

/// The robot and roles of the file, and every sequence the reversed one uses (transitively),
/// so the output checks on its own.
fn context_items(file: &SourceFile, definition: &SequenceDef) -> Vec<Item> {
    let mut needed: Vec<String> = Vec::new();
    let mut pending = used_names(definition);
    while let Some(name) = pending.pop() {
        if needed.contains(&name) {
            continue;
        }
        if let Some(decl) = file.sequence(&name) {
            pending.extend(used_names(&decl.definition));
        }
        needed.push(name);
    }
    file.items
        .iter()
        .filter(|item| match item {
            Item::Robot(_) | Item::Role(_) => true,
            Item::Sequence(decl) => needed.contains(&decl.name.name),
        })
        .cloned()
        .collect()
}

fn used_names(definition: &SequenceDef) -> Vec<String> {
    use dynarole_core::ast::{Body, ElementKind};
    fn walk(body: &Body, out: &mut Vec<String>) {
        for element in &body.elements {
            match &element.kind {
                ElementKind::Call(call) => out.push(call.name.name.clone()),
                ElementKind::Block(inner) => walk(inner, out),
                ElementKind::Statement(_) => {}
            }
        }
    }
    let mut out = Vec::new();
    match definition {
        SequenceDef::Reverse(target) => out.push(target.name.clone()),
        SequenceDef::Body(body) => walk(body, &mut out),
    }
    out
}
