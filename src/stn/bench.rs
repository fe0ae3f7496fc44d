//! `mavtempo bench stn`: incremental insertion and execution vs Floyd–Warshall on plan-like networks.

/// Figures for one network size.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StnFigures {
    pub n: usize,
    pub constraints: usize,
    pub insert_mean_us: f64,
    pub execute_mean_us: f64,
    pub execute_median_us: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub floyd_warshall_ms: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speedup_vs_floyd_warshall: Option<f64>,
}

/// Measures each size in `sizes`; Floyd–Warshall only for sizes `<= fw_max`.
pub fn run(sizes: &[usize], fw_max: usize) -> Vec<StnFigures> {
    let _ = (sizes, fw_max);
    todo!()
}
