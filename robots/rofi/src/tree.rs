//! The spanning tree the shoes are placed along: from shoe A of the lowest-ID module, every
//! module's own joints an edge of it (so each turn splits it in two), each connection either
//! an edge or a loop that must close; and the transforms its edges are made of, RoFI's legacy
//! frames. The kinematics and the sweep both place shoes along it.
//!
//! From a shoe, the module's other shoe is Rx(near)·Rz(γ)·T(0,0,1)·Ry(π)·Rx(−far), with
//! (near, far) = (α, β) from shoe A and (β, α) from shoe B; across a connection from dock d1
//! to dock d2 with twist o, the partner's shoe is face(d1)·Rz(o·90°)·T(0,0,−1)·up(d2)·Rx(π),
//! where face and up turn a dock's face onto the shoe's −Z (±X docks: Rz(π)·Ry(±90°), −Z:
//! none).

use crate::module::{Connection, Connector, Dock, Module, RofiConfiguration, Side};
use nalgebra::{Matrix4, Rotation3, Translation3, Unit, Vector3};
use std::collections::{BTreeMap, VecDeque};
use std::f64::consts::{FRAC_PI_2, PI};

/// A shoe: its module's ID and its side.
pub type Shoe = (u32, Side);

/// How far (largest difference of one matrix entry) a shoe's pose found along a loop may be
/// from the pose it already has for the loop to count as closed: RoFI's legacy tolerance.
pub const LOOP_TOLERANCE: f64 = 1e-3;

/// A spanning tree of the shoes in which every module's own link is an edge: shoes by index
/// (module's position in ID order · 2 + side), each placed from its parent.
pub(crate) struct Tree {
    pub(crate) modules: Vec<Module>,
    /// Shoes in placing order: (shoe, parent shoe and how to get there from it).
    order: Vec<(usize, Option<(usize, Link)>)>,
    /// Connections not in the tree: they must stay closed.
    loops: Vec<Connection>,
    /// For each shoe, the interval of its subtree in the placing order (Euler tour).
    subtree: Vec<(usize, usize)>,
    pub(crate) parent: Vec<Option<usize>>,
    pub(crate) index: BTreeMap<u32, usize>,
}

#[derive(Clone, Copy)]
enum Link {
    /// Across the module's joints from the parent's side.
    Module(Side),
    /// Across a connection from the parent's dock.
    Connection(Dock, u8, Dock),
}

impl Tree {
    /// The tree of `config` from shoe A of its lowest-ID module; the error lists the modules
    /// no connection reaches.
    pub(crate) fn of(config: &RofiConfiguration) -> Result<Tree, Vec<u32>> {
        let modules: Vec<Module> = config.modules().copied().collect();
        let index: BTreeMap<u32, usize> = (modules.iter().enumerate())
            .map(|(i, m)| (m.id, i))
            .collect();
        let shoe = |id: u32, side: Side| index.get(&id).map(|m| m * 2 + side as usize);
        let n = modules.len() * 2;
        let mut parent = vec![None; n];
        let mut order = Vec::with_capacity(n);
        let mut placed = vec![false; n];
        let mut tree_connections = Vec::new();
        let mut queue = VecDeque::new();
        if n > 0 {
            placed[0] = true;
            order.push((0, None));
            placed[1] = true;
            parent[1] = Some(0);
            order.push((1, Some((0, Link::Module(Side::A)))));
            queue.push_back(0usize);
        }
        while let Some(m) = queue.pop_front() {
            for side in [Side::A, Side::B] {
                for dock in Dock::ALL {
                    let here = m * 2 + side as usize;
                    let port = (modules[m].id, Connector::new(side, dock));
                    let Some(c) = config.connection_at(port) else {
                        continue;
                    };
                    let Some(there) = shoe(c.to.0, c.to.1.side()) else {
                        continue;
                    };
                    if placed[there] {
                        continue;
                    }
                    let link = Link::Connection(dock, c.orientation.quarter_turns(), c.to.1.dock());
                    placed[there] = true;
                    parent[there] = Some(here);
                    order.push((there, Some((here, link))));
                    tree_connections.push(c);
                    let other = there ^ 1;
                    placed[other] = true;
                    parent[other] = Some(there);
                    order.push((other, Some((there, Link::Module(c.to.1.side())))));
                    queue.push_back(there / 2);
                }
            }
        }
        let unreached: Vec<u32> = (modules.iter().enumerate())
            .filter(|(m, _)| !placed[m * 2])
            .map(|(_, module)| module.id)
            .collect();
        if !unreached.is_empty() {
            return Err(unreached);
        }
        let in_tree = |c: &Connection| {
            tree_connections
                .iter()
                .any(|t| *t == *c || *t == c.reversed())
        };
        let loops = (config.connections().iter())
            .filter(|c| !in_tree(c))
            .copied()
            .collect();
        let subtree = euler(&parent, &order);
        Ok(Tree {
            modules,
            order,
            loops,
            subtree,
            parent,
            index,
        })
    }

    /// The connections the tree does not use: each closes a loop.
    pub(crate) fn loops(&self) -> &[Connection] {
        &self.loops
    }

    pub(crate) fn shoe_index(&self, (id, side): Shoe) -> Option<usize> {
        self.index.get(&id).map(|m| m * 2 + side as usize)
    }

    pub(crate) fn shoe_of(&self, index: usize) -> Shoe {
        let side = if index % 2 == 0 { Side::A } else { Side::B };
        (self.modules[index / 2].id, side)
    }

    /// Is `shoe` in the subtree of `root`?
    pub(crate) fn within(&self, shoe: usize, root: usize) -> bool {
        let (a, b) = self.subtree[root];
        let (x, _) = self.subtree[shoe];
        a <= x && x < b
    }

    /// Tree links from every shoe to `from`.
    pub(crate) fn hops_from(&self, from: usize) -> Vec<usize> {
        let n = self.parent.len();
        let mut neighbours = vec![Vec::new(); n];
        for (child, p) in self.parent.iter().enumerate() {
            if let Some(p) = p {
                neighbours[child].push(*p);
                neighbours[*p].push(child);
            }
        }
        let mut hops = vec![usize::MAX; n];
        hops[from] = 0;
        let mut queue = VecDeque::from([from]);
        while let Some(s) = queue.pop_front() {
            for &t in &neighbours[s] {
                if hops[t] == usize::MAX {
                    hops[t] = hops[s] + 1;
                    queue.push_back(t);
                }
            }
        }
        hops
    }

    /// Every shoe's pose with the modules' joints at `modules`' angles.
    pub(crate) fn poses(&self, modules: &[Module]) -> Vec<Matrix4<f64>> {
        let mut poses = vec![Matrix4::identity(); self.parent.len()];
        for &(shoe, from) in &self.order {
            if let Some((parent, link)) = from {
                let step = match link {
                    Link::Module(side) => across_module(&modules[parent / 2], side),
                    Link::Connection(d1, o, d2) => across_connection(d1, o, d2),
                };
                poses[shoe] = poses[parent] * step;
            }
        }
        poses
    }
    /// A connection outside the tree whose two shoes do not mate at `poses`, and by how much
    /// (the largest difference of one matrix entry) they miss.
    pub(crate) fn open_loop(&self, poses: &[Matrix4<f64>]) -> Option<(Connection, f64)> {
        self.loops.iter().find_map(|c| {
            let ends = (
                self.shoe_index((c.from.0, c.from.1.side())),
                self.shoe_index((c.to.0, c.to.1.side())),
            );
            // Both ends are modules of the tree: a connection names declared modules only.
            let (Some(from), Some(to)) = ends else {
                return Some((*c, f64::INFINITY));
            };
            let step = across_connection(
                c.from.1.dock(),
                c.orientation.quarter_turns(),
                c.to.1.dock(),
            );
            let gap = (poses[from] * step - poses[to]).abs().max();
            (gap > LOOP_TOLERANCE).then_some((*c, gap))
        })
    }
}

/// Each shoe's (entry, exit) in a depth-first walk of the tree given by `parent`.
fn euler(
    parent: &[Option<usize>],
    order: &[(usize, Option<(usize, Link)>)],
) -> Vec<(usize, usize)> {
    let n = parent.len();
    let mut children = vec![Vec::new(); n];
    for &(shoe, from) in order {
        if let Some((p, _)) = from {
            children[p].push(shoe);
        }
    }
    let mut span = vec![(0, 0); n];
    let mut clock = 0;
    // (shoe, next child to visit)
    let mut stack = vec![(0usize, 0usize)];
    if n == 0 {
        return span;
    }
    span[0].0 = clock;
    clock += 1;
    while let Some((shoe, next)) = stack.last().copied() {
        if let Some(&child) = children[shoe].get(next) {
            if let Some(top) = stack.last_mut() {
                top.1 += 1;
            }
            span[child].0 = clock;
            clock += 1;
            stack.push((child, 0));
        } else {
            span[shoe].1 = clock;
            stack.pop();
        }
    }
    span
}

/// From shoe `from` of `module` to its other shoe.
pub fn across_module(module: &Module, from: Side) -> Matrix4<f64> {
    let (near, far) = match from {
        Side::A => (module.alpha, module.beta),
        Side::B => (module.beta, module.alpha),
    };
    rotation(Vector3::x(), near.to_radians())
        * rotation(Vector3::z(), module.gamma.to_radians())
        * translation(Vector3::z())
        * rotation(Vector3::y(), PI)
        * rotation(Vector3::x(), -far.to_radians())
}

/// From a shoe to the shoe mated at its dock `from` (partner's dock `to`, twist in quarter
/// turns).
pub fn across_connection(from: Dock, quarter_turns: u8, to: Dock) -> Matrix4<f64> {
    face_to_dock(from)
        * rotation(Vector3::z(), f64::from(quarter_turns) * FRAC_PI_2)
        * translation(-Vector3::z())
        * dock_face_up(to)
        * rotation(Vector3::x(), PI)
}

/// Turns the shoe's −Z face onto dock `dock`'s face (the way out of the shoe).
pub(crate) fn face_to_dock(dock: Dock) -> Matrix4<f64> {
    match dock {
        Dock::PlusX => rotation(Vector3::z(), PI) * rotation(Vector3::y(), FRAC_PI_2),
        Dock::MinusX => rotation(Vector3::z(), PI) * rotation(Vector3::y(), -FRAC_PI_2),
        Dock::MinusZ => Matrix4::identity(),
    }
}

/// Turns dock `dock`'s face onto the shoe's −Z face (the way into the partner's shoe).
fn dock_face_up(dock: Dock) -> Matrix4<f64> {
    match dock {
        Dock::PlusX => rotation(Vector3::z(), PI) * rotation(Vector3::y(), -FRAC_PI_2),
        Dock::MinusX => rotation(Vector3::z(), PI) * rotation(Vector3::y(), FRAC_PI_2),
        Dock::MinusZ => Matrix4::identity(),
    }
}

fn rotation(axis: Vector3<f64>, radians: f64) -> Matrix4<f64> {
    Rotation3::from_axis_angle(&Unit::new_normalize(axis), radians).to_homogeneous()
}

fn translation(by: Vector3<f64>) -> Matrix4<f64> {
    Translation3::from(by).to_homogeneous()
}
