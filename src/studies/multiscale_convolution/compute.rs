//! The overall-α study's computation: the targets on a grid, the per-pair fits under every
//! metric, the refits and their error statistics.

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::multiscale::alpha_me::{held_out_alphas, training_alphas};
use crate::multiscale::overall::{
    alpha_moment, corrected, eq7, fit_corrected, fit_improved, fit_pair_with, improved, refit_eq7,
    sum_of_squares, vmf, LightScan, Metric, PairFit,
};

#[derive(Clone, Copy, Debug, serde::Serialize)]
pub(super) struct Stats {
    pub max_rel: f64,
    pub rms_rel: f64,
    pub worst: (f64, f64),
}

pub(super) fn stats(pts: &[(f64, f64, f64)], f: &dyn Fn(f64, f64) -> f64) -> Stats {
    let mut s = Stats {
        max_rel: 0.0,
        rms_rel: 0.0,
        worst: (0.0, 0.0),
    };
    let mut ss = 0.0;
    for &(x, y, a) in pts {
        let e = ((f(x, y) - a) / a).abs();
        let e = if e.is_nan() { f64::INFINITY } else { e };
        ss += e * e;
        if e > s.max_rel {
            s.max_rel = e;
            s.worst = (x, y);
        }
    }
    s.rms_rel = (ss / pts.len() as f64).sqrt();
    s
}

pub(super) fn grid(axis: &[f64]) -> Vec<(f64, f64)> {
    axis.iter()
        .flat_map(|&x| axis.iter().map(move |&y| (x, y)))
        .collect()
}

pub(super) fn metric_value(p: &PairFit, m: Metric) -> f64 {
    match m {
        Metric::MomentUnclipped => p.moment_unclipped,
        Metric::MomentClipped => p.moment_clipped,
        Metric::L2 => p.l2,
        Metric::Caps => p.caps,
    }
}

/// A per-metric refit: the metric, its coefficients, in-sample and held-out stats.
pub(super) type Row = (Metric, Vec<f64>, Stats, Stats);

/// Everything the study computes; the report and the plots only read it.
pub(super) struct Computed {
    pub g: super::params::Params,
    pub lo: f64,
    pub hi: f64,
    pub held_axis: Vec<f64>,
    pub held: Vec<(f64, f64, f64)>,
    pub held_clamp: Vec<(f64, f64, f64)>,
    pub c7: Vec<f64>,
    pub sse7: f64,
    pub sse_paper: f64,
    pub ci: Vec<f64>,
    pub c_me: crate::multiscale::alpha_me::OursFit,
    pub ours: Stats,
    pub m: usize,
    pub fits: Vec<PairFit>,
    pub held_fits: Vec<PairFit>,
    pub per_metric_ours: Vec<Row>,
    pub per_metric_corr: Vec<Row>,
    pub passed_moment: bool,
}

impl Computed {
    /// Ours: the product identity through the α_me fit, α = α_me-fit(1 − ρ_me ρ_mi).
    pub fn product(&self, x: f64, y: f64) -> f64 {
        let (ym, yi) = (
            crate::multiscale::mrl::mrl_pair(y).1,
            crate::multiscale::mrl::mrl_pair(x).1,
        );
        self.c_me.eval(ym + yi - ym * yi)
    }
}

/// Every model, named.
pub(super) type Model<'a> = (&'static str, Box<dyn Fn(f64, f64) -> f64 + 'a>);

/// The models judged against the targets.
pub(super) fn models(c: &Computed) -> Vec<Model<'_>> {
    let c7 = &c.c7;
    let ci = &c.ci;
    let eq7r = move |x: f64, y: f64| c7[0] * x * x + c7[1] * x + c7[2] * y + c7[3] * x * y;
    vec![
        ("paper Eq 7", Box::new(eq7)),
        ("Eq 7 form, refitted (linear LS)", Box::new(eq7r)),
        ("α² = α_mi² + α_me²", Box::new(sum_of_squares)),
        ("vMF α² + 2/κ", Box::new(|x, y| vmf(x, y, 2.0))),
        ("vMF α² + 1/κ", Box::new(|x, y| vmf(x, y, 1.0))),
        ("vMF α² + 1/(2κ)", Box::new(|x, y| vmf(x, y, 0.5))),
        (
            "polynomial α² = α_mi² + α_me² + α_mi α_me P (6 coefficients, both limits exact)",
            Box::new(move |x, y| improved(ci, x, y)),
        ),
        (
            "ours: α_me-fit(1 − ρ(α_me)ρ(α_mi)) (product identity)",
            Box::new(move |x, y| c.product(x, y)),
        ),
    ]
}

/// The dense closed-form targets, the refits, and the per-point fits under every metric.
pub(super) fn compute(
    spec: &FitSpec,
    g: super::params::Params,
    all: &[FitSpec],
    preset: Preset,
) -> Result<Computed> {
    let (lo, hi) = (g.alpha_min, g.alpha_max);
    // dense closed-form target (unclipped moment metric)
    let train_axis = training_alphas(g.dense_points, lo, hi);
    let held_axis = held_out_alphas(g.dense_points - 1, lo, hi);
    let target = |pts: Vec<(f64, f64)>| -> Result<Vec<(f64, f64, f64)>> {
        pts.into_iter()
            .map(|(x, y)| Ok((x, y, alpha_moment(x, y)?)))
            .collect()
    };
    let train = target(grid(&train_axis))?;
    let held = target(grid(&held_axis))?;
    let (c7, sse7) = refit_eq7(&train)?;
    let sse_paper: f64 = train.iter().map(|&(x, y, a)| (eq7(x, y) - a).powi(2)).sum();
    let ci = fit_improved(&train)?;
    // ours: the product identity through the α_me fit of fits/multiscale-alpha-me.toml,
    // α = α_me-fit(1 − ρ_me ρ_mi) — both limits hold up to that fit's error
    let me_spec = all
        .iter()
        .find(|s| s.name == "multiscale-alpha-me")
        .cloned()
        .ok_or_else(|| {
            Error::InvalidArgument(format!(
                "{} needs the multiscale-alpha-me spec in the same fits directory",
                spec.name
            ))
        })?;
    let me = me_spec.params::<crate::multiscale::alpha_me::Settings>(preset)?;
    let c_me = me.fit()?;
    let product = |x: f64, y: f64| {
        let (ym, yi) = (
            crate::multiscale::mrl::mrl_pair(y).1,
            crate::multiscale::mrl::mrl_pair(x).1,
        );
        c_me.eval(ym + yi - ym * yi)
    };
    // judge ours on the α_me fit's domain (now [1e-4, 1e2]: every held-out target here)
    let held_clamp: Vec<(f64, f64, f64)> = held
        .iter()
        .copied()
        .filter(|p| p.2 <= me.alpha_max)
        .collect();
    let ours = stats(&held_clamp, &product);
    // per-point fits under every metric (expensive)
    let m = g.metric_points;
    let axis = training_alphas(m, lo, hi);
    let pairs = grid(&axis);
    let pb = crate::progress::Progress::new(
        "convolution fits",
        (pairs.len() + (m - 1) * (m - 1)) as u64,
    );
    // memoised (cached, shardable; crate::memo): each pair's fit is a pure function of it;
    // the caps metric's scan is the same for every pair: computed once (41 one-LTC light
    // sets, a fraction of one pair's fit), before the pairs
    let scan = LightScan::compute();
    let fit_all = |label: &str, pts: &[(f64, f64)]| {
        crate::memo::map(label, pts.len(), |k| {
            let r = fit_pair_with(&scan, pts[k].0, pts[k].1);
            pb.inc(1);
            r
        })
    };
    let fits = fit_all("per-pair metric fits", &pairs)?;
    // held-out metric points: the (m−1)² grid half a step off
    let held_metric_axis = held_out_alphas(m - 1, lo, hi);
    let held_fits = fit_all("held-out per-pair metric fits", &grid(&held_metric_axis))?;
    pb.finish();
    let passed_moment = ours.max_rel <= spec.tolerance.max_rel;

    type Row = (Metric, Vec<f64>, Stats, Stats);
    let mut per_metric_ours: Vec<Row> = Vec::new();
    let mut per_metric_corr: Vec<Row> = Vec::new();
    for k in Metric::ALL {
        let pts: Vec<(f64, f64, f64)> = fits
            .iter()
            .map(|p| (p.alpha_mi, p.alpha_me, metric_value(p, k)))
            .collect();
        let hpts: Vec<(f64, f64, f64)> = held_fits
            .iter()
            .map(|p| (p.alpha_mi, p.alpha_me, metric_value(p, k)))
            .collect();
        let c = fit_improved(&pts)?;
        let (si, sh) = (
            stats(&pts, &|x, y| improved(&c, x, y)),
            stats(&hpts, &|x, y| improved(&c, x, y)),
        );
        per_metric_ours.push((k, c, si, sh));
        let c = fit_corrected(&pts)?;
        let (si, sh) = (
            stats(&pts, &|x, y| corrected(&c, x, y)),
            stats(&hpts, &|x, y| corrected(&c, x, y)),
        );
        per_metric_corr.push((k, c, si, sh));
    }
    Ok(Computed {
        g,
        lo,
        hi,
        held_axis,
        held,
        held_clamp,
        c7: c7.to_vec(),
        sse7,
        sse_paper,
        ci: ci.to_vec(),
        c_me,
        ours,
        m,
        fits,
        held_fits,
        per_metric_ours,
        per_metric_corr,
        passed_moment,
    })
}
