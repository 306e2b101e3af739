//! A sequence as a file of its own: the robot and roles of the file it comes from and every
//! sequence it uses, transitively, so that the result checks without the rest of the file
//! (`dynarole reverse` prints the reverse of a sequence this way).

use crate::ast::{Body, ElementKind, Item, SequenceDecl, SequenceDef, SourceFile};

/// The items of a file holding `decl` after what it needs of `file` (in `file`'s order); `Err`
/// with the name when a sequence it needs already has `decl`'s name.
pub fn standalone(file: &SourceFile, decl: SequenceDecl) -> Result<Vec<Item>, String> {
    let mut items = context_items(file, &decl.definition);
    let taken = items
        .iter()
        .any(|i| matches!(i, Item::Sequence(d) if d.name.name == decl.name.name));
    if taken {
        return Err(decl.name.name);
    }
    items.push(Item::Sequence(decl));
    Ok(items)
}

/// The robot and roles of `file`, and every sequence `definition` uses (transitively).
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

/// The sequences `definition` names directly (calls and the target of a `reverse`).
fn used_names(definition: &SequenceDef) -> Vec<String> {
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

#[cfg(test)]
mod tests {
    use super::standalone;
    use crate::ast::Item;
    use crate::parse;

    const FILE: &str = "robot snakebot;\nrole M0 requires id == 0;\n\
        sequence a { M0.Connector[0].retract(); }\n\
        sequence b { a(); }\n\
        sequence c { M0.Connector[0].extend(); }\n\
        sequence d = reverse b;\n";

    fn names(items: &[Item]) -> Vec<String> {
        items
            .iter()
            .map(|i| match i {
                Item::Robot(_) => "robot".to_string(),
                Item::Role(_) => "role".to_string(),
                Item::Sequence(d) => d.name.name.clone(),
            })
            .collect()
    }

    #[test]
    fn keeps_what_the_sequence_uses_transitively() {
        let parsed = parse(FILE);
        let mut decl = parsed.file.sequence("d").expect("d").clone();
        decl.name.name = "e".into();
        let items = standalone(&parsed.file, decl).expect("e is free");
        assert_eq!(names(&items), ["robot", "role", "a", "b", "e"]);
    }

    #[test]
    fn refuses_a_name_it_needs() {
        let parsed = parse(FILE);
        let mut decl = parsed.file.sequence("d").expect("d").clone();
        decl.name.name = "a".into();
        assert_eq!(standalone(&parsed.file, decl), Err("a".to_string()));
    }
}
