//! Multi-scale LTC identities (seed 000 §3.3): the closed form of ‖b̄‖(α).

use super::{Outcome, Worst};
use crate::integrate::mc::{mis, Strategy};
use crate::integrate::quad::Tol;
use crate::integrate::sphere::{integrate_sphere, SphereRule};
use crate::integrate::Preset;
use crate::ltc::LtcDist;
use crate::multiscale::mrl::{alpha_from_one_minus, mrl_pair};
use nalgebra::Vector3;

/// ‖b̄‖(α) closed form vs adaptive quadrature of seed 000 Eq 4 vs MC sampling of the LTC;
/// the inverse round trip; the limits.
pub fn mrl_closed_form(p: Preset) -> Outcome {
    let alphas: &[f64] = match p {
        Preset::Quick => &[1e-4, 0.1, 0.9, 1.0, 1.1, 3.0],
        _ => &[
            1e-4, 1e-3, 0.01, 0.1, 0.3, 0.6, 0.9, 0.99, 1.0, 1.01, 1.5, 3.0, 10.0,
        ],
    };
    let mut quad = Worst::default();
    let mut z = Worst::default();
    let mut inv = Worst::default();
    for &a in alphas {
        let g = LtcDist::isotropic(a).expect("α > 0");
        let (b, y) = mrl_pair(a);
        // Eq 4: ∫_H b·ẑ γ(b) db with γ evaluated from Eq 1 (not from the GGX identity)
        let f = |w: &Vector3<f64>| w.z.max(0.0) * g.eval(w);
        let e = integrate_sphere(
            &f,
            &SphereRule::hemisphere(a.min(1.0)),
            Tol::new(1e-12, 1e-12, 20_000_000),
        );
        quad.update((e.value - b).abs(), || {
            format!("α={a} (closed {b:.15}, quad {e})")
        });
        // MIS with a 30× wider LTC: 1 − ‖b̄‖ is carried by the heavy tail (mass spread over
        // every scale between α and 1), which sampling γ alone reaches too rarely for its
        // standard error to mean anything at α = 1e-4
        let wide = LtcDist::isotropic((30.0 * a).min(1.0).max(a)).expect("α > 0");
        let strat: [&dyn Strategy<Vector3<f64>>; 2] = [&g, &wide];
        let mc = mis(&f, &strat, p.mc_samples(), 77);
        z.update((mc.value - b).abs() / mc.error.max(1e-300), || {
            format!("α={a} (MC {mc})")
        });
        let back = alpha_from_one_minus(y)
            .map(|x| (x - a).abs() / a)
            .unwrap_or(f64::INFINITY);
        inv.update(back, || format!("α={a}"));
    }
    // dense round trip of the inverse
    for i in 0..=2000 {
        let a = 1e-6 * (1e8f64).powf(i as f64 / 2000.0);
        let back = alpha_from_one_minus(mrl_pair(a).1)
            .map(|x| (x - a).abs() / a)
            .unwrap_or(f64::INFINITY);
        inv.update(back, || format!("α={a:.3e}"));
    }
    let a0 = 1e-6;
    let ratio0 = mrl_pair(a0).1 / (a0 * a0 * ((2.0 / a0).ln() - 1.0));
    let big = 1e4;
    let ratio_inf = mrl_pair(big).0 / (std::f64::consts::PI / (2.0 * big));
    let t = 1e-10;
    Outcome {
        id: "mrl-closed-form",
        title: "Closed form of the mean resultant length ‖b̄‖(α) of the isotropic LTC",
        source: "seed 000 Eq 2–4",
        ranges: format!("α ∈ {alphas:?}; inverse round trip on 2001 points in [1e-6, 1e2]"),
        cases: alphas.len(),
        worst_error: quad.err,
        error_kind: "abs (closed form vs quadrature of Eq 4)",
        worst_case: quad.case,
        tolerance: t,
        passed: quad.err <= t && z.err <= 3.0 && inv.err <= 1e-13,
        seconds: 0.0,
        notes: vec![
            format!("MC (MIS of the LTC and a 30× wider LTC, {} tuples): worst |z| = {:.2} at {}", p.mc_samples(), z.err, z.case),
            format!("inverse α(‖b̄‖) (safeguarded Newton on the closed form): worst relative round-trip error {:.2e} at {}", inv.err, inv.case),
            format!("α → 0: (1 − ‖b̄‖)/(α²(ln(2/α) − 1)) = {ratio0:.9} at α = 1e-6 (→ 1)"),
            format!("α → ∞: ‖b̄‖/(π/(2α)) = {ratio_inf:.6} at α = 1e4 (→ 1); past α = 1 the LTC keeps spreading toward the horizon and ‖b̄‖ keeps falling below 2/3, so the paper's clamp at α = 1 (‖b̄‖ ≈ 0.667) is a modelling choice, not a limit of the map"),
        ],
    }
}
