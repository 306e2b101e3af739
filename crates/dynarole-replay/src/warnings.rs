//! The model's warnings compared as multisets: what two orders of the same statements warn
//! about, a split into the same two parts being the same whichever side commanded it.

use crate::robot_world::Warned;
use dynarole_world::Warning;

/// The first warning of `these` that `others` does not have (counting repeats).
pub(crate) fn unmatched<'w>(these: &'w [Warned], others: &[Warned]) -> Option<&'w Warned> {
    let mut left: Vec<&Warning> = others.iter().map(|(_, warning)| warning).collect();
    these.iter().find(|(_, warning)| {
        match left.iter().position(|other| same_warning(other, warning)) {
            Some(k) => {
                left.swap_remove(k);
                false
            }
            None => true,
        }
    })
}

/// The same warning as the model reports it, but a split into the same two parts is the same
/// whichever side commanded it (the model lists the commanding module's side first).
fn same_warning(a: &Warning, b: &Warning) -> bool {
    match (a, b) {
        (
            Warning::Split { first, second },
            Warning::Split {
                first: other_first,
                second: other_second,
            },
        ) => {
            (first == other_first && second == other_second)
                || (first == other_second && second == other_first)
        }
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(first: &[&str], second: &[&str]) -> Warned {
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect();
        let warning = Warning::Split {
            first: names(first),
            second: names(second),
        };
        ("step".to_string(), warning)
    }

    #[test]
    fn one_split_is_the_same_whichever_side_commands_it() {
        // Two retracts that each leave M4 alone when done second: either order ends with the
        // same split, reported from the other side.
        let ab = [split(&["M4"], &["M0", "M1"])];
        let ba = [split(&["M0", "M1"], &["M4"])];
        assert!(unmatched(&ab, &ba).is_none());
        assert!(unmatched(&ba, &ab).is_none());
    }

    #[test]
    fn a_warning_in_one_order_only_is_unmatched_counting_repeats() {
        let once = [split(&["M3"], &["M0"])];
        let twice = [split(&["M3"], &["M0"]), split(&["M0"], &["M3"])];
        let other = [split(&["M4"], &["M0", "M3"])];
        assert!(unmatched(&once, &[]).is_some());
        assert!(unmatched(&[], &once).is_none());
        assert!(unmatched(&twice, &once).is_some());
        assert!(unmatched(&once, &other).is_some());
    }
}
