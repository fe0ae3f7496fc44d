//! `--dispatch earliest|latest|goal-driven[:search|:marking]`, shared by the subcommands that run the
//! executive (flatten [`DispatchArg`] into their arguments).

use clap::Args;

use crate::dispatch::PolicyKind;

#[derive(Args, Debug, Clone, Copy)]
pub struct DispatchArg {
    /// When the executive starts actions: goal-driven (the default: actions serving an operator's goal start
    /// as early as possible, the others at their latest start; goal-driven:search or goal-driven:marking pick
    /// how that support is found), earliest (everything as early as possible), or latest.
    #[arg(long, default_value = "goal-driven", value_name = "POLICY")]
    pub dispatch: PolicyKind,
}
