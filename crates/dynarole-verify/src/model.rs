//! The model of a robot running a sequence: the sequences lowered, the robot's communication
//! graph as a `Topology`, the method chosen (one full model, or one compositional model per
//! module), and the Promela generated for it.

use crate::VerifyError;
use dynarole_codegen::{
    generate_compositional, generate_promela, liveness_graph, CompileOptions, Fault, LivenessGraph,
    Model, ModelOptions, Protocol, ProtocolInfo, Topology, TopologyLink, TopologyModule,
};
use dynarole_core::ast::SeparatorKind;
use dynarole_core::check::Label;
use dynarole_core::expand::Plan;
use dynarole_core::lower::{Ir, LimitError};
use dynarole_core::Program;
use dynarole_replay::{communication_graph, Assignment, CommGraph, RobotWorld};
use std::collections::BTreeSet;

/// How the robot is modelled (see docs/verification.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Compositional for the lattice protocol on more than [`AUTO_FULL_MODULES`] modules
    /// (one run, NV storage, no broken variant), full otherwise.
    Auto,
    /// Every module's logic and every link.
    Full,
    /// Lattice only: one model per module, every packet any state the robot has reached.
    Compositional,
}

/// Modules above which the full model's exhaustive search is not expected to finish: `auto`
/// then chooses the compositional model for the lattice protocol, and a full model is first
/// searched within bounds (`check::BOUNDED_STEPS`).
pub const AUTO_FULL_MODULES: usize = 3;

/// What the model is of: a checked program, its expanded sequences and where they run.
pub struct Inputs<'a> {
    pub program: &'a Program<'a>,
    /// The sequences' names, in turn (the model's name is them joined by ` + `).
    pub names: &'a [String],
    pub plans: &'a [Plan],
    /// The module behind every label on the start configuration.
    pub assignment: &'a Assignment,
    /// The start configuration, ready to replay the plans on.
    pub world: &'a RobotWorld,
    /// The configuration's name in messages (its file).
    pub configuration: &'a str,
}

/// The bounds of the environment and the method: what `compile --target promela` and
/// `verify` share.
#[derive(Clone, Debug)]
pub struct BuildOptions {
    /// The protocol and its options (its `name` is the model's).
    pub compile: CompileOptions,
    pub method: Method,
    /// Module resets, at most, in a run.
    pub resets: u8,
    /// The only modules that may reset (names in the configuration); empty: every module.
    pub reset_only: Vec<String>,
    /// Packets that can be in flight at once and be delivered late.
    pub late: u8,
    /// A deliberately broken lattice protocol (tests of the checker itself).
    pub fault: Option<Fault>,
}

/// A model and what it was made from.
pub struct Built {
    pub ir: Ir,
    pub models: Models,
    pub topology: Topology,
    pub graph: CommGraph,
    pub name: String,
}

/// The full model, or one compositional model per module.
pub enum Models {
    Full(Model),
    Compositional {
        /// One per module of the topology, in its order.
        per_module: Vec<Model>,
        liveness: LivenessGraph,
    },
}

impl Built {
    /// The files a model is written to (`model.pml`; the compositional method:
    /// `model-MODULE.pml` for each module), with their models.
    pub fn model_files(&self) -> Vec<(String, &Model)> {
        match &self.models {
            Models::Full(model) => vec![("model.pml".to_string(), model)],
            Models::Compositional { per_module, .. } => per_module
                .iter()
                .zip(&self.topology.modules)
                .map(|(model, m)| (format!("model-{}.pml", m.name), model))
                .collect(),
        }
    }
}

/// Whether `protocol` is one the model checker models (asked before anything is read).
pub fn modelled(protocol: Protocol) -> Result<(), VerifyError> {
    protocol.model().map(|_| ()).map_err(VerifyError::Usage)
}

fn limit_error(e: LimitError) -> VerifyError {
    VerifyError::Source(vec![e.into()])
}

/// Lowers and models the sequences on the configuration.
pub fn build(inputs: &Inputs, options: &BuildOptions) -> Result<Built, VerifyError> {
    let shape = options.compile.protocol.shape();
    let ir = dynarole_core::driver::lower(inputs.program, inputs.plans, shape)
        .map_err(|d| VerifyError::Source(vec![d]))?;
    let graph = communication_graph(
        inputs.program,
        inputs.plans,
        inputs.world.clone(),
        inputs.assignment,
    );
    let topology = topology(&ir, &graph, inputs.assignment)?;
    let model_options = ModelOptions {
        compile: options.compile.clone(),
        resets: options.resets,
        reset_modules: reset_modules(&graph, options, inputs.configuration)?,
        late: options.late,
        fault: options.fault,
    };
    refuse_what_is_not_modelled(options)?;
    let models = generate(&ir, &topology, &model_options, options.method).map_err(limit_error)?;
    Ok(Built {
        ir,
        models,
        topology,
        graph,
        name: inputs.names.join(" + "),
    })
}

/// The modules of `--reset-only`, as indices into the graph's modules.
fn reset_modules(
    graph: &CommGraph,
    options: &BuildOptions,
    configuration: &str,
) -> Result<Vec<usize>, VerifyError> {
    options
        .reset_only
        .iter()
        .map(|wanted| {
            graph.names.iter().position(|n| n == wanted).ok_or_else(|| {
                VerifyError::Usage(format!(
                    "--reset-only {wanted}: no module of that name in {configuration}"
                ))
            })
        })
        .collect()
}

/// The broken variants and the compositional method exist for the lattice protocol only.
fn refuse_what_is_not_modelled(options: &BuildOptions) -> Result<(), VerifyError> {
    let o = &options.compile;
    let broken = |info: &ProtocolInfo| info.model.is_some_and(|m| m.broken_variants);
    if !broken(o.protocol.info()) && options.fault.is_some() {
        return Err(VerifyError::Usage(format!(
            "the broken variants exist for the {} protocol only",
            Protocol::names_where(broken).join(" and ")
        )));
    }
    if options.method == Method::Compositional
        && (!o.protocol.has_compositional_model() || o.without_nv() || o.runs() != 1)
    {
        return Err(VerifyError::Usage(format!(
            "--method compositional models the {} protocol with NV storage and one run (--epochs 1); use --method full",
            Protocol::with_compositional_model()
        )));
    }
    Ok(())
}

/// Whether the compositional model is used: asked for, or `auto` on a lattice robot of more
/// than AUTO_FULL_MODULES modules (one run, NV, no broken variant).
fn compositional(options: &ModelOptions, modules: usize, method: Method) -> bool {
    let o = &options.compile;
    match method {
        Method::Full => false,
        Method::Compositional => true,
        Method::Auto => {
            o.protocol.has_compositional_model()
                && !o.without_nv()
                && o.runs() == 1
                && options.fault.is_none()
                && modules > AUTO_FULL_MODULES
        }
    }
}

fn generate(
    ir: &Ir,
    topology: &Topology,
    options: &ModelOptions,
    method: Method,
) -> Result<Models, LimitError> {
    if !compositional(options, topology.modules.len(), method) {
        return generate_promela(ir, topology, options).map(Models::Full);
    }
    // Late packets are subsumed: every packet is any state the robot has already reached.
    let options = ModelOptions {
        late: 0,
        ..options.clone()
    };
    let liveness = liveness_graph(ir, topology);
    let per_module = (0..topology.modules.len())
        .map(|k| generate_compositional(ir, topology, &options, k, &liveness))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Models::Compositional {
        per_module,
        liveness,
    })
}

/// The model's view of the robot: every module of the configuration with the address of the
/// label assigned to it, and its links (fair when they exist throughout).
fn topology(ir: &Ir, graph: &CommGraph, assignment: &Assignment) -> Result<Topology, VerifyError> {
    let modules = graph
        .names
        .iter()
        .map(|name| module(ir, assignment, name))
        .collect::<Result<Vec<_>, _>>()?;
    let all: BTreeSet<(usize, usize)> = graph.always.union(&graph.sometimes).copied().collect();
    let links = all
        .into_iter()
        .map(|(from, to)| TopologyLink {
            from,
            to,
            fair_stages: fair_stages(ir, graph, (from, to)),
        })
        .collect();
    Ok(Topology { modules, links })
}

/// The module `name` with the address of its role, if it has one.
fn module(ir: &Ir, assignment: &Assignment, name: &str) -> Result<TopologyModule, VerifyError> {
    let labels: Vec<&Label> = assignment
        .iter()
        .filter(|(_, module)| *module == name)
        .map(|(label, _)| label)
        .collect();
    let addresses: Vec<u8> = labels
        .iter()
        .filter_map(|l| ir.addresses.iter().find(|a| a.label == **l))
        .map(|a| a.number)
        .collect();
    if addresses.len() > 1 {
        return Err(VerifyError::Input(format!(
            "module {name} has several roles; the model needs one address per module"
        )));
    }
    Ok(TopologyModule {
        name: name.to_string(),
        address: addresses.first().copied(),
    })
}

/// The stages in which `link` surely exists. A link surely exists in stage k (statements
/// 0..k done, k not) when it exists in every configuration from the one after the first k
/// statements to the one after the group (up to the next `;`) that statement k belongs to;
/// in the last stage, in the final one.
fn fair_stages(ir: &Ir, graph: &CommGraph, link: (usize, usize)) -> Vec<usize> {
    let n = ir.statements.len();
    let group_end = |k: usize| -> usize {
        (k..n)
            .find(|&j| ir.statements[j].separator == SeparatorKind::Sequential)
            .map_or(n, |j| j + 1)
    };
    (0..=n)
        .filter(|&k| {
            let last = if k == n { n } else { group_end(k) };
            (k..=last).all(|t| graph.stages.get(t).is_some_and(|s| s.contains(&link)))
        })
        .collect()
}
