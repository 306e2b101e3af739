//! Plans written in RoFI's old text format read back to the same configurations, whatever the
//! angles, docks, sides and twists.

use dynarole_robot_rofi::{
    read_old_format, write_old_format, Connection, Connector, Dock, Module, Orientation,
    RofiConfiguration, Side,
};
use proptest::prelude::*;

fn any_dock() -> impl Strategy<Value = Dock> {
    prop_oneof![Just(Dock::PlusX), Just(Dock::MinusX), Just(Dock::MinusZ)]
}

fn any_side() -> impl Strategy<Value = Side> {
    prop_oneof![Just(Side::A), Just(Side::B)]
}

/// Modules 1..=n with any angles, each after the first connected to an earlier one (some
/// connectors may clash: those configurations are skipped).
fn configuration(
    angles: &[(f64, f64, f64)],
    links: &[(usize, Side, Dock, usize, Side, Dock)],
) -> Option<RofiConfiguration> {
    let modules: Vec<Module> = (angles.iter().enumerate())
        .map(|(i, &(a, b, g))| Module::new(i as u32 * 7 + 3, a, b, g))
        .collect();
    let connections: Vec<Connection> = (links.iter().enumerate())
        .map(|(i, &(parent, s1, d1, o, s2, d2))| Connection {
            from: (modules[parent % (i + 1)].id, Connector::new(s1, d1)),
            orientation: Orientation::ALL[o % 4],
            to: (modules[i + 1].id, Connector::new(s2, d2)),
        })
        .collect();
    RofiConfiguration::from_parts(&modules, &connections).ok()
}

proptest! {
    #[test]
    fn a_plan_written_reads_back_the_same(
        worlds in proptest::collection::vec(
            (
                proptest::collection::vec((-90.0f64..=90.0, -90.0f64..=90.0, -720.0f64..720.0), 4),
                proptest::collection::vec((0usize..4, any_side(), any_dock(), 0usize..4, any_side(), any_dock()), 3),
            ),
            1..4,
        ),
    ) {
        let configurations: Vec<RofiConfiguration> = worlds
            .iter()
            .filter_map(|(angles, links)| configuration(angles, links))
            .collect();
        prop_assume!(!configurations.is_empty());
        let text = write_old_format(&configurations);
        let plan = read_old_format(&text).map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        let back: Vec<RofiConfiguration> = plan.configurations.into_iter().map(|(_, c)| c).collect();
        prop_assert_eq!(back, configurations, "{}", text);
    }
}
