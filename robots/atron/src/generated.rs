//! Configurations made by rule rather than read from the shared data files, for tests and
//! benchmarks that need robots of any size.

/// The zig-zag ATRON chain of the rotation experiments, `n` modules long (`n` >= 1), as the
/// data files' JSON: modules alternately east-west and north-south, each latched to the next.
pub fn atron_chain_json(n: usize) -> String {
    let modules: Vec<String> = (0..n)
        .map(|k| {
            let orientation = if k % 2 == 0 { "EW" } else { "NS" };
            format!(
                r#"{{"name": "M{k}", "id": {k}, "position": [{k}, 0, {}], "orientation": "{orientation}", "joint": 0}}"#,
                k % 2
            )
        })
        .collect();
    let connections: Vec<String> = (0..n.saturating_sub(1))
        .map(|k| {
            if k % 2 == 0 {
                format!(r#"["M{k}", 5, "M{}", 0]"#, k + 1)
            } else {
                format!(r#"["M{k}", 2, "M{}", 1]"#, k + 1)
            }
        })
        .collect();
    format!(
        r#"{{"name": "chain", "robot": "ATRON", "modules": [{}], "connections": [{}]}}"#,
        modules.join(",\n"),
        connections.join(",\n")
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AtronConfiguration;
    use dynarole_world::RobotKind;

    #[test]
    fn chains_load_with_every_module_latched_to_the_next() {
        for n in [1, 2, 7] {
            let config = crate::KIND
                .read_configuration(&atron_chain_json(n))
                .expect("loads");
            let c = config
                .downcast_ref::<AtronConfiguration>()
                .expect("an ATRON chain");
            assert_eq!(c.modules().len(), n);
        }
    }
}
