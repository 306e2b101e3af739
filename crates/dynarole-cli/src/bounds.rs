//! The bounds of a model's environment (`--resets`, `--reset-only`, `--late`, `--method`):
//! below `compile` and `model`, which both flatten them, so that neither imports the other.

/// The bounds of the environment, shared by `verify` and `compile --target promela`.
#[derive(Clone, Debug, clap::Args)]
pub struct ModelArgs {
    /// Module resets, at most, in a run (any module, at any moment, mid-operation included).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub resets: u8,
    /// Only this module may reset (its name in the configuration); may be repeated.
    #[arg(long = "reset-only", value_name = "MODULE")]
    pub reset_only: Vec<String>,
    /// Packets that can be in flight at once and be delivered late (again and again, so also
    /// duplicated and reordered). Losses are not bounded: any packet may be lost.
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub late: u8,
    /// How to model the robot: `full` (every module's logic and every link), `compositional`
    /// (lattice only: one model per module, every packet any state the robot has reached;
    /// scales to large robots), `auto` (compositional for the lattice protocol on more than
    /// three modules).
    #[arg(long, value_enum, default_value_t = MethodArg::Auto)]
    pub method: MethodArg,
}

/// How the robot is modelled (see docs/verification.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodArg {
    Auto,
    Full,
    Compositional,
}
