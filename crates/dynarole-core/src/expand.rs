//! Expansion of a sequence into a [`Plan`]: compositions and reversals inlined, every
//! statement resolved, the nesting of blocks kept. Later passes (replay, lowering) start here.

use crate::ast::*;
use crate::check::{resolve_statement, Program, ResolvedStatement};
use crate::diagnostic::{Diagnostic, DiagnosticKind};
use crate::span::Span;

/// A sequence with every name resolved: what the robot will do, in which order.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Plan {
    pub elements: Vec<PlanElement>,
    /// A synchronous group (`sync { ... }`): one parallel group of turns, started at one
    /// instant and moved in lock-step.
    pub synchronous: bool,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlanElement {
    pub kind: PlanKind,
    pub separator: SeparatorKind,
    /// Where this element comes from (for a reversed statement: the original statement).
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PlanKind {
    Op(ResolvedStatement),
    /// A block, or a sequence used inside another one.
    Block(Plan),
}

impl Program<'_> {
    /// The plan of sequence `name`, or `None` if there is no such sequence.
    pub fn expand(&self, name: &str) -> Option<Plan> {
        let decl = self.file.sequence(name)?;
        Some(match &decl.definition {
            SequenceDef::Body(body) => self.expand_body(body),
            SequenceDef::Reverse(target) => self.expand_reversed(&target.name),
        })
    }

    fn expand_reversed(&self, name: &str) -> Plan {
        match self.file.sequence(name).map(|d| &d.definition) {
            Some(SequenceDef::Body(body)) => self.expand_body(&self.reverse_body(body)),
            // The reverse of a reverse is the original.
            Some(SequenceDef::Reverse(target)) => self.expand(&target.name).unwrap_or_default(),
            None => Plan::default(),
        }
    }

    fn expand_body(&self, body: &Body) -> Plan {
        let elements = body
            .elements
            .iter()
            .filter_map(|element| {
                let kind = match &element.kind {
                    ElementKind::Statement(s) => {
                        PlanKind::Op(resolve_statement(self.file, s, &self.robot).ok()?)
                    }
                    ElementKind::Block(inner) => PlanKind::Block(self.expand_body(inner)),
                    ElementKind::Call(call) if call.reverse.is_some() => {
                        PlanKind::Block(self.expand_reversed(&call.name.name))
                    }
                    ElementKind::Call(call) => PlanKind::Block(self.expand(&call.name.name)?),
                };
                Some(PlanElement {
                    kind,
                    separator: element.separator.kind,
                    span: element.span,
                })
            })
            .collect();
        Plan {
            elements,
            synchronous: body.synchronous.is_some(),
        }
    }
}

impl Plan {
    /// Every statement, in source order.
    pub fn statements(&self) -> Vec<&ResolvedStatement> {
        let mut out = Vec::new();
        self.collect(&mut out);
        out
    }

    fn collect<'p>(&'p self, out: &mut Vec<&'p ResolvedStatement>) {
        for element in &self.elements {
            match &element.kind {
                PlanKind::Op(s) => out.push(s),
                PlanKind::Block(inner) => inner.collect(out),
            }
        }
    }

    /// Where its first synchronous group is, nested ones included.
    pub fn first_synchronous(&self) -> Option<Span> {
        self.elements
            .iter()
            .find_map(|element| match &element.kind {
                PlanKind::Block(inner) if inner.synchronous => Some(element.span),
                PlanKind::Block(inner) => inner.first_synchronous(),
                PlanKind::Op(_) => None,
            })
    }

    /// The plan as the paper's state machine can run it: a flat list of statements, each with
    /// its separator. A block is spliced in when that keeps its meaning (it is alone in its
    /// parallel group, or it is itself one parallel group); otherwise the paper protocol, with
    /// its single pending set, cannot express it (Sec. III-A), and this says where.
    pub fn flatten_for_paper(&self) -> Result<Vec<(ResolvedStatement, SeparatorKind)>, Diagnostic> {
        let mut out: Vec<(ResolvedStatement, SeparatorKind)> = Vec::new();
        let group_sizes = self.group_sizes();
        for (element, &group_size) in self.elements.iter().zip(&group_sizes) {
            match &element.kind {
                PlanKind::Op(s) => out.push((s.clone(), element.separator)),
                PlanKind::Block(inner) if inner.synchronous => {
                    let reason = "the paper protocol has no synchronous start".to_string();
                    return Err(Diagnostic::new(
                        DiagnosticKind::NotSupportedByPaperProtocol { reason },
                        element.span,
                    ));
                }
                PlanKind::Block(inner) => {
                    let flat = inner.flatten_for_paper()?;
                    let inner_groups = flat
                        .iter()
                        .filter(|(_, sep)| *sep == SeparatorKind::Sequential)
                        .count();
                    if group_size > 1 && inner_groups > 1 {
                        let reason = "this block has sequential steps and runs in parallel with other statements".to_string();
                        return Err(Diagnostic::new(
                            DiagnosticKind::NotSupportedByPaperProtocol { reason },
                            element.span,
                        ));
                    }
                    splice(&mut out, flat, element.separator);
                }
            }
        }
        Ok(out)
    }

    /// For each element, the size of the parallel group it belongs to: the elements before
    /// it in the group and those up to and including the next `;` (none if no `;` follows).
    /// Two passes, so a group of any length costs its length.
    fn group_sizes(&self) -> Vec<usize> {
        let n = self.elements.len();
        let mut sizes = vec![0; n];
        let mut next_sequential = None;
        for i in (0..n).rev() {
            if self.elements[i].separator == SeparatorKind::Sequential {
                next_sequential = Some(i);
            }
            sizes[i] = next_sequential.map_or(0, |end| end - i + 1);
        }
        let mut before = 0;
        for (size, element) in sizes.iter_mut().zip(&self.elements) {
            *size += before;
            before = if element.separator == SeparatorKind::Sequential {
                0
            } else {
                before + 1
            };
        }
        sizes
    }
}

/// Appends a flattened block; its last statement takes the block's own separator.
fn splice(
    out: &mut Vec<(ResolvedStatement, SeparatorKind)>,
    mut flat: Vec<(ResolvedStatement, SeparatorKind)>,
    separator: SeparatorKind,
) {
    match flat.last_mut() {
        Some(last) => last.1 = separator,
        // An empty block still closes the group it ends.
        None => {
            if let (Some(last), SeparatorKind::Sequential) = (out.last_mut(), separator) {
                last.1 = SeparatorKind::Sequential;
            }
        }
    }
    out.append(&mut flat);
}
