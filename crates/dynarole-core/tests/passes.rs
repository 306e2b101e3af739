//! Snapshot tests of each compiler pass; every snapshot holds the source and the pass's output.

use dynarole_core::ast::*;
use dynarole_core::check::Label;
use dynarole_core::expand::{Plan, PlanKind};
use dynarole_core::format::{format_file, format_items};
use dynarole_core::lexer::lex;
use dynarole_core::span::line_col;
use dynarole_core::{analyze, parse, Diagnostic};

const FIG5: &str = include_str!("../../../robots/atron/examples/fig5.dr");

const SMALL: &str = "robot atron;
role Wheel requires connected($CONNECTOR_1) && id != 0;
sequence s {
    M0.Connector[$CONNECTOR_0].retract() & // open
    Wheel.Joint.rotateFromToBy(0, 108, true, 150);
    { M3.Joint.rotateFromToBy(0, 324, false, 150); M4.Connector[4].extend(); } & other;
}
sequence other { M6.Connector[$CONNECTOR_2].retract(); }
sequence back = reverse s;
";

fn snapshot(source: &str, pass: &str, output: &str) -> String {
    format!("{source}\n----- {pass} -----\n{output}")
}

fn diagnostics_text(source: &str, diagnostics: &[Diagnostic]) -> String {
    let mut out = String::new();
    for d in diagnostics {
        let (line, col) = line_col(source, d.span.start);
        let desc = d.describe();
        out.push_str(&format!(
            "{line}:{col} {}[{}] {} ({})\n",
            severity(d),
            desc.code,
            desc.title,
            desc.label
        ));
        if let Some(hint) = desc.hint {
            out.push_str(&format!("    hint: {hint}\n"));
        }
    }
    out
}

fn severity(d: &Diagnostic) -> &'static str {
    match d.severity() {
        dynarole_core::Severity::Error => "error",
        dynarole_core::Severity::Warning => "warning",
    }
}

#[test]
fn lexer_pass() {
    let source = "M0.Connector[$CONNECTOR_0].retract() & /* c */ x; // end\n$ 12 &&||!=";
    let lexed = lex(source);
    let mut out: Vec<String> = lexed
        .tokens
        .iter()
        .map(|(t, s)| format!("{}..{} {:?}", s.start, s.end, t))
        .collect();
    out.extend(
        lexed
            .comments
            .iter()
            .map(|c| format!("comment {}..{} {:?}", c.span.start, c.span.end, c.text)),
    );
    out.push(diagnostics_text(source, &lexed.errors));
    insta::assert_snapshot!(snapshot(source, "tokens", &out.join("\n")));
}

/// A compact, indented view of the tree (spans left out).
fn tree(file: &SourceFile) -> String {
    let mut out = String::new();
    for item in &file.items {
        match item {
            Item::Robot(d) => out.push_str(&format!("robot {}\n", d.name.name)),
            Item::Role(d) => out.push_str(&format!(
                "role {}\n  {}\n",
                d.name.name,
                expr_tree(&d.predicate)
            )),
            Item::Sequence(d) => match &d.definition {
                SequenceDef::Reverse(t) => {
                    out.push_str(&format!("sequence {} = reverse {}\n", d.name.name, t.name))
                }
                SequenceDef::Body(body) => {
                    out.push_str(&format!("sequence {}\n", d.name.name));
                    body_tree(body, 1, &mut out);
                }
            },
        }
    }
    out
}

fn body_tree(body: &Body, depth: usize, out: &mut String) {
    for e in &body.elements {
        let sep = match e.separator.kind {
            SeparatorKind::Sequential => ";",
            SeparatorKind::Parallel => "&",
        };
        let pad = "  ".repeat(depth);
        match &e.kind {
            ElementKind::Statement(s) => out.push_str(&format!(
                "{pad}stmt label={} part={} index={:?} method={} args={:?} {sep}\n",
                s.label.name,
                s.part.name,
                s.index.as_ref().map(|a| &a.kind),
                s.method.name,
                s.args.iter().map(|a| &a.kind).collect::<Vec<_>>()
            )),
            ElementKind::Call(c) => out.push_str(&format!(
                "{pad}call {}{} {sep}\n",
                if c.reverse.is_some() { "reverse " } else { "" },
                c.name.name
            )),
            ElementKind::Block(inner) => {
                out.push_str(&format!("{pad}block {sep}\n"));
                body_tree(inner, depth + 1, out);
            }
        }
    }
}

fn expr_tree(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Binary { op, lhs, rhs } => {
            format!("({} {} {})", op.symbol(), expr_tree(lhs), expr_tree(rhs))
        }
        ExprKind::Unary { op, operand } => format!("({op:?} {})", expr_tree(operand)),
        ExprKind::Paren(inner) => expr_tree(inner),
        ExprKind::Call { function, args } => format!(
            "{}({})",
            function.name,
            args.iter().map(expr_tree).collect::<Vec<_>>().join(", ")
        ),
        ExprKind::Name(n) => n.name.clone(),
        ExprKind::Int(n) => n.to_string(),
        ExprKind::Bool(b) => b.to_string(),
        ExprKind::Constant(c) => format!("${c}"),
    }
}

#[test]
fn parser_pass() {
    let parsed = parse(SMALL);
    let out = format!(
        "{}{}",
        tree(&parsed.file),
        diagnostics_text(SMALL, &parsed.diagnostics)
    );
    insta::assert_snapshot!(snapshot(SMALL, "tree", &out));
}

#[test]
fn parser_recovers_and_reports_every_error() {
    let source = "robot atron;\nsequence s {\n  M0.Connector[.retract();\n  M1.Joint.rotateFromToBy(0, 108, true 150);\n  M3.Connector[$CONNECTOR_4].retract();\n}\nrole r requires id = 3 & x;\n}\nsequence t { M2.Connector[$CONNECTOR_4].extend() }\n";
    let parsed = parse(source);
    let out = format!(
        "{}{}",
        tree(&parsed.file),
        diagnostics_text(source, &parsed.diagnostics)
    );
    insta::assert_snapshot!(snapshot(source, "tree and diagnostics", &out));
}

#[test]
fn check_pass() {
    let source = "robot atron;\nrole Wheel requires connected(9) || id;\nsequence s {\n  M0.Connector[$CONNECTOR_1].extend() &\n  Whel.Joint.rotateFromToBy(0, 100, true, 150);\n  M3.Joint.rotateToBy(108, true, 150);\n  t;\n}\nsequence back = reverse s;\n";
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    assert!(program.is_none());
    insta::assert_snapshot!(snapshot(
        source,
        "diagnostics",
        &diagnostics_text(source, &diagnostics)
    ));
}

#[test]
fn format_pass() {
    let source = "robot atron; role W requires (id==1||id==2)&&!connected($CONNECTOR_0);\nsequence s{M0.Connector[$CONNECTOR_0].retract()&M3.Connector[$CONNECTOR_4].retract();/* why */ {M1.Joint.rotateFromToBy(0,108,true,150);reverse t;}; t;}\nsequence t{M2.Connector[4].extend();}";
    let parsed = parse(source);
    assert!(parsed.diagnostics.is_empty());
    let formatted = format_file(&parsed.file, source);
    let again = format_file(&parse(&formatted).file, &formatted);
    assert_eq!(formatted, again, "formatting is not idempotent");
    insta::assert_snapshot!(snapshot(source, "fmt", &formatted));
}

#[test]
fn reverse_pass_fig5() {
    let parsed = parse(FIG5);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let program = program.expect("Fig. 5 checks");
    let name = program.reverse_name("eight2car");
    assert_eq!(name, "car2eight");
    let reversed = program
        .reverse_sequence("eight2car", &name)
        .expect("exists")
        .expect("invertible");
    insta::assert_snapshot!(snapshot(
        FIG5,
        "reverse eight2car",
        &format_items(vec![Item::Sequence(reversed)])
    ));
}

/// The expected text of the reversed Fig. 5, written out by hand from Sec. IV-C's rules.
#[test]
fn reverse_of_fig5_equals_expected_text() {
    let expected = include_str!("car2eight.expected.dr");
    let parsed = parse(FIG5);
    let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.expect("Fig. 5 checks");
    let reversed = program
        .reverse_sequence("eight2car", "car2eight")
        .expect("exists")
        .expect("invertible");
    let robot = parsed.file.items[0].clone();
    assert_eq!(
        format_items(vec![robot, Item::Sequence(reversed)]),
        expected
    );
}

fn plan_tree(plan: &Plan, robot: &dynarole_core::RobotApi, depth: usize, out: &mut String) {
    for e in &plan.elements {
        let pad = "  ".repeat(depth);
        let sep = match e.separator {
            SeparatorKind::Sequential => ";",
            SeparatorKind::Parallel => "&",
        };
        match &e.kind {
            PlanKind::Op(s) => {
                let part = &robot.parts[s.part];
                let who = match &s.label {
                    Label::Module(id) => format!("module {id}"),
                    Label::Role(r) => format!("role {r}"),
                };
                let args: Vec<String> = s.args.iter().map(ToString::to_string).collect();
                out.push_str(&format!(
                    "{pad}{who}: {}{:?}.{}({}) {sep}\n",
                    part.name,
                    s.index,
                    part.operations[s.operation].name,
                    args.join(", ")
                ));
            }
            PlanKind::Block(inner) => {
                out.push_str(&format!("{pad}block {sep}\n"));
                plan_tree(inner, robot, depth + 1, out);
            }
        }
    }
}

#[test]
fn expand_pass() {
    let parsed = parse(SMALL);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let program = program.expect("checks");
    let mut out = String::new();
    for name in ["s", "back"] {
        out.push_str(&format!("plan {name}\n"));
        let plan = program.expand(name).expect("exists");
        plan_tree(&plan, &program.robot, 1, &mut out);
        let paper = plan
            .flatten_for_paper()
            .map(|flat| flat.len())
            .map_err(|d| d.describe().label);
        out.push_str(&format!("  paper protocol: {paper:?}\n"));
    }
    insta::assert_snapshot!(snapshot(SMALL, "expand", &out));
}

fn ir_text(ir: &dynarole_core::lower::Ir) -> String {
    let mut out = format!(
        "robot {} window {} max_args {}\n",
        ir.robot, ir.window, ir.max_args
    );
    for a in &ir.addresses {
        out.push_str(&format!("address {} = {:?}\n", a.number, a.label));
    }
    for (i, (part, op)) in ir.operations.iter().enumerate() {
        out.push_str(&format!("op {i} = {part}.{op}\n"));
    }
    for (i, s) in ir.statements.iter().enumerate() {
        let sep = if s.separator == SeparatorKind::Parallel {
            "&"
        } else {
            ";"
        };
        let after = s
            .previous_on_module
            .map_or(String::new(), |p| format!(" after {p}"));
        out.push_str(&format!(
            "s{i:<3} @{} op{} [{}] {:?} deps {:?}{after} {sep}  {}\n",
            s.address, s.op, s.index, s.args, s.deps, s.text
        ));
    }
    out
}

#[test]
fn lower_pass_fig5() {
    let parsed = parse(FIG5);
    let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.expect("checks");
    let plan = program.expand("eight2car").expect("exists");
    let ir = program.lower(&[plan]).expect("fits");
    let mut out = ir_text(&ir);
    out.push_str("paper protocol states:\n");
    for unit in ir.paper_layout().expect("fits") {
        out.push_str(&format!(
            "  {:>3} {:?} @{} {:?}\n",
            unit.first_state, unit.kind, unit.address, unit.statements
        ));
    }
    insta::assert_snapshot!(snapshot(
        "(robots/atron/examples/fig5.dr, sequence eight2car)",
        "lower",
        &out
    ));
}

#[test]
fn lower_pass_nested_blocks() {
    let source = "robot atron;\nsequence s {\n    { M0.Connector[0].retract(); M0.Joint.rotateFromToBy(0, 108, true, 150); } &\n    { M3.Connector[4].retract(); M1.Joint.rotateFromToBy(0, 324, false, 150); };\n    M0.Connector[0].extend();\n}\n";
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let program = program.expect("checks");
    let ir = program
        .lower(&[program.expand("s").expect("s")])
        .expect("fits");
    insta::assert_snapshot!(snapshot(source, "lower", &ir_text(&ir)));
}
