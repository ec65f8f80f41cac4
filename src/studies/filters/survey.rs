//! The survey's representations (seed 004 §3.2, [`crate::survey`]) on the footprint
//! study's own map cases: the same footprints, views, light samples and truth as the
//! filters of results/filters.md, so every row is comparable. Each footprint's
//! representations are built once (from its base texels, or from its four children one
//! level down for the MIP-mapped variants) and measured on every view's samples.

use super::cases::MapCase;
use super::plan::seed_of;
use crate::error::Result;
use crate::filters::footprint::NormalMap;
use crate::filters::rules;
use crate::filters::truth::CaseResult;
use crate::microfacet::NdfKind;
use crate::survey::em::{merge_slopes, merge_vmf, EmLog, SlopeMixture, VmfMixture};
use crate::survey::fournier::{self, Target};
use crate::survey::sh::{HanSh, VmfConvolved, Zonal};
use crate::survey::single::{OlanoNorth, SggxLobe, SlopeGaussian};
use crate::survey::{BaseLobe, ExactPdf, NormalPdf, Shading, Texels};
use nalgebra::Vector3;
use rayon::prelude::*;
use serde::Serialize;

type V3 = Vector3<f64>;

/// One row of the survey table: its name, family (one colour in the Pareto plot) and
/// parameters per texel (`None` for the exact distribution, which keeps every texel).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Row {
    pub name: &'static str,
    pub family: &'static str,
    pub params: Option<usize>,
}

const fn row(name: &'static str, family: &'static str, params: usize) -> Row {
    Row {
        name,
        family,
        params: Some(params),
    }
}

/// Lobe counts of Fournier's sums.
pub const FOURNIER_K: [usize; 5] = [1, 2, 3, 5, 7];
/// Lobe counts of the EM mixtures fitted per footprint, and of the MIP-mapped ones.
pub const EM_K: [usize; 3] = [1, 2, 4];
pub const MIP_K: [usize; 2] = [2, 4];
/// SH degrees of Han et al.'s basis.
pub const SH_L: [usize; 3] = [3, 7, 15];
/// The base lobe's zonal series length (degree) for the vMF convolution.
const ZONAL_LMAX: usize = 320;
/// Directions of Fournier's least-squares objective.
const FOURNIER_DIRS: usize = 256;

/// The survey rows, in the order of [`FootprintFit::reps`]. Parameter counts: a lobe's
/// weight, its direction (2) and its width (1); mixtures' weights sum to 1 (one less); SH
/// drops p_00 (always 1/√4π).
pub const ROWS: [Row; 24] = [
    Row {
        name: "exact footprint NDF q_A under the Eq 12 rule (floor)",
        family: "exact",
        params: None,
    },
    row("Schilling, recomputed per level", "Schilling", 5),
    row(
        "Schilling, MIP-mapped linearly (one level)",
        "Schilling (mipped)",
        5,
    ),
    row("Olano & North 3D Gaussian (Eq 17)", "Olano & North", 9),
    row("SGGX / Neyret ellipsoid (Eq 18)", "SGGX", 5),
    row("Olano & Baker Gaussian slopes (Eq 19)", "Olano & Baker", 5),
    row("Fournier, 1 Blinn–Phong lobe (Eq 20)", "Fournier", 4),
    row("Fournier, 2 lobes", "Fournier", 8),
    row("Fournier, 3 lobes", "Fournier", 12),
    row("Fournier, 5 lobes", "Fournier", 20),
    row("Fournier, 7 lobes", "Fournier", 28),
    row("Tan et al., 1 slope Gaussian (Eq 21), EM", "Tan et al.", 3),
    row("Tan et al., 2 lobes, EM", "Tan et al.", 7),
    row("Tan et al., 4 lobes, EM", "Tan et al.", 15),
    row(
        "Tan et al., 2 lobes, MIP-mapped (aligned)",
        "Tan et al. (mipped)",
        7,
    ),
    row(
        "Tan et al., 4 lobes, MIP-mapped (aligned)",
        "Tan et al. (mipped)",
        15,
    ),
    row("Han et al. SH, degree 3", "Han SH", 15),
    row("Han et al. SH, degree 7", "Han SH", 63),
    row("Han et al. SH, degree 15", "Han SH", 255),
    row("Han et al. vMF, 1 lobe (Eq 22), EM", "Han vMF", 3),
    row("Han et al. vMF, 2 lobes, EM", "Han vMF", 7),
    row("Han et al. vMF, 4 lobes, EM", "Han vMF", 15),
    row(
        "Han et al. vMF, 2 lobes, MIP-mapped (aligned)",
        "Han vMF (mipped)",
        7,
    ),
    row(
        "Han et al. vMF, 4 lobes, MIP-mapped (aligned)",
        "Han vMF (mipped)",
        15,
    ),
];

/// What building one footprint's representations found (for the report's diagnostics).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Diag {
    /// Per merged K ([`MIP_K`]): (misaligned pairs, pairs) for Tan and for vMF.
    pub tan_align: Vec<(usize, usize)>,
    pub vmf_align: Vec<(usize, usize)>,
    pub em: EmLog,
    /// Per Fournier K: L-BFGS iterations and the fit's relative L2 on its directions.
    pub fournier_iters: Vec<u64>,
    pub fournier_fit_l2: Vec<f64>,
    /// The Olano–North normalisation's relative quadrature error.
    pub olano_north_z_err: f64,
    /// Terms of the longest vMF zonal series.
    pub vmf_terms: usize,
}

/// One footprint's representations and the shading rule they share.
pub struct FootprintFit {
    pub reps: Vec<Box<dyn NormalPdf>>,
    pub shading: Shading,
    pub diag: Diag,
}

fn add_log(a: &mut EmLog, b: &EmLog) {
    a.iterations += b.iterations;
    a.reseeded += b.reseeded;
    a.dropped += b.dropped;
    a.floored += b.floored;
    a.kappa_capped += b.kappa_capped;
}

/// Every representation of one footprint (block `idx` of `level`) for the base lobe.
pub fn fit_footprint(
    map: &NormalMap,
    level: usize,
    idx: usize,
    base: BaseLobe,
    zonal: &Zonal,
    seed: u64,
) -> Result<FootprintFit> {
    let lw = (map.width >> level).max(1);
    let (i, j) = (idx % lw, idx / lw);
    let normals = map.block(level, i, j);
    let w = vec![1.0 / normals.len() as f64; normals.len()];
    let t = Texels {
        normals: &normals,
        weights: &w,
        base,
    };
    let kid_normals: Vec<Vec<V3>> = (0..4)
        .map(|q| map.block(level.saturating_sub(1), 2 * i + q % 2, 2 * j + q / 2))
        .collect();
    let kid_w: Vec<Vec<f64>> = kid_normals
        .iter()
        .map(|k| vec![1.0 / k.len() as f64; k.len()])
        .collect();
    let kids: Vec<Texels> = kid_normals
        .iter()
        .zip(&kid_w)
        .map(|(n, w)| Texels {
            normals: n,
            weights: w,
            base,
        })
        .collect();
    let mut diag = Diag::default();
    let mut reps: Vec<Box<dyn NormalPdf>> = vec![
        Box::new(ExactPdf::new(&t)),
        Box::new(SlopeGaussian::schilling(&t)?),
    ];
    let ch: Vec<(V3, SlopeGaussian)> = kids
        .iter()
        .map(|k| Ok((k.mean_normal(), SlopeGaussian::schilling(k)?)))
        .collect::<Result<_>>()?;
    reps.push(Box::new(SlopeGaussian::schilling_mipped(&ch)?));
    let on = OlanoNorth::new(&t)?;
    diag.olano_north_z_err = on.z_rel_err;
    reps.push(Box::new(on));
    reps.push(Box::new(SggxLobe::new(&t)?));
    reps.push(Box::new(SlopeGaussian::olano_baker(&t)?));
    let target = Target::new(&t, FOURNIER_DIRS, seed);
    for k in FOURNIER_K {
        let f = fournier::fit(&t, &target, k, 100)?;
        diag.fournier_iters.push(f.iterations);
        diag.fournier_fit_l2.push(f.fit_rel_l2);
        reps.push(Box::new(f));
    }
    for k in EM_K {
        let m = SlopeMixture::fit(t.normals, t.weights, k, base.alpha)?;
        add_log(&mut diag.em, &m.log);
        reps.push(Box::new(m));
    }
    for k in MIP_K {
        let children: Vec<SlopeMixture> = kids
            .iter()
            .map(|c| SlopeMixture::fit(c.normals, c.weights, k, base.alpha))
            .collect::<Result<_>>()?;
        let merged = merge_slopes(&children);
        diag.tan_align.push((merged.misaligned, merged.pairs));
        reps.push(Box::new(SlopeMixture {
            comps: merged.lobes,
            base_var: 0.5 * base.alpha * base.alpha,
            log: EmLog::default(),
        }));
    }
    for l in SH_L {
        reps.push(Box::new(HanSh::new(&t, zonal, l)?));
    }
    for k in EM_K {
        let m = VmfMixture::fit(t.normals, t.weights, k)?;
        add_log(&mut diag.em, &m.log);
        let c = VmfConvolved::new(&m, zonal);
        diag.vmf_terms = diag.vmf_terms.max(c.terms());
        reps.push(Box::new(c));
    }
    for k in MIP_K {
        let children: Vec<VmfMixture> = kids
            .iter()
            .map(|c| VmfMixture::fit(c.normals, c.weights, k))
            .collect::<Result<_>>()?;
        let merged = merge_vmf(&children, base.alpha);
        diag.vmf_align.push((merged.misaligned, merged.pairs));
        let m = VmfMixture {
            comps: merged.lobes,
            log: EmLog::default(),
        };
        reps.push(Box::new(VmfConvolved::new(&m, zonal)));
    }
    debug_assert_eq!(reps.len(), ROWS.len());
    let mean = t.mean_normal();
    let alpha_eq = rules::vmf(base.alpha, mean.norm().min(1.0), 2.0);
    Ok(FootprintFit {
        reps,
        shading: Shading::new(base.kind, mean, alpha_eq)?,
        diag,
    })
}

/// The survey's measurements: per case (in the map cases' order) one result per row of
/// [`ROWS`], and per footprint its diagnostics.
pub struct SurveyCases {
    pub results: Vec<Vec<CaseResult>>,
    pub diags: Vec<Diag>,
    /// Views per footprint (case c belongs to footprint c / views).
    pub views: usize,
}

/// Build every footprint's representations, then measure them on every case's samples.
pub(super) fn survey_study(
    maps: &[NormalMap],
    cases: &[MapCase],
    views: usize,
    seed: u64,
) -> Result<SurveyCases> {
    let mut zonals: Vec<((NdfKind, u64), Zonal)> = Vec::new();
    for c in cases.iter().step_by(views.max(1)) {
        let key = (c.kind, c.alpha.to_bits());
        if !zonals.iter().any(|z| z.0 == key) {
            let base = BaseLobe {
                kind: c.kind,
                alpha: c.alpha,
            };
            zonals.push((key, Zonal::new(base, ZONAL_LMAX)));
        }
    }
    let heads: Vec<&MapCase> = cases.iter().step_by(views.max(1)).collect();
    let pb = crate::progress::Progress::new("filters: survey representations", heads.len() as u64);
    let fits: Vec<FootprintFit> = heads
        .par_iter()
        .enumerate()
        .map(|(fi, c)| {
            let key = (c.kind, c.alpha.to_bits());
            let z = &zonals
                .iter()
                .find(|z| z.0 == key)
                .expect("zonal of every (kind, α)")
                .1;
            let base = BaseLobe {
                kind: c.kind,
                alpha: c.alpha,
            };
            let f = fit_footprint(
                &maps[c.map],
                c.level,
                c.idx,
                base,
                z,
                seed_of(seed ^ 0x5E, fi),
            );
            pb.inc(1);
            f
        })
        .collect::<Result<_>>()?;
    pb.finish();
    let results: Vec<Vec<CaseResult>> = cases
        .par_iter()
        .enumerate()
        .map(|(ci, c)| {
            let fit = &fits[ci / views.max(1)];
            let n = fit.shading.normal();
            fit.reps
                .iter()
                .map(|r| {
                    c.samples
                        .measure(&|v: &V3, l: &V3| fit.shading.value(&**r, v, l), &n)
                })
                .collect()
        })
        .collect();
    crate::report::stage("regen filters: survey representations done");
    Ok(SurveyCases {
        results,
        diags: fits.into_iter().map(|f| f.diag).collect(),
        views,
    })
}
