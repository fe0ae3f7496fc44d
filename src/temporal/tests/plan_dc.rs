//! The shipped problems' plans as STNUs: contingent links from the domains' `contingent` durations, and
//! the DC check at solution.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use mavtempo_temporal::lang::load_problem_and_domain;
use mavtempo_temporal::planner::{solve, Budget};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(path)
}

#[test]
fn tmp_explore() {
    for p in [
        "domains/rover/problems/fig2.ixt",
        "domains/rover/problems/dala.ixt",
        "domains/auv/problems/vents.ixt",
        "domains/shopping/problems/day.ixt",
    ] {
        let (d, pb) = load_problem_and_domain(&repo(p)).unwrap();
        let planned = solve(Arc::new(d), Arc::new(pb), Budget::steps(3_000)).unwrap();
        let plan = planned.plan;
        let net = plan.stnu();
        eprintln!("{p}: {} nodes, {} links, {} reqs", net.stnu.num_nodes(), net.links.len(), net.requirements.len());
        for l in &net.links {
            eprintln!("   {} [{}, {}]", plan.action_text(l.action), l.lower, l.upper);
        }
        match plan.check_dc() {
            Ok(dc) => {
                eprintln!("  DC, {} waits, {} edges", dc.dispatch.waits.len(), dc.dispatch.edges.len());
                for w in &dc.dispatch.waits {
                    eprintln!("    wait {} on {} delay {}", plan.temporal_network().timepoints().find(|t| t.index() == w.node).map(|t| plan.tp_text(t)).unwrap_or_default(), plan.action_text(dc.network.links[w.link].action), w.delay);
                }
            }
            Err(e) => eprintln!("  NOT DC: {e}"),
        }
    }
}
