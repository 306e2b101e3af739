//! Benchmark: parse and check a generated 10,000-statement sequence (goal: under 50 ms).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use dynarole_core::{analyze, parse};

/// A sequence of `n` ATRON statements, every fourth one closing a parallel group.
fn generated_source(n: usize) -> String {
    let mut out = String::from(
        "robot atron;\nrole Wheel requires connected($CONNECTOR_1) && id != 0;\nsequence big {\n",
    );
    for i in 0..n {
        let module = i % 50;
        let statement = match i % 3 {
            0 => format!("M{module}.Connector[$CONNECTOR_{}].retract()", (i % 4) * 2),
            1 => format!("M{module}.Joint.rotateFromToBy(0, 108, true, 150)"),
            _ => format!("Wheel.Connector[{}].extend()", (i % 4) * 2),
        };
        let separator = if i % 4 == 3 || i + 1 == n { ";" } else { " &" };
        out.push_str(&format!("    {statement}{separator}\n"));
    }
    out.push_str("}\nsequence back = reverse big;\n");
    out
}

fn bench(c: &mut Criterion) {
    let source = generated_source(10_000);
    let registry = dynarole_robots::plugins();
    c.bench_function("parse 10k statements", |b| {
        b.iter(|| parse(black_box(&source)))
    });
    let parsed = parse(&source);
    assert!(parsed.diagnostics.is_empty());
    c.bench_function("check 10k statements", |b| {
        b.iter(|| analyze(black_box(&parsed.file), &registry))
    });
    c.bench_function("parse and check 10k statements", |b| {
        b.iter(|| {
            let parsed = parse(black_box(&source));
            let (program, diagnostics) = analyze(&parsed.file, &registry);
            assert!(program.is_some() && diagnostics.is_empty());
        })
    });
    let (program, _) = analyze(&parsed.file, &registry);
    let program = program.expect("the generated source checks");
    c.bench_function("reverse 10k statements", |b| {
        b.iter(|| program.reverse_sequence("big", "gib"))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
