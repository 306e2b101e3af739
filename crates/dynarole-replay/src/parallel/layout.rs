//! The graph side of `parallelise`: sets of statements, ancestors, transitive reduction,
//! and the ways of writing a dependency graph in the language (parallel groups, series-parallel
//! blocks, the input's own groups).

use crate::bitset::BitSet;
use dynarole_core::ast::SeparatorKind;
use dynarole_core::expand::{Plan, PlanKind};
use std::collections::BTreeMap;

/// A sequence's statements arranged in the language: a statement, statements or blocks one
/// after the other (`;`), or side by side (`&`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Layout {
    Op(usize),
    Seq(Vec<Layout>),
    Par(Vec<Layout>),
}

/// The ancestors of every statement under `edges` (which point forwards).
pub(super) fn ancestors(n: usize, edges: &[(usize, usize)]) -> Vec<BitSet> {
    let mut parents = vec![Vec::new(); n];
    for &(i, j) in edges {
        parents[j].push(i);
    }
    let mut out: Vec<BitSet> = Vec::with_capacity(n);
    for (j, ps) in parents.iter().enumerate() {
        let mut set = BitSet::new(n);
        for &p in ps.iter().filter(|p| **p < j) {
            set.union(&out[p]);
            set.insert(p);
        }
        out.push(set);
    }
    out
}

/// Keeps only the edges no other path implies.
pub fn transitive_reduction(n: usize, edges: &[(usize, usize)]) -> Vec<(usize, usize)> {
    let anc = ancestors(n, edges);
    let mut parents: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(i, j) in edges {
        if i < j && j < n {
            parents[j].push(i);
        }
    }
    let mut out = Vec::new();
    for (j, ps) in parents.iter_mut().enumerate() {
        // Latest parent first: a parent is redundant when a later one already reaches it
        // (edges point forwards, so only a later parent can).
        ps.sort_unstable_by(|a, b| b.cmp(a));
        ps.dedup();
        let mut reached = BitSet::new(n);
        for &i in ps.iter() {
            if !reached.contains(i) {
                out.push((i, j));
                reached.union(&anc[i]);
                reached.insert(i);
            }
        }
    }
    out.sort_unstable();
    out
}

/// Statement `j` runs in group `level[j]`: one after the latest group of its parents.
pub(super) fn levels_layout(n: usize, edges: &[(usize, usize)]) -> Layout {
    let mut level = vec![0usize; n];
    // By later statement: every edge points forwards, so a parent's level is final first.
    let mut sorted: Vec<(usize, usize)> = edges
        .iter()
        .filter(|(i, j)| i < j && *j < n)
        .copied()
        .collect();
    sorted.sort_unstable_by_key(|&(_, j)| j);
    for &(i, j) in &sorted {
        level[j] = level[j].max(level[i] + 1);
    }
    let depth = level.iter().max().map_or(0, |m| m + 1);
    let groups = (0..depth)
        .map(|l| group((0..n).filter(|&s| level[s] == l).map(Layout::Op).collect()))
        .collect();
    Layout::Seq(groups)
}

/// The plan's own groups and blocks, statements numbered in input order.
pub(super) fn written_layout(plan: &Plan, next: &mut usize) -> Layout {
    let mut groups = Vec::new();
    let mut current = Vec::new();
    for element in &plan.elements {
        current.push(match &element.kind {
            PlanKind::Op(_) => {
                *next += 1;
                Layout::Op(*next - 1)
            }
            // Bounded by the parser's nesting limit.
            PlanKind::Block(inner) => written_layout(inner, next),
        });
        if element.separator == SeparatorKind::Sequential {
            groups.push(group(std::mem::take(&mut current)));
        }
    }
    if !current.is_empty() {
        groups.push(group(current));
    }
    Layout::Seq(groups)
}

/// Whether a sequence is nested anywhere below the top level (a block).
pub(super) fn has_blocks(layout: &Layout) -> bool {
    let children = match layout {
        Layout::Op(_) => return false,
        Layout::Seq(v) | Layout::Par(v) => v,
    };
    children.iter().any(|c| match c {
        Layout::Seq(_) => true,
        Layout::Par(v) => v.iter().any(|m| !matches!(m, Layout::Op(_))),
        Layout::Op(_) => false,
    })
}

pub(super) fn group(mut members: Vec<Layout>) -> Layout {
    if members.len() == 1 {
        members.remove(0)
    } else {
        Layout::Par(members)
    }
}

/// Series-parallel decomposition of the graph: independent parts side by side, and a part
/// split where everything before the cut precedes everything after it. Where the graph is not
/// series-parallel, the first level is cut off, which orders more than the graph asks.
pub(super) fn series_parallel(n: usize, edges: &[(usize, usize)]) -> Layout {
    let anc = ancestors(n, edges);
    let nodes: Vec<usize> = (0..n).collect();
    let mut work = SpWork { anc: &anc, edges };
    match work.layout(&nodes, 0) {
        Layout::Seq(groups) => Layout::Seq(groups),
        // One group: written like the levels, as the body's only group.
        other => Layout::Seq(vec![other]),
    }
}

struct SpWork<'a> {
    anc: &'a [BitSet],
    edges: &'a [(usize, usize)],
}

impl SpWork<'_> {
    /// Each call removes at least one node or splits the set, so the depth is at most `n`;
    /// beyond `MAX_DEPTH` the rest is written as levels.
    fn layout(&mut self, nodes: &[usize], depth: usize) -> Layout {
        const MAX_DEPTH: usize = 48;
        if nodes.len() == 1 {
            return Layout::Op(nodes[0]);
        }
        let sub: Vec<(usize, usize)> = self.induced(nodes);
        if depth >= MAX_DEPTH {
            return relabelled_levels(nodes, &sub);
        }
        let parts = components(nodes, &sub);
        if parts.len() > 1 {
            return Layout::Par(parts.iter().map(|p| self.layout(p, depth + 1)).collect());
        }
        let cuts = self.series_cuts(nodes, &sub);
        let pieces = if cuts.len() > 1 {
            cuts
        } else {
            first_level_cut(nodes, &sub)
        };
        let mut out = Vec::new();
        for piece in &pieces {
            match self.layout(piece, depth + 1) {
                Layout::Seq(inner) => out.extend(inner),
                other => out.push(other),
            }
        }
        Layout::Seq(out)
    }

    fn induced(&self, nodes: &[usize]) -> Vec<(usize, usize)> {
        self.edges
            .iter()
            .filter(|(i, j)| nodes.binary_search(i).is_ok() && nodes.binary_search(j).is_ok())
            .copied()
            .collect()
    }

    /// Pieces of `nodes` (a topological order) at every position where all the nodes before
    /// are ancestors of all the nodes after.
    fn series_cuts(&self, nodes: &[usize], sub: &[(usize, usize)]) -> Vec<Vec<usize>> {
        let order = topological(nodes, sub);
        let mut pieces = Vec::new();
        let mut start = 0;
        for cut in 1..order.len() {
            let (before, after) = order.split_at(cut);
            let clean = after
                .iter()
                .all(|&a| before[start..].iter().all(|&b| self.anc[a].contains(b)));
            if clean {
                let mut piece = before[start..].to_vec();
                piece.sort_unstable();
                pieces.push(piece);
                start = cut;
            }
        }
        let mut last = order[start..].to_vec();
        last.sort_unstable();
        pieces.push(last);
        pieces
    }
}

/// The statements with no parent in `sub`, then the rest.
fn first_level_cut(nodes: &[usize], sub: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let (first, rest): (Vec<usize>, Vec<usize>) = nodes
        .iter()
        .partition(|n| !sub.iter().any(|(_, j)| j == *n));
    vec![first, rest]
        .into_iter()
        .filter(|p| !p.is_empty())
        .collect()
}

fn relabelled_levels(nodes: &[usize], sub: &[(usize, usize)]) -> Layout {
    let local: BTreeMap<usize, usize> = nodes.iter().enumerate().map(|(k, n)| (*n, k)).collect();
    let edges: Vec<(usize, usize)> = sub
        .iter()
        .filter_map(|(i, j)| Some((*local.get(i)?, *local.get(j)?)))
        .collect();
    relabel(levels_layout(nodes.len(), &edges), nodes)
}

fn relabel(layout: Layout, nodes: &[usize]) -> Layout {
    match layout {
        Layout::Op(k) => Layout::Op(nodes.get(k).copied().unwrap_or(k)),
        Layout::Seq(v) => Layout::Seq(v.into_iter().map(|l| relabel(l, nodes)).collect()),
        Layout::Par(v) => Layout::Par(v.into_iter().map(|l| relabel(l, nodes)).collect()),
    }
}

/// Kahn's order, smallest index first (input order when the graph allows it).
fn topological(nodes: &[usize], sub: &[(usize, usize)]) -> Vec<usize> {
    let mut indegree: BTreeMap<usize, usize> = nodes.iter().map(|n| (*n, 0)).collect();
    for (_, j) in sub {
        *indegree.entry(*j).or_default() += 1;
    }
    let mut ready: std::collections::BTreeSet<usize> = indegree
        .iter()
        .filter(|(_, d)| **d == 0)
        .map(|(n, _)| *n)
        .collect();
    let mut order = Vec::with_capacity(nodes.len());
    while let Some(n) = ready.pop_first() {
        order.push(n);
        for (_, j) in sub.iter().filter(|(i, _)| *i == n) {
            if let Some(d) = indegree.get_mut(j) {
                *d -= 1;
                if *d == 0 {
                    ready.insert(*j);
                }
            }
        }
    }
    order
}

/// Weakly connected components, each sorted, ordered by their first node.
fn components(nodes: &[usize], sub: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let mut root: BTreeMap<usize, usize> = nodes.iter().map(|n| (*n, *n)).collect();
    fn find(root: &BTreeMap<usize, usize>, mut n: usize) -> usize {
        // Bounded: every step goes to a smaller index.
        while let Some(&r) = root.get(&n) {
            if r == n {
                break;
            }
            n = r;
        }
        n
    }
    for &(i, j) in sub {
        let (ri, rj) = (find(&root, i), find(&root, j));
        let (lo, hi) = (ri.min(rj), ri.max(rj));
        root.insert(hi, lo);
    }
    let mut parts: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &n in nodes {
        parts.entry(find(&root, n)).or_default().push(n);
    }
    parts.into_values().collect()
}
