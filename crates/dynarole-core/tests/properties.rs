//! Property tests: reversal is an involution that keeps separators between pairs and inverts
//! every operation; formatting is idempotent and keeps the meaning of what it formats.

use dynarole_core::ast::{ElementKind, Item, SeparatorKind, SequenceDef};
use dynarole_core::format::{format_file, format_items};
use dynarole_core::{analyze, parse};
use proptest::prelude::*;

/// A generated element: an ATRON statement, a block of elements, or a synchronous group of
/// turns.
#[derive(Clone, Debug)]
enum Gen {
    Statement(String),
    Block(Vec<(Gen, bool)>),
    Sync(Vec<String>),
}

fn turn() -> impl Strategy<Value = String> {
    let angle = prop::sample::select(vec![0, 108, 216, 324]);
    (0u32..10, angle.clone(), angle, any::<bool>(), 1u32..256)
        .prop_map(|(m, f, t, d, s)| format!("M{m}.Joint.rotateFromToBy({f}, {t}, {d}, {s})"))
}

fn statement() -> impl Strategy<Value = String> {
    let angle = prop::sample::select(vec![0, 108, 216, 324]);
    let connector = (0u8..8).prop_map(|c| c / 2 * 2);
    prop_oneof![
        (0u32..10, connector.clone())
            .prop_map(|(m, c)| format!("M{m}.Connector[$CONNECTOR_{c}].extend()")),
        (0u32..10, connector).prop_map(|(m, c)| format!("M{m}.Connector[{c}].retract()")),
        (0u32..10, angle.clone(), angle, any::<bool>(), 1u32..256)
            .prop_map(|(m, f, t, d, s)| format!("M{m}.Joint.rotateFromToBy({f}, {t}, {d}, {s})")),
    ]
}

fn elements() -> impl Strategy<Value = Vec<(Gen, bool)>> {
    let leaf = prop_oneof![
        4 => statement().prop_map(Gen::Statement),
        1 => prop::collection::vec(turn(), 1..4).prop_map(Gen::Sync),
    ];
    let element = leaf.prop_recursive(3, 24, 4, |inner| {
        prop::collection::vec((inner, any::<bool>()), 1..4).prop_map(Gen::Block)
    });
    prop::collection::vec((element, any::<bool>()), 1..12)
}

/// Source text of a body; `true` means `&`, and the last separator is always `;`.
fn body_text(elements: &[(Gen, bool)]) -> String {
    let mut out = String::from("{ ");
    for (i, (element, parallel)) in elements.iter().enumerate() {
        match element {
            Gen::Statement(s) => out.push_str(s),
            Gen::Block(inner) => out.push_str(&body_text(inner)),
            Gen::Sync(turns) => out.push_str(&format!("sync {{ {}; }}", turns.join(" & "))),
        }
        let last = i + 1 == elements.len();
        out.push_str(if *parallel && !last { " & " } else { "; " });
    }
    out.push('}');
    out
}

fn source(elements: &[(Gen, bool)]) -> String {
    format!("robot atron;\nsequence s {}\n", body_text(elements))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn reversing_twice_gives_back_the_original(elements in elements()) {
        let text = source(&elements);
        let parsed = parse(&text);
        prop_assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
        let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
        prop_assert!(diagnostics.is_empty(), "{:?}", diagnostics);
        let program = program.expect("checked");
        let Some(SequenceDef::Body(body)) = parsed.file.sequence("s").map(|d| d.definition.clone()) else {
            panic!("generated a body");
        };
        let once = program.reverse_body(&body);
        let twice = program.reverse_body(&once);
        prop_assert_eq!(body_format(&twice), body_format(&body));
        // The reverse of a synchronous group is synchronous, with the same turns inverted.
        prop_assert_eq!(synchronous_sizes(&once), synchronous_sizes(&body));
    }

    #[test]
    fn reversal_inverts_every_operation_in_reverse_order(elements in elements()) {
        let text = format!("{}sequence r = reverse s;\n", source(&elements));
        let parsed = parse(&text);
        let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
        let program = program.expect("checked");
        let forward = program.expand("s").expect("s");
        let backward = program.expand("r").expect("r");
        let mut expected: Vec<_> = forward.statements().into_iter().cloned().collect();
        expected.reverse();
        for s in &mut expected {
            let (op, args) = program.robot.invert(s.part, s.operation, &s.args).expect("invertible");
            s.operation = op;
            s.args = args;
        }
        let actual: Vec<_> = backward.statements().into_iter().cloned().collect();
        prop_assert_eq!(actual, expected);
    }

    /// In a flat body the separator between each pair is the same after reversal.
    #[test]
    fn reversal_keeps_the_separator_between_each_pair(statements in prop::collection::vec((statement(), any::<bool>()), 1..20)) {
        let elements: Vec<(Gen, bool)> = statements.into_iter().map(|(s, p)| (Gen::Statement(s), p)).collect();
        let text = source(&elements);
        let parsed = parse(&text);
        let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
        let program = program.expect("checked");
        let Some(SequenceDef::Body(body)) = parsed.file.sequence("s").map(|d| d.definition.clone()) else {
            panic!("generated a body");
        };
        let reversed = program.reverse_body(&body);
        let n = body.elements.len();
        for i in 0..n.saturating_sub(1) {
            // Pair (i, i+1) in the original is pair (n-2-i, n-1-i) in the reverse.
            prop_assert_eq!(body.elements[i].separator.kind, reversed.elements[n - 2 - i].separator.kind);
        }
        prop_assert_eq!(reversed.elements[n - 1].separator.kind, SeparatorKind::Sequential);
    }

    #[test]
    fn formatting_is_idempotent_and_keeps_the_tree(elements in elements()) {
        let text = source(&elements);
        let parsed = parse(&text);
        let formatted = format_file(&parsed.file, &text);
        let reparsed = parse(&formatted);
        prop_assert!(reparsed.diagnostics.is_empty());
        prop_assert_eq!(format_file(&reparsed.file, &formatted), formatted.clone());
        prop_assert_eq!(shape(&reparsed.file.items), shape(&parsed.file.items));
    }
}

/// The number of statements of each synchronous group, in order of their first statement
/// (the reverse lists them backwards, so sorted).
fn synchronous_sizes(body: &dynarole_core::ast::Body) -> Vec<usize> {
    let mut out = Vec::new();
    for e in &body.elements {
        if let ElementKind::Block(inner) = &e.kind {
            if inner.synchronous.is_some() {
                out.push(inner.elements.len());
            }
            out.extend(synchronous_sizes(inner));
        }
    }
    out.sort_unstable();
    out
}

fn body_format(body: &dynarole_core::ast::Body) -> String {
    let decl = dynarole_core::ast::SequenceDecl {
        name: dynarole_core::ast::Ident {
            name: "s".into(),
            span: body.span,
        },
        definition: SequenceDef::Body(body.clone()),
        span: body.span,
    };
    format_items(vec![Item::Sequence(decl)])
}

/// The tree without positions, to compare two parses of differently laid-out text.
fn shape(items: &[Item]) -> String {
    fn body(b: &dynarole_core::ast::Body, out: &mut String) {
        for e in &b.elements {
            match &e.kind {
                ElementKind::Statement(s) => out.push_str(&dynarole_core::format::statement(s)),
                ElementKind::Call(c) => out.push_str(&c.name.name),
                ElementKind::Block(inner) => {
                    if inner.synchronous.is_some() {
                        out.push_str("sync");
                    }
                    out.push('{');
                    body(inner, out);
                    out.push('}');
                }
            }
            out.push_str(if e.separator.kind == SeparatorKind::Parallel {
                "&"
            } else {
                ";"
            });
        }
    }
    let mut out = String::new();
    for item in items {
        if let Item::Sequence(d) = item {
            if let SequenceDef::Body(b) = &d.definition {
                body(b, &mut out);
            }
        }
    }
    out
}
