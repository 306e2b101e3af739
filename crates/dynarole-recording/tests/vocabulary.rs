//! The trace events as the documentation states them: `docs/simulator.md` holds the table
//! `markdown_table` writes from the vocabulary, so the two cannot drift apart.

use dynarole_recording::markdown_table;

#[test]
fn the_simulator_docs_hold_the_table_of_events() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/simulator.md");
    let docs = std::fs::read_to_string(path).expect("docs/simulator.md");
    let table = markdown_table();
    assert!(
        docs.contains(&table),
        "docs/simulator.md must hold the table of trace events, as written from \
         crates/dynarole-recording/src/trace_event.rs:\n{table}"
    );
}
