//! `mavtempo plan DOMAIN PROBLEM [--json] [--dot]` (PDDL files: [`super::plan_pddl`]): plans, checks the plan with the independent checker and
//! prints it (text, JSON `Solution`, or a Graphviz graph of the partial order like seed 1 Fig. 5).

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use clap::Args;

use crate::cli::out::{out, outln};
use crate::lang;
use crate::plan::solution::{Consumer, Establisher, PlanTerm, Solution};
use crate::plan::validate::validate;
use crate::planner::{solve_dc, Budget, DcMode};

#[derive(Args, Debug)]
pub struct PlanArgs {
    /// The domain file (e.g. domains/rover/rover.ixt).
    pub domain: PathBuf,
    /// The problem file (e.g. domains/rover/problems/fig2.ixt).
    pub problem: PathBuf,
    /// Print the plan as JSON (the `Solution` type).
    #[arg(long, conflicts_with = "dot")]
    pub json: bool,
    /// Print a Graphviz graph of the partial order.
    #[arg(long)]
    pub dot: bool,
    /// Maximum number of planning steps.
    #[arg(long, default_value_t = 200_000)]
    pub max_steps: u64,
    /// Only a dynamically controllable plan (the durations the domain marks `contingent` decided by the
    /// world; docs/stnu.md): without it, a plan that is not DC is printed with the reason.
    #[arg(long)]
    pub require_dc: bool,
    /// PDDL problems: also write the plan in the IPC format to FILE (`-`: stdout).
    #[arg(long, value_name = "FILE")]
    pub pddl_out: Option<PathBuf>,
}

pub fn run(args: PlanArgs) -> ExitCode {
    if crate::pddl::is_pddl(&args.domain) || crate::pddl::is_pddl(&args.problem) {
        return super::plan_pddl::run(&args);
    }
    if args.pddl_out.is_some() {
        crate::cli::out::errln!("--pddl-out is for PDDL problems (DOMAIN.pddl PROBLEM.pddl)");
        return ExitCode::FAILURE;
    }
    let domain = match lang::load_domain(&args.domain) {
        Ok(d) => Arc::new(d),
        Err(e) => {
            crate::cli::out::err!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let problem = match lang::load_problem(&args.problem, &domain) {
        Ok(p) => Arc::new(p),
        Err(e) => {
            crate::cli::out::err!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let dc = if args.require_dc {
        DcMode::Require
    } else {
        DcMode::Report
    };
    let planned = match solve_dc(
        domain.clone(),
        problem.clone(),
        Budget::steps(args.max_steps),
        dc,
    ) {
        Ok(p) => p,
        Err(e) => {
            crate::cli::out::errln!("no plan for {}: {e}", problem.name);
            return ExitCode::FAILURE;
        }
    };
    let sol = planned.plan.to_solution(&HashMap::new());
    let checked = validate(&domain, &problem, &sol);
    if args.json {
        let printed = super::json_out::print_json_pretty("cannot serialise the plan", &sol);
        if printed != ExitCode::SUCCESS {
            return printed;
        }
    } else if args.dot {
        out!("{}", dot(&sol, &problem));
    } else {
        out!("{}", text(&sol, &problem));
        outln!(
            "{} actions, {} causal links, {} planning steps, {} backtracks",
            sol.actions.len(),
            sol.causal_links.len(),
            planned.steps,
            planned.backtracks
        );
        match &planned.not_controllable {
            None => outln!("dynamically controllable"),
            Some(why) => outln!("{why}"),
        }
    }
    match checked {
        Ok(_) => {
            if !args.json && !args.dot {
                outln!("checker: plan accepted");
            }
            ExitCode::SUCCESS
        }
        Err(r) => {
            crate::cli::out::errln!("checker: plan REJECTED: {r}");
            ExitCode::FAILURE
        }
    }
}

fn term(t: &PlanTerm, sol: &Solution, p: &crate::model::Problem) -> String {
    match t {
        PlanTerm::Obj(o) => p.object_name(*o).to_string(),
        PlanTerm::Unknown => "+oo".into(),
        PlanTerm::Var(v) => sol.variables.get(v.index()).map_or("?".into(), |v| {
            let d: Vec<&str> = v.domain.iter().map(|&o| p.object_name(o)).collect();
            format!("{}{{{}}}", v.name, d.join(","))
        }),
    }
}

fn window(sol: &Solution, tp: crate::plan::solution::PlanTp) -> String {
    let t = sol.timepoint(tp);
    let f = |x: Option<i64>, inf: &str| {
        x.map_or(inf.to_string(), |v| format!("{:.3}", v as f64 / 1000.0))
    };
    t.map_or("?".into(), |t| {
        format!("[{}, {}]", f(t.lb, "-oo"), f(t.ub, "+oo"))
    })
}

/// The readable listing: actions by earliest start, with parameters and windows (seconds), links, goals.
fn text(sol: &Solution, p: &crate::model::Problem) -> String {
    let mut out = format!("plan for {} ({}):\n", sol.problem, sol.domain);
    let mut acts: Vec<_> = sol.actions.iter().collect();
    let lb = |a: &crate::plan::solution::PlanAction| {
        a.timepoints
            .first()
            .and_then(|&t| sol.timepoint(t))
            .and_then(|t| t.lb)
            .unwrap_or(0)
    };
    acts.sort_by_key(|a| (lb(a), a.id));
    for a in acts {
        let args: Vec<String> = a.args.iter().map(|t| term(t, sol, p)).collect();
        let (st, et) = (a.timepoints.first(), a.timepoints.last());
        out += &format!(
            "  {:>4} {}({})  start {}  end {}\n",
            a.name,
            a.task_name,
            args.join(", "),
            st.map_or("?".into(), |&t| window(sol, t)),
            et.map_or("?".into(), |&t| window(sol, t)),
        );
    }
    out += "causal links:\n";
    for l in &sol.causal_links {
        out += &format!(
            "  {} -> {}\n",
            establisher(l.establisher, sol),
            consumer(l.consumer, sol)
        );
    }
    for g in sol.unachieved() {
        out += &format!(
            "unachieved goal {}: {}\n",
            g.name,
            g.reason.as_deref().unwrap_or("?")
        );
    }
    out
}

fn action_name(sol: &Solution, a: crate::plan::solution::PlanActionId) -> String {
    sol.action(a)
        .map_or("?".into(), |x| format!("{}:{}", x.name, x.task_name))
}

fn establisher(e: Establisher, sol: &Solution) -> String {
    match e {
        Establisher::Initial => "initial".into(),
        Establisher::Timed { index } => format!("timed{index}"),
        Establisher::Event { action, .. } => action_name(sol, action),
    }
}

fn consumer(c: Consumer, sol: &Solution) -> String {
    match c {
        Consumer::Hold { action, .. } | Consumer::EventFrom { action, .. } => {
            action_name(sol, action)
        }
        Consumer::Goal { goal } => sol
            .goals
            .iter()
            .find(|g| g.goal == goal)
            .map_or("goal ?".into(), |g| format!("goal {}", g.name)),
    }
}

/// Graphviz: one node per action and goal, an edge per causal link (labelled with its proposition) — the
/// partial order of seed 1 Fig. 5.
pub(super) fn dot(sol: &Solution, p: &crate::model::Problem) -> String {
    let mut out = String::from(
        "digraph plan {\n  rankdir=LR;\n  node [shape=box];\n  initial [shape=ellipse];\n",
    );
    for a in &sol.actions {
        let args: Vec<String> = a.args.iter().take(4).map(|t| term(t, sol, p)).collect();
        out += &format!(
            "  {} [label=\"{}({})\"];\n",
            a.name,
            a.task_name,
            args.join(", ")
        );
    }
    for g in &sol.goals {
        out += &format!(
            "  goal_{} [shape=ellipse, label=\"{}\"];\n",
            g.goal.0, g.name
        );
    }
    for l in &sol.causal_links {
        let from = match l.establisher {
            Establisher::Initial => "initial".to_string(),
            Establisher::Timed { index } => {
                out += &format!("  timed{index} [shape=ellipse];\n");
                format!("timed{index}")
            }
            Establisher::Event { action, .. } => format!("a{}", action.0),
        };
        let to = match l.consumer {
            Consumer::Hold { action, .. } | Consumer::EventFrom { action, .. } => {
                format!("a{}", action.0)
            }
            Consumer::Goal { goal } => format!("goal_{}", goal.0),
        };
        if from == to {
            continue;
        }
        let value = term(&l.value, sol, p);
        out += &format!("  {from} -> {to} [label=\"{value}\"];\n");
    }
    out += "}\n";
    out
}
