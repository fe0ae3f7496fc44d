//! Dispatch: when to start the actions of a flexible plan (seed 2, goal-driven dispatching).
//!
//! - [`graph`]: the dispatcher's view of the plan's causal structure ([`CausalView`]) and the plan-change
//!   notifications ([`Change`]) that keep an owned mirror ([`CausalGraph`]) up to date.
//! - [`search`]: Algorithm 2 (SearchForGoal), forward search over causal links to an external goal.
//! - [`marking`]: Algorithms 3–8, the incremental marking `List_goals`, with retraction on backtrack.
//! - [`plan_adapter`]: the same over the project's plan: [`PlanView`] (Algorithm 2 on the plan) and
//!   [`PlanMarking`] (the marking kept from the plan's change log across backtracks, repairs and replans).
//! - [`policy`]: the [`DispatchPolicy`] trait and the `earliest`, `latest` and `goal-driven` (Algorithm 1)
//!   policies, named in config and on the command line by [`PolicyKind`].
//! - [`dispatcher`]: Algorithm 1 over the standalone [`CausalGraph`] and its [`Marking`] (`mavtempo bench
//!   dispatch` and the dispatch scenario tests); the executive's own works over the plan.

pub mod dispatcher;
pub mod graph;
pub mod marking;
pub mod plan_adapter;
pub mod policy;
pub mod search;

/// A trail level of the [`Marking`] (the one level type of every trailed store).
pub use backtrack::Level as MarkLevel;
pub use graph::{
    ActionId, CausalGraph, CausalView, Change, Establisher, GoalId, GraphError, Link, LinkId, Node,
};
pub use marking::Marking;
pub use plan_adapter::{PlanMarking, PlanView};
pub use policy::{
    Decision, DispatchPolicy, Earliest, GoalDriven, Latest, PolicyKind, StartWindow, SupportForm,
    Tick, UnknownPolicy,
};
pub use search::{search_for_goal, GoalSearch};
