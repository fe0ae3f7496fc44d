//! `mavtempo bench stn`: incremental insertion and execution vs Floyd–Warshall on plan-like networks.

use std::time::Instant;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::stn::{floyd_warshall, Stn, Time, Timepoint, INF};

/// A plan-like network: actions (start, end) with duration intervals, precedences and bounded links to
/// earlier actions on parallel branches, deadlines and release dates. `schedule` is a solution (the network is
/// consistent by construction); timepoint `i` of `schedule` is the `i`-th added timepoint (origin excluded).
#[derive(Clone, Debug)]
pub struct PlanLike {
    pub timepoints: usize,
    /// `(from, to, lb, ub)` over timepoint indices, 0 being the origin.
    pub constraints: Vec<(u32, u32, Time, Time)>,
    pub schedule: Vec<Time>,
}

/// About `n` timepoints (n/2 actions) and 4 constraints per timepoint, from `seed`.
pub fn plan_like(n: usize, seed: u64) -> PlanLike {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let actions = (n / 2).max(1);
    // Action i has start 2i+1 and end 2i+2; times in milliseconds.
    let mut time: Vec<Time> = vec![0];
    let mut cs = Vec::new();
    for i in 0..actions {
        let (st, et) = (2 * i as u32 + 1, 2 * i as u32 + 2);
        let window = i.min(24);
        let preds: Vec<usize> = (0..window.min(3))
            .map(|_| i - 1 - rng.gen_range(0..window))
            .collect();
        let ready = preds.iter().map(|&j| time[2 * j + 2]).max().unwrap_or(0);
        let s = ready + rng.gen_range(1..5_000);
        let d = rng.gen_range(1_000..20_000);
        time.push(s);
        time.push(s + d);
        cs.push((st, et, d - rng.gen_range(0..d / 2), d + rng.gen_range(0..d)));
        for &j in &preds {
            cs.push((2 * j as u32 + 2, st, 1, INF));
        }
        if let Some(&j) = preds.first() {
            // A bounded link: start within some time after a predecessor's end.
            let gap = s - time[2 * j + 2];
            cs.push((2 * j as u32 + 2, st, 1, gap + rng.gen_range(0..10_000)));
        }
        if window > 0 {
            let j = i - 1 - rng.gen_range(0..window);
            let delay = s + d - time[2 * j + 2];
            cs.push((2 * j as u32 + 2, et, delay - rng.gen_range(0..5_000), INF));
            let k = i - 1 - rng.gen_range(0..window);
            let delay = s - time[2 * k + 1];
            cs.push((
                2 * k as u32 + 1,
                st,
                delay - rng.gen_range(0..5_000),
                delay + rng.gen_range(0..20_000),
            ));
        }
        cs.push((0, et, 0, s + d + rng.gen_range(0..60_000)));
        if rng.gen_bool(0.5) {
            cs.push((0, st, (s - rng.gen_range(0..30_000)).max(0), INF));
        }
    }
    PlanLike {
        timepoints: 2 * actions,
        constraints: cs,
        schedule: time[1..].to_vec(),
    }
}

impl PlanLike {
    /// Builds the network; `None` only if the generator broke its own invariant.
    pub fn build(&self) -> Option<Stn> {
        let (mut stn, tp) = self.timepoints();
        for &(f, t, lb, ub) in &self.constraints {
            stn.add_constraint(tp[f as usize], tp[t as usize], lb, ub)
                .ok()?;
        }
        Some(stn)
    }

    /// A network with the timepoints alone, and them by their number here (0 is the origin).
    fn timepoints(&self) -> (Stn, Vec<Timepoint>) {
        let mut stn = Stn::new();
        let mut tp = vec![stn.origin()];
        tp.extend((0..self.timepoints).map(|_| stn.add_timepoint()));
        (stn, tp)
    }
}

/// Figures for one network size.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StnFigures {
    pub n: usize,
    pub constraints: usize,
    /// Mean time of one incremental `add_constraint` while building the network.
    pub insert_mean_us: f64,
    /// Mean and median time of one `execute`, every timepoint executed in schedule order.
    pub execute_mean_us: f64,
    pub execute_median_us: f64,
    /// One Floyd–Warshall solve of the built network.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub floyd_warshall_ms: Option<f64>,
    /// `floyd_warshall_ms / insert_mean_us`: one recomputation vs one incremental insertion.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speedup_vs_floyd_warshall: Option<f64>,
}

/// Why a benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum StnBenchError {
    #[error("generated network of {0} timepoints is inconsistent (generator bug)")]
    Inconsistent(usize),
}

/// Measures each size in `sizes` (timepoints); Floyd–Warshall only for sizes `<= fw_max`.
pub fn run(sizes: &[usize], fw_max: usize) -> Result<Vec<StnFigures>, StnBenchError> {
    sizes.iter().map(|&n| measure(n, fw_max)).collect()
}

fn measure(n: usize, fw_max: usize) -> Result<StnFigures, StnBenchError> {
    let plan = plan_like(n, 42 + n as u64);
    let (mut stn, tp) = plan.timepoints();
    let start = Instant::now();
    for &(f, t, lb, ub) in &plan.constraints {
        stn.add_constraint(tp[f as usize], tp[t as usize], lb, ub)
            .map_err(|_| StnBenchError::Inconsistent(n))?;
    }
    let insert_mean_us = micros(start) / plan.constraints.len() as f64;

    let floyd_warshall_ms = (n <= fw_max).then(|| {
        let start = Instant::now();
        let apsp = floyd_warshall::solve(&stn);
        std::hint::black_box(apsp);
        micros(start) / 1_000.0
    });

    // Execute in schedule order, each at its scheduled time clamped into its current bounds.
    let mut order: Vec<usize> = (0..plan.timepoints).collect();
    order.sort_by_key(|&i| plan.schedule[i]);
    let mut times = Vec::with_capacity(order.len());
    for i in order {
        let t = tp[i + 1];
        let at = plan.schedule[i].clamp(stn.lb(t), stn.ub(t));
        let start = Instant::now();
        stn.execute(t, at)
            .map_err(|_| StnBenchError::Inconsistent(n))?;
        times.push(micros(start));
    }
    let execute_mean_us = times.iter().sum::<f64>() / times.len().max(1) as f64;
    times.sort_by(f64::total_cmp);
    let execute_median_us = times.get(times.len() / 2).copied().unwrap_or(0.0);

    Ok(StnFigures {
        n,
        constraints: plan.constraints.len(),
        insert_mean_us,
        execute_mean_us,
        execute_median_us,
        speedup_vs_floyd_warshall: floyd_warshall_ms.map(|ms| ms * 1_000.0 / insert_mean_us),
        floyd_warshall_ms,
    })
}

fn micros(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e6
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bench_reports_floyd_warshall_only_up_to_its_limit() {
        let figures = run(&[40, 60], 40).unwrap();
        assert_eq!(
            figures.iter().map(|f| f.n).collect::<Vec<_>>(),
            vec![40, 60]
        );
        assert!(
            figures[0].floyd_warshall_ms.is_some()
                && figures[0].speedup_vs_floyd_warshall.is_some()
        );
        assert!(
            figures[1].floyd_warshall_ms.is_none()
                && figures[1].speedup_vs_floyd_warshall.is_none()
        );
        assert!(figures.iter().all(|f| f.constraints >= 3 * f.n / 2));
    }
}
