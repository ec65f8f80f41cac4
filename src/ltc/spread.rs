//! Whether another fitting route is no worse than the reference route, judged against the
//! reference's own spread rather than against the judge's bars.
//!
//! A table's per-cell held-out errors are exact integrals with bars of ~1e-5 relative, but
//! the fit itself is not that repeatable: the reference route refitted on another draw of
//! its training samples (the same work, the strata offset) moves hundreds of cells by far
//! more than their bars, both ways, through the warm-start chain down each column. So "no
//! worse than the reference cell by cell within the bars" rejects the reference itself.
//!
//! The rule here: take R draws of the reference route (3 ≤ R ≤ 9). Leaving draw r out,
//! the other R − 1 draws give each cell an envelope, their largest and smallest error.
//! Draw r is exchangeable with them, so four statistics of it against that envelope show
//! what a fresh draw of the reference does: the cells where it lands above the envelope
//! beyond both bars, the sum of those differences, its surplus of cells above over cells
//! below (a fresh draw is as often below the others as above), and its mean error. A
//! candidate is measured against the same R envelopes, each statistic the mean over them.
//! It is **no worse** when each of its four statistics is within the one-sided 95 %
//! prediction bound of the draws' own: mean + t₀.₉₅(R − 1)·s·√(1 + 1/R) over the R draws
//! (Student's t; the mean error's bound on the draws' means). So a fresh draw fails each
//! test about one time in twenty (a route within the reference's spread is called worse
//! about one time in five at most, over the four); a route a little worse almost
//! everywhere fails on its surplus, one much worse in a few cells on its sum.

use crate::integrate::{Figure, Quad};

/// One route's cells above (and below) one envelope, beyond both bars.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Exceed {
    /// Cells where the route's error is above every other draw's by more than the two bars.
    pub above: usize,
    /// The sum over those cells of the difference (as a fraction, not in points).
    pub excess: f64,
    /// The largest such difference.
    pub largest: f64,
    /// Cells where it is below every other draw's by more than the two bars.
    pub below: usize,
}

/// What the rule found: each draw left out against the others, the candidate against the
/// same envelopes, and the verdict.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Verdict {
    /// Cells every draw and the candidate have a figure for.
    pub cells: usize,
    /// Draw r against the other draws, per r.
    pub reference: Vec<Exceed>,
    /// The candidate against the same envelopes (draw r's left out), per r.
    pub candidate: Vec<Exceed>,
    /// Mean over r of the candidate's cells above, of its excess, and of its surplus of
    /// cells above over cells below; its mean error over the counted cells.
    pub candidate_above: f64,
    pub candidate_excess: f64,
    pub candidate_surplus: f64,
    pub candidate_mean: Figure<Quad>,
    /// The mean error over the counted cells of each draw.
    pub reference_means: Vec<Figure<Quad>>,
    /// The one-sided 95 % prediction bounds of the four statistics from the draws'.
    pub above_bound: f64,
    pub excess_bound: f64,
    pub surplus_bound: f64,
    pub mean_bound: f64,
    /// Every statistic of the candidate within its bound (the mean error less its bar).
    pub no_worse: bool,
}

/// Per-cell figures of one route, every cell in one fixed order (`None` where there is no
/// figure, a singular cell).
pub type Cells = [Option<Figure<Quad>>];

/// `x` against the envelope of `others` over the cells `common` (where every route has a
/// figure).
fn exceed(x: &Cells, others: &[&Cells], common: &[usize]) -> Exceed {
    let mut e = Exceed::default();
    let by_value = |a: &Figure<Quad>, b: &Figure<Quad>| a.value.total_cmp(&b.value);
    for &k in common {
        let (Some(xk), Some(os)) = (
            x[k],
            others.iter().map(|o| o[k]).collect::<Option<Vec<_>>>(),
        ) else {
            continue;
        };
        let (Some(hi), Some(lo)) = (
            os.iter().copied().max_by(by_value),
            os.iter().copied().min_by(by_value),
        ) else {
            continue;
        };
        let up = xk.value - hi.value;
        if up > xk.error + hi.error {
            e.above += 1;
            e.excess += up;
            e.largest = e.largest.max(up);
        }
        if lo.value - xk.value > xk.error + lo.error {
            e.below += 1;
        }
    }
    e
}

/// One-sided 95 % quantiles of Student's t for ν = 1 … 8 degrees of freedom.
const T95: [f64; 8] = [6.314, 2.920, 2.353, 2.132, 2.015, 1.943, 1.895, 1.860];

/// The one-sided 95 % prediction bound of one more value of the sample `x` (3 ≤ len ≤ 9).
fn bound(x: &[f64]) -> f64 {
    let r = x.len() as f64;
    let m = x.iter().sum::<f64>() / r;
    let sd = (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (r - 1.0)).sqrt();
    m + T95[x.len() - 2] * sd * (1.0 + 1.0 / r).sqrt()
}

/// The rule over the reference's `draws` (each every cell, the same order and length) and
/// a `candidate`. Only cells where every draw and the candidate have a figure count.
/// `None` for fewer than 3 or more than 9 draws, or unequal lengths.
pub fn judge(draws: &[&Cells], candidate: &Cells) -> Option<Verdict> {
    let n = candidate.len();
    if !(3..=9).contains(&draws.len()) || draws.iter().any(|d| d.len() != n) {
        return None;
    }
    let common: Vec<usize> = (0..n)
        .filter(|&k| candidate[k].is_some() && draws.iter().all(|d| d[k].is_some()))
        .collect();
    let (mut reference, mut against) = (Vec::new(), Vec::new());
    for r in 0..draws.len() {
        let others: Vec<&Cells> = (0..draws.len())
            .filter(|&s| s != r)
            .map(|s| draws[s])
            .collect();
        reference.push(exceed(draws[r], &others, &common));
        against.push(exceed(candidate, &others, &common));
    }
    let mean = |x: &Cells| {
        let v: Vec<Figure<Quad>> = common.iter().filter_map(|&k| x[k]).collect();
        Figure::mean_bounded(&v)
    };
    let stats = |e: &Exceed| [e.above as f64, e.excess, e.above as f64 - e.below as f64];
    let avg = |k: usize| against.iter().map(|e| stats(e)[k]).sum::<f64>() / against.len() as f64;
    let bound_of = |k: usize| bound(&reference.iter().map(|e| stats(e)[k]).collect::<Vec<_>>());
    let reference_means: Vec<Figure<Quad>> = draws.iter().map(|d| mean(d)).collect();
    let candidate_mean = mean(candidate);
    let mean_bound = bound(&reference_means.iter().map(|m| m.value).collect::<Vec<_>>());
    let (c, b) = (
        [avg(0), avg(1), avg(2)],
        [bound_of(0), bound_of(1), bound_of(2)],
    );
    Some(Verdict {
        cells: common.len(),
        no_worse: c.iter().zip(&b).all(|(c, b)| c <= b)
            && candidate_mean.value - candidate_mean.error <= mean_bound,
        reference,
        candidate: against,
        candidate_above: c[0],
        candidate_excess: c[1],
        candidate_surplus: c[2],
        candidate_mean,
        reference_means,
        above_bound: b[0],
        excess_bound: b[1],
        surplus_bound: b[2],
        mean_bound,
    })
}

/// One cheaper route of a work study, as factors on the published route: samples per
/// axis (rounded, at least 2) and the Nelder–Mead cap (rounded, at least 1), and what its
/// trials are measured on.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Route {
    pub samples: f64,
    pub max_iters: f64,
    /// "moving" (the reference fitter's: half of the samples drawn from each trial LTC),
    /// "fixed" (drawn once per stage, `ltc::fit::Method::FixedNodes`), "fixed-all" (every
    /// stage of a table's fit, `Method::FixedNodesAll`).
    #[serde(default)]
    pub nodes: crate::ltc::fit::Nodes,
}

impl Route {
    /// The route's (samples, cap) from the published (samples, cap).
    pub fn of(&self, samples: usize, max_iters: u64) -> (usize, u64) {
        (
            ((samples as f64 * self.samples).round() as usize).max(2),
            ((max_iters as f64 * self.max_iters).round() as u64).max(1),
        )
    }
}

/// A work study's plan as its spec gives it: the reference's other training draws (strata
/// offsets in [0, 1), distinct, none the published `TRAIN_OFFSET`; 2 to 8 of them, so the
/// rule sees 3 to 9 draws) and 1 to 12 routes, each factor in range.
pub fn check_plan(draws: &[f64], routes: &[Route]) -> std::result::Result<(), String> {
    use crate::fit::spec::within;
    use crate::ltc::fit::TRAIN_OFFSET;
    within("draws (its length)", draws.len(), 2, 8)?;
    within("routes (its length)", routes.len(), 1, 12)?;
    for (k, &o) in draws.iter().enumerate() {
        if !(0.0..1.0).contains(&o) || o == TRAIN_OFFSET || draws[..k].contains(&o) {
            return Err(format!(
                "draws = {draws:?}: each offset in [0, 1), distinct, and not the published {TRAIN_OFFSET}"
            ));
        }
    }
    for r in routes {
        within("samples (a factor)", r.samples, 0.05, 1.0)?;
        within("max_iters (a factor)", r.max_iters, 0.01, 1.0)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cells(v: &[f64], bar: f64) -> Vec<Option<Figure<Quad>>> {
        v.iter().map(|&x| Some(Figure::new(x, bar))).collect()
    }

    /// A deterministic scatter in [0, 1): the draws' and candidates' noise.
    fn noise(seed: u64, n: usize) -> Vec<f64> {
        use rand::{Rng, SeedableRng};
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        (0..n).map(|_| r.random::<f64>()).collect()
    }

    fn draws_and(base: &[f64], seeds: &[u64], scale: f64) -> Vec<Vec<Option<Figure<Quad>>>> {
        seeds
            .iter()
            .map(|&s| {
                let z = noise(s, base.len());
                let v: Vec<f64> = base.iter().zip(&z).map(|(b, z)| b + scale * z).collect();
                cells(&v, 1e-6)
            })
            .collect()
    }

    /// Shifted copies of a fresh draw, by `shift` in every cell.
    fn shifted(base: &[f64], seed: u64, shift: f64) -> Vec<Option<Figure<Quad>>> {
        draws_and(base, &[seed], 0.01)[0]
            .iter()
            .map(|f| f.map(|f| Figure::new(f.value + shift, f.error)))
            .collect()
    }

    /// Over 200 sets of four draws: a fifth draw of the same scatter is called no worse
    /// in at least 80 % of them (the rule's four 5 % bounds); the same shifted up by a
    /// fifth of the scatter in every cell is called worse in at least 95 %; shifted down,
    /// never.
    #[test]
    fn fresh_draws_pass_and_shifted_ones_do_not() {
        let base: Vec<f64> = (0..2000).map(|k| 0.05 + 1e-5 * k as f64).collect();
        let (mut fresh, mut up, mut down) = (0, 0, 0);
        for set in 0..200u64 {
            let seeds: Vec<u64> = (0..5).map(|k| 1000 * set + k).collect();
            let d = draws_and(&base, &seeds[..4], 0.01);
            let refs: Vec<&Cells> = d.iter().map(|x| x.as_slice()).collect();
            let pass = |c: &Cells| judge(&refs, c).unwrap().no_worse as u32;
            fresh += pass(&shifted(&base, seeds[4], 0.0));
            up += pass(&shifted(&base, seeds[4], 0.002));
            down += pass(&shifted(&base, seeds[4], -0.002));
        }
        assert!(fresh >= 160, "a fresh draw passed {fresh} of 200");
        assert!(
            up <= 10,
            "a draw worse by 0.002 everywhere passed {up} of 200"
        );
        assert_eq!(down, 200);
    }

    /// Differences inside the two bars count neither way; a few cells far worse fail the
    /// sum even when the count passes.
    #[test]
    fn bars_and_excess() {
        let a = cells(&[0.1, 0.1, 0.1, 0.1, 0.1], 1e-3);
        let b = cells(&[0.1005, 0.1, 0.1, 0.1, 0.1], 1e-3);
        let c = cells(&[0.1, 0.1005, 0.1, 0.1, 0.1], 1e-3);
        let refs: Vec<&Cells> = vec![&a, &b, &c];
        let v = judge(&refs, &cells(&[0.1019, 0.099, 0.1, 0.1, 0.1], 1e-3)).unwrap();
        assert_eq!(v.reference.iter().map(|e| e.above).sum::<usize>(), 0);
        assert_eq!(v.candidate_above, 0.0);
        assert!(v.no_worse, "{v:?}");
        let far = cells(&[0.2, 0.1, 0.1, 0.1, 0.1], 1e-3);
        let v = judge(&refs, &far).unwrap();
        assert!(!v.no_worse, "{v:?}");
        assert!((v.candidate.iter().map(|e| e.largest).fold(0.0, f64::max) - 0.1).abs() < 1e-12);
    }

    /// Missing cells are left out of every comparison; too few draws or unequal lengths
    /// give no verdict.
    #[test]
    fn missing_cells_and_bad_shapes() {
        let a = cells(&[0.1, 0.2, 0.3], 0.0);
        let mut b = cells(&[0.11, 0.2, 0.3], 0.0);
        b[1] = None;
        let d = cells(&[0.12, 0.25, 0.3], 0.0);
        let c = cells(&[0.1, 0.9, 0.3], 0.0);
        let v = judge(&[&a, &b, &d], &c).unwrap();
        assert_eq!(v.cells, 2);
        assert!(v.no_worse, "{v:?}");
        assert!(judge(&[&a, &d], &c).is_none());
        assert!(judge(&[&a, &b, &d], &c[..1]).is_none());
    }
}
