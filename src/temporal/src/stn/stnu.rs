//! Simple Temporal Network with Uncertainty (STNU; Vidal & Fargier 1999, Morris, Muscettola & Vidal 2001):
//! an STN whose *requirement* constraints the executive must satisfy, plus *contingent links* `(A, l, u, C)`:
//! once the activation timepoint `A` is executed, the world — not the executive — decides when the
//! contingent timepoint `C` happens, somewhere in `[A + l, A + u]` (a move's, a download's duration).
//!
//! The network is *dynamically controllable* (DC) when the executive can satisfy every requirement whatever
//! the durations, deciding each of its timepoints only from the contingent ends observed so far.
//! [`Stnu::check_dc`] decides it by Morris's O(n³) algorithm ([`super::dc`]);
//! [`super::dc_reference`] is the classic tightening fixpoint of Morris & Muscettola 2005, the test
//! oracle and bench baseline.
//!
//! Nodes are dense indices `0..n` chosen by the caller (the plan uses its STN's timepoint indices).

use super::Time;
use super::INF;

/// A requirement constraint `to − from ∈ [lb, ub]` (`-INF` / `INF` for none).
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug)]
pub struct Requirement {
    pub from: usize,
    pub to: usize,
    pub lb: Time,
    pub ub: Time,
}

/// A contingent link: `contingent − activation ∈ [lower, upper]`, chosen by the world.
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug)]
pub struct ContingentLink {
    pub activation: usize,
    pub contingent: usize,
    pub lower: Time,
    pub upper: Time,
}

/// An STNU over nodes `0..n`.
#[derive(Clone, Default, Debug)]
pub struct Stnu {
    n: usize,
    requirements: Vec<Requirement>,
    links: Vec<ContingentLink>,
}

/// A network the DC check cannot take.
#[derive(Clone, Eq, PartialEq, Debug, thiserror::Error)]
pub enum StnuError {
    #[error("node {node} is outside the network's {n} nodes")]
    NoSuchNode { node: usize, n: usize },
    #[error("a contingent link needs finite bounds 0 <= lower <= upper, found [{lower}, {upper}]")]
    BadBounds { lower: Time, upper: Time },
    #[error(
        "node {node} is already the contingent end of a link: the world cannot decide it twice"
    )]
    TwiceContingent { node: usize },
    #[error("a contingent link cannot start and end at node {node}")]
    SelfLink { node: usize },
}

/// Why a network is not dynamically controllable: the semi-reducible negative cycle found, as the
/// contingent links and requirements whose edges (or whose derived edges) make it up. With no link, the
/// requirements alone are inconsistent.
#[derive(Clone, Eq, PartialEq, Debug, thiserror::Error)]
#[error("{}", self.describe())]
pub struct NotDc {
    /// Indices into [`Stnu::links`], sorted, deduplicated.
    pub links: Vec<usize>,
    /// Indices into [`Stnu::requirements`], sorted, deduplicated.
    pub requirements: Vec<usize>,
}

impl NotDc {
    fn describe(&self) -> String {
        if self.links.is_empty() {
            format!(
                "not dynamically controllable: requirements {:?} are inconsistent",
                self.requirements
            )
        } else {
            format!(
                "not dynamically controllable: the durations the world chooses for contingent link(s) {:?} \
                 can violate requirement(s) {:?}",
                self.links, self.requirements
            )
        }
    }
}

/// A wait (Morris, Muscettola & Vidal 2001): `node` must not be executed before `activation + delay`
/// unless the link's contingent end has been observed first.
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug)]
pub struct Wait {
    pub node: usize,
    /// Index into [`Stnu::links`].
    pub link: usize,
    pub delay: Time,
}

/// An ordinary constraint `to − from ≤ weight` derived by the check (a consequence of DC execution).
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug)]
pub struct DerivedEdge {
    pub from: usize,
    pub to: usize,
    pub weight: Time,
}

/// The dispatchable form of a DC network: the requirements, the derived ordinary edges, and the waits an
/// executive honours (it executes a controllable node only once its waits are over, reacting to each
/// contingent end as it is observed).
#[derive(Clone, Default, Debug)]
pub struct Dispatchable {
    pub edges: Vec<DerivedEdge>,
    pub waits: Vec<Wait>,
}

impl Dispatchable {
    /// The waits on `node`.
    pub fn waits_on(&self, node: usize) -> impl Iterator<Item = &Wait> + '_ {
        self.waits.iter().filter(move |w| w.node == node)
    }
}

impl Stnu {
    /// An empty network over nodes `0..n`.
    pub fn new(n: usize) -> Self {
        Stnu {
            n,
            ..Stnu::default()
        }
    }

    pub fn num_nodes(&self) -> usize {
        self.n
    }

    pub fn requirements(&self) -> &[Requirement] {
        &self.requirements
    }

    pub fn links(&self) -> &[ContingentLink] {
        &self.links
    }

    fn check_node(&self, node: usize) -> Result<(), StnuError> {
        if node < self.n {
            Ok(())
        } else {
            Err(StnuError::NoSuchNode { node, n: self.n })
        }
    }

    /// Adds the requirement `to − from ∈ [lb, ub]`; returns its index.
    pub fn add_requirement(
        &mut self,
        from: usize,
        to: usize,
        lb: Time,
        ub: Time,
    ) -> Result<usize, StnuError> {
        self.check_node(from)?;
        self.check_node(to)?;
        self.requirements.push(Requirement {
            from,
            to,
            lb: lb.max(-INF),
            ub: ub.min(INF),
        });
        Ok(self.requirements.len() - 1)
    }

    /// Adds the contingent link `contingent − activation ∈ [lower, upper]`; returns its index.
    pub fn add_contingent(
        &mut self,
        activation: usize,
        contingent: usize,
        lower: Time,
        upper: Time,
    ) -> Result<usize, StnuError> {
        self.check_node(activation)?;
        self.check_node(contingent)?;
        if activation == contingent {
            return Err(StnuError::SelfLink { node: contingent });
        }
        if lower < 0 || lower > upper || upper >= INF {
            return Err(StnuError::BadBounds { lower, upper });
        }
        if self.links.iter().any(|k| k.contingent == contingent) {
            return Err(StnuError::TwiceContingent { node: contingent });
        }
        self.links.push(ContingentLink {
            activation,
            contingent,
            lower,
            upper,
        });
        Ok(self.links.len() - 1)
    }

    /// Whether the network is dynamically controllable (Morris 2014); its dispatchable form if it is.
    pub fn check_dc(&self) -> Result<Dispatchable, NotDc> {
        super::dc::check(self)
    }

    /// The waits (and derived edges) of every part of the network the check gets through, and the first
    /// conflict if it is not DC: what an executive can still honour when the world may break the plan.
    pub fn dispatch_best_effort(&self) -> (Dispatchable, Option<NotDc>) {
        super::dc::best_effort(self)
    }
}
