//! RoFI's voxel JSON: one world read as a configuration (modules numbered in the order of their
//! A bodies, facing connectors connected), a plan matched world to world whatever each world's
//! placement and body order, and an error naming the field or the world for each rule a file
//! can break.

use dynarole_robot_rofi::{
    read_plan, read_voxel, recognise, validate, Format, RofiConfiguration, Side,
};
use proptest::prelude::*;
use serde_json::{json, Value};

/// Two modules in a line along X, written as rofi-voxel writes a world: module 1 at cells 0
/// and 1, module 2 at 2 and 3, every joint at zero.
fn line(modules: usize) -> Value {
    let bodies: Vec<Value> = (0..2 * modules)
        .map(|i| {
            json!({"body_dir": {"axis": "X", "is_positive": i % 2 == 0}, "joint_pos": 0,
                   "pos": [i, 0, 0], "shoe_rotated": false})
        })
        .collect();
    json!({ "bodies": bodies })
}

fn example(name: &str) -> String {
    let path = format!("{}/examples/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn one_world_is_a_line_of_modules_joined_at_their_facing_connectors() {
    let text = line(3).to_string();
    assert_eq!(recognise(&text), Some(Format::Voxel));
    let plan = read_voxel(&text).expect("a world");
    let [(0, config)] = plan.configurations.as_slice() else {
        panic!("one configuration")
    };
    let ids: Vec<u32> = config.modules().map(|m| m.id).collect();
    assert_eq!(ids, [1, 2, 3]);
    assert!(config
        .modules()
        .all(|m| m.alpha == 0.0 && m.beta == 0.0 && m.gamma == 0.0));
    // Shoe B of each module faces shoe A of the next: −Z to −Z.
    assert_eq!(config.connections().len(), 2);
    let poses = validate(config).expect("valid");
    let far = poses.centre((3, Side::B)).expect("a shoe");
    assert!((far.coords.norm() - 5.0).abs() < 1e-9, "{far}");
}

#[test]
fn a_rofiworld_is_still_a_rofiworld() {
    let world =
        r#"{"modules": [{"id": 1, "type": "universal", "alpha": 0, "beta": 0, "gamma": 0}]}"#;
    assert_eq!(recognise(world), Some(Format::RofiWorld));
    assert_eq!(recognise(&format!("[{world}]")), Some(Format::RofiWorld));
    assert_eq!(recognise(&format!("[{}]", line(1))), Some(Format::Voxel));
}

/// The configurations of a voxel plan, as read.
fn configurations(text: &str) -> Vec<(usize, RofiConfiguration)> {
    read_voxel(text)
        .map(|p| p.configurations)
        .expect("the plan reads")
}

#[test]
fn the_example_plans_read_and_the_loop_is_cut_and_closed() {
    for name in ["voxel-three.json", "voxel-five-loop.json"] {
        let text = example(name);
        let worlds: Vec<Value> = serde_json::from_str(&text).expect("an array");
        let read = read_plan(&text, Format::Voxel).expect("reads");
        assert_eq!(read.indices.last(), Some(&(worlds.len() - 1)), "{name}");
        assert_eq!(read.indices.len(), read.configurations.len());
    }
    // Some world of the loop plan is two configurations: its turn, then what it connects.
    let loop_plan = read_plan(&example("voxel-five-loop.json"), Format::Voxel).expect("reads");
    assert!(loop_plan.indices.windows(2).any(|w| w[0] == w[1]));
}

/// One of the 24 rotations of the grid, by index.
fn grid_rotation(index: usize) -> [[i64; 3]; 3] {
    let mut all = Vec::new();
    for p in [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ] {
        for signs in 0..8 {
            let mut m = [[0i64; 3]; 3];
            for (row, &column) in p.iter().enumerate() {
                m[row][column] = if signs >> row & 1 == 1 { -1 } else { 1 };
            }
            let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
            if det == 1 {
                all.push(m);
            }
        }
    }
    all[index % 24]
}

fn apply(m: &[[i64; 3]; 3], v: [i64; 3]) -> [i64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

fn unit(axis: usize, positive: bool) -> [i64; 3] {
    let mut v = [0; 3];
    v[axis] = if positive { 1 } else { -1 };
    v
}

/// One body turned by `m` and shifted by `by`, written back in rofi-voxel's terms: its X
/// connectors' axis and its Z connector's direction decide `shoe_rotated` and `joint_pos`
/// (written here from RoFI's description of the format, independently of the reader).
fn turned_body(body: &Value, m: &[[i64; 3]; 3], by: [i64; 3]) -> Value {
    let axis = "XYZ"
        .find(
            body["body_dir"]["axis"]
                .as_str()
                .expect("a field of the example"),
        )
        .expect("a field of the example");
    let positive = body["body_dir"]["is_positive"]
        .as_bool()
        .expect("a field of the example");
    let rotated = body["shoe_rotated"]
        .as_bool()
        .expect("a field of the example");
    let joint = body["joint_pos"].as_i64().expect("a field of the example");
    let (next, prev) = ((axis + 1) % 3, (axis + 2) % 3);
    let x_axis = unit(if rotated { prev } else { next }, true);
    let z_axis = if rotated { next } else { prev };
    let z = match joint {
        0 => unit(axis, !positive),
        90 => unit(z_axis, true),
        _ => unit(z_axis, false),
    };
    let pos: Vec<i64> = body["pos"]
        .as_array()
        .expect("a field of the example")
        .iter()
        .map(|c| c.as_i64().expect("a field of the example"))
        .collect();
    let pos = apply(m, [pos[0], pos[1], pos[2]]);
    let dir = apply(m, unit(axis, positive));
    let new_axis = dir
        .iter()
        .position(|c| *c != 0)
        .expect("a field of the example");
    let x = apply(m, x_axis);
    let new_rotated = x
        .iter()
        .position(|c| *c != 0)
        .expect("a field of the example")
        == (new_axis + 2) % 3;
    let z = apply(m, z);
    let joint = if z == dir.map(|c| -c) {
        0
    } else if z.iter().sum::<i64>() > 0 {
        90
    } else {
        -90
    };
    json!({"body_dir": {"axis": &"XYZ"[new_axis..=new_axis], "is_positive": dir[new_axis] > 0},
           "joint_pos": joint, "pos": [pos[0] + by[0], pos[1] + by[1], pos[2] + by[2]],
           "shoe_rotated": new_rotated})
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// rofi-voxel normalises each world on its own: any placement of the later worlds, and
    /// any order of their bodies, reads as the same plan.
    #[test]
    fn a_plan_reads_the_same_whatever_each_later_world_s_placement(
        turns in proptest::collection::vec(0usize..24, 16),
        shift in proptest::array::uniform3(-20i64..20),
        shuffle in any::<u64>(),
    ) {
        let text = example("voxel-five-loop.json");
        let worlds: Vec<Value> = serde_json::from_str(&text).expect("an array");
        let moved: Vec<Value> = worlds.iter().enumerate().map(|(k, world)| {
            if k == 0 {
                return world.clone();
            }
            let m = grid_rotation(turns[k % turns.len()]);
            let mut bodies: Vec<Value> = world["bodies"].as_array().expect("a field of the example").iter()
                .map(|b| turned_body(b, &m, shift)).collect();
            let n = bodies.len();
            for i in 0..n {
                let j = (shuffle.rotate_left(i as u32) as usize).wrapping_add(k) % n;
                bodies.swap(i, j);
            }
            json!({ "bodies": bodies })
        }).collect();
        let moved_text = serde_json::to_string(&moved).expect("JSON");
        prop_assert_eq!(configurations(&moved_text), configurations(&text));
    }
}

/// The message of the error reading `text` gives, with its path.
fn refusal(text: &str) -> (String, String) {
    match read_voxel(text) {
        Err(e) => (e.path, e.message),
        Ok(_) => panic!("read: {text}"),
    }
}

#[test]
fn each_broken_rule_is_named_at_its_field_or_world() {
    let world = line(2);
    let with = |path: &str, value: Value| {
        let mut w = world.clone();
        w.pointer_mut(path).map(|v| *v = value).expect("a field");
        w.to_string()
    };
    let cases: Vec<(String, &str, &str)> = vec![
        (
            with("/bodies/0/body_dir/axis", json!("W")),
            "bodies[0].body_dir.axis",
            "expected an axis",
        ),
        (
            with("/bodies/1/joint_pos", json!(45)),
            "bodies[1].joint_pos",
            "expected 0, 90 or -90",
        ),
        (
            with("/bodies/2/pos", json!([1, 0, 0])),
            "",
            "where another body is",
        ),
        (
            with("/bodies/3/body_dir/is_positive", json!(true)),
            "",
            "no body points back",
        ),
        (
            with("/bodies/0/pos", json!([2000000, 0, 0])),
            "bodies[0].pos",
            "beyond",
        ),
        (
            json!({"bodies": []}).to_string(),
            "bodies",
            "a body or more",
        ),
        (
            json!({"bodies": [], "extra": 1}).to_string(),
            "extra",
            "unknown field",
        ),
        (
            json!([world, 3]).to_string(),
            "[1]",
            "expected a voxel world",
        ),
        (
            json!([world, world]).to_string(),
            "[1]",
            "is not world 0 with one joint turned",
        ),
    ];
    for (text, path, message) in cases {
        let (at, said) = refusal(&text);
        assert_eq!(at, path, "{text}: {said}");
        assert!(said.contains(message), "{text}: {said}");
    }
    let (_, said) = refusal("{\"bodies\": [");
    assert!(said.contains("EOF"), "{said}");
}

#[test]
fn a_world_too_large_to_match_is_refused_naming_the_limit() {
    let (at, said) = refusal(&line(129).to_string());
    assert_eq!(at, "bodies");
    assert!(said.contains("at most 256"), "{said}");
}
