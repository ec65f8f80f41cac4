//! The anisotropic table's design study: what each dimension's resolution costs (dense
//! 1D lines through the domain, each node fitted as a table cell is, interpolated at
//! coarser spacings).

use super::compute::{fit_case, Case, Fitted, Plan};
use crate::error::Result;
use crate::ltc::aniso::{AnisoGgxTarget, Inv7};
use crate::ltc::table::FittedTable;
use crate::ltc::target::LtcTarget;

pub use crate::results::ltc_aniso::{Design, Penalty};

/// The dimensions of the table.
pub const DIMS: [&str; 4] = ["r_x = √α_x", "r_y = √α_y", "φ", "t = √(1 − cos θ)"];

/// One line of the design study: the fits at its nodes.
struct Line {
    dim: usize,
    nodes: Vec<Fitted>,
}

fn case_at(base: &[f64; 4], dim: usize, u: f64, amin: f64) -> Case {
    let mut p = *base;
    p[dim] = if dim == 2 {
        u * std::f64::consts::FRAC_PI_2
    } else {
        u
    };
    Case {
        ax: (p[0] * p[0]).max(amin),
        ay: (p[1] * p[1]).max(amin),
        phi: p[2],
        theta: (1.0 - p[3] * p[3]).clamp(0.0, 1.0).acos(),
    }
}

/// Dense lines through the domain, one per dimension and base point, each node fitted as
/// a table cell is; then every coarser spacing 2, 4, … of the same nodes, the dropped
/// nodes interpolated linearly.
pub(super) fn design_study(iso: &FittedTable, pl: &Plan) -> Result<Design> {
    let bases: Vec<[f64; 4]> = if pl.line <= 5 {
        vec![[0.7, 0.35, std::f64::consts::FRAC_PI_6, 0.55]]
    } else {
        vec![
            [0.7, 0.35, std::f64::consts::FRAC_PI_6, 0.55],
            [0.45, 0.2, std::f64::consts::FRAC_PI_3, 0.8],
        ]
    };
    let amin = pl.grid.alpha_min;
    let l = pl.line;
    let jobs: Vec<(usize, usize, usize)> = (0..bases.len())
        .flat_map(|b| (0..4).flat_map(move |d| (0..l).map(move |k| (b, d, k))))
        .collect();
    let fits: Vec<Fitted> =
        crate::memo::map_items("ltc-aniso design lines", &jobs, |&(b, d, k)| {
            fit_case(
                iso,
                case_at(&bases[b], d, k as f64 / (l - 1) as f64, amin),
                pl,
            )
        })?;
    let lines: Vec<Line> = fits
        .chunks(l)
        .enumerate()
        .map(|(q, c)| Line {
            dim: q % 4,
            nodes: c.to_vec(),
        })
        .collect();
    // every interpolated node of every spacing that divides the line (n = (l − 1)/step + 1
    // nodes), judged in parallel: (dim, step, the entries, the norm, the case)
    let mut jobs: Vec<(usize, usize, Inv7, f64, Case)> = Vec::new();
    let mut fitted_at: Vec<(usize, usize, f64)> = Vec::new();
    for dim in 0..4 {
        for step in (2..l).filter(|s| (l - 1) % s == 0) {
            for line in lines.iter().filter(|x| x.dim == dim) {
                for k in (0..l).filter(|k| k % step != 0) {
                    let (k0, k1) = (k - k % step, k - k % step + step);
                    let w = (k - k0) as f64 / step as f64;
                    let (a, b) = (&line.nodes[k0], &line.nodes[k1]);
                    let inv: Inv7 = std::array::from_fn(|q| a.inv[q] * (1.0 - w) + b.inv[q] * w);
                    let norm = a.norm * (1.0 - w) + b.norm * w;
                    jobs.push((dim, step, inv, norm, line.nodes[k].case));
                    fitted_at.push((dim, step, line.nodes[k].err));
                }
            }
        }
    }
    let judged: Vec<(f64, f64)> = crate::memo::map_items(
        "ltc-aniso design interpolation",
        &jobs,
        |(_, _, inv, norm, c)| {
            let t = AnisoGgxTarget::new(c.ax, c.ay, c.theta, c.phi)?;
            let (albedo, _, _) = t.albedo(1e-7);
            let (l2, _, bar) = super::compute::held_out(&t, albedo, &[(*inv, *norm)], pl.tol);
            Ok((l2[0], bar))
        },
    )?;
    let mut penalties = Vec::new();
    for dim in 0..4 {
        for step in (2..l).filter(|s| (l - 1) % s == 0) {
            let pick = |v: &dyn Fn(usize) -> f64| {
                let x: Vec<f64> = (0..jobs.len())
                    .filter(|&q| jobs[q].0 == dim && jobs[q].1 == step)
                    .map(v)
                    .collect();
                x.iter().sum::<f64>() / x.len().max(1) as f64
            };
            penalties.push(Penalty {
                dim,
                n: (l - 1) / step + 1,
                interpolated: pick(&|q| judged[q].0),
                fitted: pick(&|q| fitted_at[q].2),
            });
        }
    }
    let bar_max = judged
        .iter()
        .map(|x| x.1)
        .chain(fits.iter().map(|f| f.bar))
        .fold(0.0, f64::max);
    Ok(Design {
        bases,
        penalties,
        bar_max,
    })
}
