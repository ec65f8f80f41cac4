//! The anisotropic table's summary: the fitted cells and the cases between them against
//! the engines' isotropic substitutes, by anisotropy, and the error predicted for other
//! table sizes from the design study.

use super::compute::{Between, Case, Fitted, Plan};
use super::design::{Design, Penalty};

pub use crate::results::ltc_aniso::{Bin, MeanMax, Prediction, Summary};

fn mean_max(v: impl Iterator<Item = f64>) -> MeanMax {
    let v: Vec<f64> = v.filter(|x| x.is_finite()).collect();
    MeanMax {
        mean: crate::integrate::Figure::mean_of(&v),
        max: v.iter().cloned().fold(0.0, f64::max),
        count: v.len(),
    }
}

const BINS: [(&str, f64, f64); 5] = [
    ("α_max/α_min ≤ 1.5", 0.0, 1.5),
    ("1.5 – 3", 1.5, 3.0),
    ("3 – 10", 3.0, 10.0),
    ("10 – 100", 10.0, 100.0),
    ("> 100", 100.0, f64::INFINITY),
];

fn ratio(c: &Case) -> f64 {
    c.ax.max(c.ay) / c.ax.min(c.ay)
}

/// The interpolation penalty of `dim` at `n` nodes, in squares (e_interp² − e_fit²: the
/// interpolation's share of the squared relative L2): measured where the study has it,
/// else extrapolated from its finest measured spacing by h² in the error, h⁴ in squares
/// (linear interpolation of a smooth function).
fn penalty(d: &Design, dim: usize, n: usize) -> (f64, bool) {
    let rows: Vec<&Penalty> = d.penalties.iter().filter(|p| p.dim == dim).collect();
    if let Some(p) = rows.iter().find(|p| p.n == n) {
        return ((p.interpolated.powi(2) - p.fitted.powi(2)).max(0.0), false);
    }
    let Some(fine) = rows.iter().max_by_key(|p| p.n) else {
        return (f64::NAN, true);
    };
    let base = (fine.interpolated.powi(2) - fine.fitted.powi(2)).max(0.0);
    let h = (fine.n - 1) as f64 / (n.max(2) - 1) as f64;
    (base * h.powi(4), true)
}

pub(super) fn summarise(
    fitted: &[Fitted],
    cases: &[Between],
    design: &Design,
    pl: &Plan,
) -> Summary {
    // the fits' root-mean-square error: squares add for independent perturbations
    let fit_floor =
        (fitted.iter().map(|f| f.err * f.err).sum::<f64>() / fitted.len().max(1) as f64).sqrt();
    let predict = |size: [usize; 4]| {
        let mut ex = false;
        let mut e2 = fit_floor * fit_floor;
        for (dim, &n) in size.iter().enumerate() {
            let (p, x) = penalty(design, dim, n);
            e2 += p;
            ex |= x;
        }
        let e = e2.sqrt();
        let texels = size.iter().product::<usize>();
        Prediction {
            size,
            texels,
            // three RGBA16F texels per cell
            bytes_f16: texels * 3 * 8,
            predicted_mean: e,
            extrapolated: ex,
        }
    };
    let g = pl.grid;
    let sizes = [
        [g.n_r, g.n_r, g.n_phi, g.n_t],
        [8, 8, 8, 8],
        [16, 16, 16, 16],
        [32, 32, 8, 32],
    ];
    Summary {
        fit_rms: fit_floor,
        between_rms: (cases
            .iter()
            .map(|c| c.err_table.powi(2))
            .filter(|x| x.is_finite())
            .sum::<f64>()
            / cases.len().max(1) as f64)
            .sqrt(),
        cells_fitted: fitted.len(),
        cells: Bin {
            label: "table cells".into(),
            ours: mean_max(fitted.iter().map(|f| f.err)),
            iso_geo: mean_max(fitted.iter().map(|f| f.err_iso_geo)),
            iso_max: mean_max(fitted.iter().map(|f| f.err_iso_max)),
        },
        between_table: mean_max(cases.iter().map(|c| c.err_table)),
        between_table_f16: mean_max(cases.iter().map(|c| c.err_table_f16)),
        between_iso_geo: mean_max(cases.iter().map(|c| c.err_iso_geo)),
        between_iso_max: mean_max(cases.iter().map(|c| c.err_iso_max)),
        by_anisotropy: BINS
            .iter()
            .map(|&(label, lo, hi)| {
                let inb: Vec<&Between> = cases
                    .iter()
                    .filter(|c| ratio(&c.case) > lo && ratio(&c.case) <= hi)
                    .collect();
                Bin {
                    label: label.into(),
                    ours: mean_max(inb.iter().map(|c| c.err_table)),
                    iso_geo: mean_max(inb.iter().map(|c| c.err_iso_geo)),
                    iso_max: mean_max(inb.iter().map(|c| c.err_iso_max)),
                }
            })
            .collect(),
        design: design.clone(),
        predictions: sizes.into_iter().map(predict).collect(),
        bar_max: fitted
            .iter()
            .map(|f| f.bar)
            .chain(cases.iter().map(|c| c.bar))
            .fold(design.bar_max, f64::max),
        cells_l1: mean_max(fitted.iter().map(|f| f.err_l1)),
        between_table_l1: mean_max(cases.iter().map(|c| c.err_table_l1)),
    }
}

/// The fitted cells' held-out error averaged onto two planes: (r_x, r_y) over (φ, t),
/// rows r_y, and (φ, t) over (r_x, r_y), rows t; 0 where no fitted cell falls (the
/// mirror half), else floored at 1e-8 for the log colour scale.
#[derive(Clone, Debug)]
pub struct HeatMaps {
    pub rx_ry: Vec<Vec<f64>>,
    pub phi_t: Vec<Vec<f64>>,
}

pub(super) fn heat_maps(fitted: &[Fitted], pl: &Plan) -> HeatMaps {
    let g = pl.grid;
    let idx = |x: f64, n: usize| ((x * (n - 1) as f64).round() as usize).min(n - 1);
    let mut a = vec![vec![(0.0, 0usize); g.n_r]; g.n_r];
    let mut b = vec![vec![(0.0, 0usize); g.n_phi]; g.n_t];
    for f in fitted.iter().filter(|f| f.err.is_finite()) {
        let c = &f.case;
        let (ix, iy) = (idx(c.ax.sqrt(), g.n_r), idx(c.ay.sqrt(), g.n_r));
        let k = idx(c.phi / std::f64::consts::FRAC_PI_2, g.n_phi);
        let j = idx((1.0 - c.theta.cos()).max(0.0).sqrt(), g.n_t);
        a[iy][ix].0 += f.err;
        a[iy][ix].1 += 1;
        b[j][k].0 += f.err;
        b[j][k].1 += 1;
    }
    let mean = |m: Vec<Vec<(f64, usize)>>| -> Vec<Vec<f64>> {
        m.into_iter()
            .map(|r| {
                r.into_iter()
                    .map(|(s, n)| if n > 0 { (s / n as f64).max(1e-8) } else { 0.0 })
                    .collect()
            })
            .collect()
    };
    HeatMaps {
        rx_ry: mean(a),
        phi_t: mean(b),
    }
}
