//! A counterexample as the steps of a run on the model (what `verify --record` draws): each
//! issue, completion, reset and copy of the shared state by the module's name, and the broken
//! property where it breaks.

use crate::explain::Counterexample;
use crate::trail::Event;
use dynarole_core::lower::Ir;
use dynarole_recording::ModelStep;

/// The steps of `cx` (statements numbered as in `ir`) and the properties it breaks, in order.
pub fn counterexample_steps(cx: &Counterexample, ir: &Ir) -> (Vec<ModelStep>, Vec<String>) {
    let name = |m: &usize| cx.module_names.get(*m).cloned().unwrap_or_default();
    let mut broken = Vec::new();
    let steps = cx
        .events
        .iter()
        .enumerate()
        .filter_map(|(k, e)| match e {
            Event::Issue { m, s, .. } => Some(ModelStep::Issue(*s, name(m))),
            Event::Done { m, s } => Some(ModelStep::Done(*s, name(m))),
            Event::Reset { m } => Some(ModelStep::Reset(name(m))),
            Event::Copy { m, .. } => Some(ModelStep::Copy(name(m), cx.copies.get(&k)?.clone())),
            Event::Violation { property, m, s } => {
                broken.push(property.clone());
                let text = ir.statements.get(*s).map_or("", |st| st.text.as_str());
                Some(ModelStep::Violation(
                    name(m),
                    format!("#{s} {text}: {property} broken here"),
                ))
            }
            _ => None,
        })
        .collect();
    (steps, broken)
}
