//! Properties of the `.scen` reader and writer: reading never panics, whatever the text, and
//! every valid scenario comes back from its written text.

use dynarole_robot_cubes::scen::{
    looks_like_scen, read_scen, write_scen, Group, MoveLine, MoveSet, ScenModule, Scenario,
};
use proptest::prelude::*;
use proptest::sample::Index;

/// The scenario with every line number set to 0, to compare contents only.
fn without_lines(mut s: Scenario) -> Scenario {
    s.groups.iter_mut().for_each(|g| g.line = 0);
    s.modules.iter_mut().for_each(|m| m.line = 0);
    for set in &mut s.sets {
        set.line = 0;
        set.moves.iter_mut().for_each(|m| m.line = 0);
    }
    s
}

const MAX_GROUP_ID: i64 = (1 << 53) - 1;
const MAX_COORDINATE: i32 = 1_000_000;

fn groups() -> impl Strategy<Value = Vec<Group>> {
    let look = (prop::array::uniform3(0i64..=255), 0i64..=100);
    prop::collection::btree_map(-MAX_GROUP_ID..=MAX_GROUP_ID, look, 1..5).prop_map(|groups| {
        groups
            .into_iter()
            .map(|(id, (colour, size_percent))| Group {
                line: 0,
                id,
                colour,
                size_percent,
            })
            .collect()
    })
}

fn modules(groups: Vec<Group>) -> impl Strategy<Value = Vec<ScenModule>> {
    let cell = prop::array::uniform3(-MAX_COORDINATE..=MAX_COORDINATE);
    prop::collection::btree_map(any::<u32>(), (any::<Index>(), cell), 1..8).prop_map(
        move |modules| {
            modules
                .into_iter()
                .map(|(id, (group, position))| ScenModule {
                    line: 0,
                    id,
                    group: group.get(&groups).id,
                    position,
                })
                .collect()
        },
    )
}

/// Sets whose stars are where the writer puts them: on the first line of a checkpoint set,
/// and the first set always a checkpoint.
fn sets(modules: &[ScenModule]) -> impl Strategy<Value = Vec<MoveSet>> {
    let ids: Vec<u32> = modules.iter().map(|m| m.id).collect();
    let step = (
        any::<Index>(),
        any::<i32>(),
        prop::array::uniform3(-MAX_COORDINATE..=MAX_COORDINATE),
    );
    let set = (any::<bool>(), prop::collection::vec(step, 1..4));
    prop::collection::vec(set, 0..4).prop_map(move |sets| {
        (0..)
            .zip(sets)
            .map(|(index, (checkpoint, steps))| {
                let checkpoint = index == 0 || checkpoint;
                let moves = (0..)
                    .zip(steps)
                    .map(|(position, (module, code, d))| MoveLine {
                        line: 0,
                        starred: checkpoint && position == 0,
                        id: *module.get(&ids),
                        code: i64::from(code),
                        d,
                    })
                    .collect();
                MoveSet {
                    line: 0,
                    checkpoint,
                    moves,
                }
            })
            .collect()
    })
}

fn scenario() -> impl Strategy<Value = Scenario> {
    let header = ("[^\r\n]{0,12}", "[^\r\n]{1,12}");
    (header, groups())
        .prop_flat_map(|(header, groups)| (Just(header), Just(groups.clone()), modules(groups)))
        .prop_flat_map(|(header, groups, modules)| {
            let sets = sets(&modules);
            (Just(header), Just(groups), Just(modules), sets)
        })
        .prop_map(|((name, description), groups, modules, sets)| Scenario {
            name,
            description,
            groups,
            modules,
            sets,
        })
}

/// One edit of a text, at a position given as a fraction of its characters.
#[derive(Clone, Debug)]
enum Edit {
    Insert(Index, char),
    Delete(Index),
    Replace(Index, char),
    DuplicateLine(Index),
    DeleteLine(Index),
}

/// Characters that matter to the grammar, and a few that only could.
fn grammar_char() -> impl Strategy<Value = char> {
    prop_oneof![
        prop::sample::select(vec![
            '0', '1', '9', '-', '+', ',', '*', '/', ' ', '\t', '\r', '\n', '.', 'x', 'é', '€',
        ]),
        any::<char>(),
    ]
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<Index>(), grammar_char()).prop_map(|(at, c)| Edit::Insert(at, c)),
        any::<Index>().prop_map(Edit::Delete),
        (any::<Index>(), grammar_char()).prop_map(|(at, c)| Edit::Replace(at, c)),
        any::<Index>().prop_map(Edit::DuplicateLine),
        any::<Index>().prop_map(Edit::DeleteLine),
    ]
}

fn apply(text: &str, edit: &Edit) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    let mut lines: Vec<&str> = text.split('\n').collect();
    match *edit {
        Edit::Insert(at, c) => chars.insert(at.index(chars.len() + 1), c),
        Edit::Delete(at) if !chars.is_empty() => {
            chars.remove(at.index(chars.len()));
        }
        Edit::Replace(at, c) if !chars.is_empty() => {
            let at = at.index(chars.len());
            chars[at] = c;
        }
        Edit::DuplicateLine(at) => {
            let at = at.index(lines.len());
            lines.insert(at, lines[at]);
            return lines.join("\n");
        }
        Edit::DeleteLine(at) => {
            lines.remove(at.index(lines.len()));
            return lines.join("\n");
        }
        Edit::Delete(_) | Edit::Replace(..) => {}
    }
    chars.into_iter().collect()
}

proptest! {
    #[test]
    fn written_scenarios_read_back(s in scenario()) {
        let text = write_scen(&s);
        let again = read_scen(&text);
        prop_assert_eq!(again.map(without_lines), Ok(s));
        prop_assert!(looks_like_scen(&text));
    }

    #[test]
    fn reading_any_text_does_not_panic(text in any::<String>()) {
        let _ = read_scen(&text);
        let _ = looks_like_scen(&text);
    }

    #[test]
    fn reading_data_lines_of_grammar_characters_does_not_panic(
        data in prop::collection::vec(grammar_char(), 0..200),
    ) {
        let text = format!("name\ndescription\nCUBE\n\n{}", data.into_iter().collect::<String>());
        let _ = read_scen(&text);
        let _ = looks_like_scen(&text);
    }

    #[test]
    fn reading_an_edited_scenario_does_not_panic(
        s in scenario(),
        edits in prop::collection::vec(edit(), 1..6),
    ) {
        let text = edits.iter().fold(write_scen(&s), |text, edit| apply(&text, edit));
        if let Err(refusal) = read_scen(&text) {
            // A refusal points inside the text, or at the line just after it.
            prop_assert!(refusal.line >= 1 && refusal.line <= text.split('\n').count() + 1);
            prop_assert!(refusal.column >= 1);
        }
        let _ = looks_like_scen(&text);
    }
}

#[test]
fn json_and_rofi_texts_are_not_scenarios() {
    let json = serde_json::json!({ "modules": [[0, 0, 0], [1, 0, 0]], "name": "CUBE" });
    assert!(!looks_like_scen(&json.to_string()));
    assert!(!looks_like_scen(
        &serde_json::to_string_pretty(&json).expect("JSON prints")
    ));
    assert!(!looks_like_scen("C\nM 1 0 0 0\nM 2 90 0 0\n\n1,2,3,4,5\n"));
}
