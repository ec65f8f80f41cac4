//! The visibility study's aggregates: every measured case reduced to mean ± s.e. rows per
//! method and scene group ([`summarise`]), what the report and the plots format.

use super::compute::{shadow_methods, Measured, LEGENDRE_K};
use crate::integrate::Figure;
use crate::visibility::shadow::{max_usable_c, Method, Occluders, Precision};
use serde::Serialize;

#[derive(Clone, Debug, Serialize)]
pub struct MethodRow {
    pub name: String,
    pub params: usize,
    /// mean |error| ± s.e. over all cases, then per group (maps or scenes).
    pub all: Figure,
    pub groups: Vec<Figure>,
    pub max: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub horizon_groups: Vec<String>,
    pub horizon_single: Vec<MethodRow>,
    pub horizon_joint: Vec<MethodRow>,
    /// The joint forms at l = v (truth 1), mean ± s.e. of |error|.
    pub hotspot: Vec<(String, Figure)>,
    pub eq28_hotspot_max: f64,
    pub shadow_groups: Vec<String>,
    pub shadow_f32: Vec<MethodRow>,
    pub shadow_f16: Vec<MethodRow>,
    pub eq33_cost: MethodRow,
    /// VSM's light bleeding: mean lit fraction where PCF is 0, per occluder scene.
    pub bleeding: Vec<(String, Figure, usize)>,
    /// Per ESM constant: mean |error| where some texel is deeper than d̄, and elsewhere.
    pub esm_divergence: Vec<(f64, Figure, Figure)>,
    pub precision: Vec<(String, f64, f64)>,
}

fn row(name: String, params: usize, errs: &[f64], groups: Vec<Vec<f64>>) -> MethodRow {
    MethodRow {
        name,
        params,
        all: Figure::mean_of(errs),
        groups: groups.iter().map(|g| Figure::mean_of(g)).collect(),
        max: errs.iter().cloned().fold(0.0, f64::max),
    }
}

fn method_name(m: &Method) -> String {
    match *m {
        Method::Vsm => "VSM (Chebyshev)".into(),
        Method::Csm { terms, fixed } => format!(
            "CSM, {terms} terms{}",
            if fixed { ", offset + scale" } else { "" }
        ),
        Method::Esm { c } => format!("ESM, c = {c}"),
        Method::Evsm { c } => format!("EVSM, c = {c}"),
    }
}

fn occluder_name(o: Occluders) -> &'static str {
    match o {
        Occluders::Plane => "plane",
        Occluders::Layers => "layers",
        Occluders::Fence => "fence",
        Occluders::Sphere => "sphere",
    }
}

/// The horizon rows of a set of cases: (maps, V_A(v) rows, V_A(l, v) rows, the joint forms
/// at l = v, the worst |Eq 28 − 1| at l = v).
pub type HorizonSummary = (
    Vec<String>,
    Vec<MethodRow>,
    Vec<MethodRow>,
    Vec<(String, Figure)>,
    f64,
);

pub fn horizon_summary(cases: &[super::compute::HorizonCase]) -> HorizonSummary {
    let hg: Vec<String> = {
        let mut g: Vec<String> = cases.iter().map(|c| c.map.clone()).collect();
        g.dedup();
        g
    };
    let mut single_names = vec![
        "Fournier: linear ramp (8)".to_string(),
        "Tan et al.: Gaussian HDF, erf (8)".into(),
    ];
    single_names.extend(
        LEGENDRE_K
            .iter()
            .map(|k| format!("Legendre, {k} terms per azimuth ({})", 4 * k)),
    );
    single_names.push("diagnostic: Tan et al. erf from horizons at v's own azimuth".into());
    single_names.push("diagnostic: Legendre 32 from horizons at v's own azimuth".into());
    let single_params: Vec<usize> = [8, 8]
        .into_iter()
        .chain(LEGENDRE_K.iter().map(|k| 4 * k))
        .chain([8, 128])
        .collect();
    let horizon_single = (0..single_names.len())
        .map(|k| {
            let e: Vec<f64> = cases
                .iter()
                .map(|c| (c.single[k] - c.truth_v).abs())
                .collect();
            let g = hg
                .iter()
                .map(|n| {
                    cases
                        .iter()
                        .filter(|c| &c.map == n)
                        .map(|c| (c.single[k] - c.truth_v).abs())
                        .collect()
                })
                .collect();
            row(single_names[k].clone(), single_params[k], &e, g)
        })
        .collect();
    let joint_names = [
        "Fournier: ramp, V_A(l)V_A(v)",
        "Tan erf, uncorrelated product",
        "Tan erf + Eq 28",
        "Tan erf + Ashikhmin β (width 0.25 rad)",
        "Legendre 16 + Eq 28",
    ];
    let joint_params = [8, 8, 8, 8, 64];
    let horizon_joint: Vec<MethodRow> = (0..joint_names.len())
        .map(|k| {
            let e: Vec<f64> = cases
                .iter()
                .map(|c| (c.joint[k] - c.truth_lv).abs())
                .collect();
            let g = [true, false]
                .iter()
                .map(|&h| {
                    cases
                        .iter()
                        .filter(|c| c.hotspot == h)
                        .map(|c| (c.joint[k] - c.truth_lv).abs())
                        .collect()
                })
                .collect();
            row(joint_names[k].to_string(), joint_params[k], &e, g)
        })
        .collect();
    let hotspot = (0..joint_names.len())
        .map(|k| {
            let e: Vec<f64> = cases
                .iter()
                .filter(|c| c.hotspot)
                .map(|c| (c.joint[k] - 1.0).abs())
                .collect();
            (joint_names[k].to_string(), Figure::mean_of(&e))
        })
        .collect();
    let eq28_hotspot_max = cases
        .iter()
        .filter(|c| c.hotspot && c.single[1] > 0.0)
        .map(|c| (c.joint[2] - 1.0).abs())
        .fold(0.0, f64::max);
    (hg, horizon_single, horizon_joint, hotspot, eq28_hotspot_max)
}

pub fn summarise(m: &Measured) -> Summary {
    let (hg, horizon_single, horizon_joint, hotspot, eq28_hotspot_max) =
        horizon_summary(&m.horizon);
    let sh = shadow_summary(m);
    Summary {
        horizon_groups: hg,
        horizon_single,
        horizon_joint,
        hotspot,
        eq28_hotspot_max,
        shadow_groups: sh.0,
        shadow_f32: sh.1,
        shadow_f16: sh.2,
        eq33_cost: sh.3,
        bleeding: sh.4,
        esm_divergence: sh.5,
        precision: sh.6,
    }
}

/// One error per shadow case, over all cases and per occluder scene.
fn by_scene(
    m: &Measured,
    occ: &[Occluders],
    err: &dyn Fn(&super::compute::ShadowCase) -> f64,
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let all = m.shadow.iter().map(err).collect();
    let per = occ
        .iter()
        .map(|o| {
            m.shadow
                .iter()
                .filter(|c| c.scene.occluders == *o)
                .map(err)
                .collect()
        })
        .collect();
    (all, per)
}

type ShadowSummary = (
    Vec<String>,
    Vec<MethodRow>,
    Vec<MethodRow>,
    MethodRow,
    Vec<(String, Figure, usize)>,
    Vec<(f64, Figure, Figure)>,
    Vec<(String, f64, f64)>,
);

/// The shadow rows: every method at f32 and f16 per scene, Eq 33's cost, VSM's bleeding,
/// ESM's divergence region and the precision limits.
fn shadow_summary(m: &Measured) -> ShadowSummary {
    let occ = [
        Occluders::Plane,
        Occluders::Layers,
        Occluders::Fence,
        Occluders::Sphere,
    ];
    let methods = shadow_methods();
    let shadow_rows = |f16: bool| -> Vec<MethodRow> {
        methods
            .iter()
            .enumerate()
            .map(|(k, meth)| {
                let err = |c: &super::compute::ShadowCase| {
                    ((if f16 { &c.f16 } else { &c.f32 })[k] - c.pcf).abs()
                };
                let (e, g) = by_scene(m, &occ, &err);
                row(method_name(meth), meth.params(), &e, g)
            })
            .collect()
    };
    let eq33 = {
        let err = |c: &super::compute::ShadowCase| (c.pcf_mean_depth - c.pcf).abs();
        let (e, g) = by_scene(m, &occ, &err);
        row(
            "PCF at the mean receiver depth (Eq 33's assumption)".into(),
            1,
            &e,
            g,
        )
    };
    let bleeding = occ
        .iter()
        .map(|o| {
            let v: Vec<f64> = m
                .shadow
                .iter()
                .filter(|c| c.scene.occluders == *o && c.pcf == 0.0)
                .map(|c| c.f32[0])
                .collect();
            (occluder_name(*o).to_string(), Figure::mean_of(&v), v.len())
        })
        .collect();
    let esm_divergence = methods
        .iter()
        .enumerate()
        .filter_map(|(k, meth)| match meth {
            Method::Esm { c } => {
                let pick = |d: bool| -> Vec<f64> {
                    m.shadow
                        .iter()
                        .filter(|s| s.diverging == d)
                        .map(|s| (s.f32[k] - s.pcf).abs())
                        .collect()
                };
                Some((
                    *c,
                    Figure::mean_of(&pick(true)),
                    Figure::mean_of(&pick(false)),
                ))
            }
            _ => None,
        })
        .collect();
    let precision = vec![
        (
            "ESM (stores e^{cz}, z ≤ 1)".to_string(),
            max_usable_c(false, Precision::F32),
            max_usable_c(false, Precision::F16),
        ),
        (
            "EVSM (stores e^{2cz})".to_string(),
            max_usable_c(true, Precision::F32),
            max_usable_c(true, Precision::F16),
        ),
    ];
    (
        occ.iter().map(|o| occluder_name(*o).to_string()).collect(),
        shadow_rows(false),
        shadow_rows(true),
        eq33,
        bleeding,
        esm_divergence,
        precision,
    )
}
