//! `--dispatch earliest|latest|goal-driven[:search|:marking]`, shared by the subcommands that run the
//! executive (flatten [`DispatchArg`] into their arguments).

use clap::Args;

use crate::dispatch::PolicyKind;

#[derive(Args, Debug, Clone, Copy)]
pub struct DispatchArg {
    /// When the executive starts actions: earliest (IxTeT-eXeC), latest, or goal-driven (seed 2; its
    /// support test by Algorithm 2 search or the incremental marking: goal-driven:search, goal-driven:marking).
    #[arg(long, default_value = "earliest", value_name = "POLICY")]
    pub dispatch: PolicyKind,
}
