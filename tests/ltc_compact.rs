//! Compact LTC tables (`ltc::compact`): the Chebyshev series against independent
//! references — T_k(x) = cos(k·acos x), a polynomial of lower degree than the series
//! reproduced by the least-squares fit, the f32 shading form within its stated bound of
//! the f64 reference over the whole input range, bad input as typed errors.

mod common;

use ndfbench::ltc::compact::{Compact, Series, Transform};
use ndfbench::ltc::table::FittedTable;
use proptest::prelude::*;

/// A 64² table whose channel `ch` is `f(ch, r, t)` at the texel centres.
fn table_of(n: usize, f: impl Fn(usize, f64, f64) -> f64) -> FittedTable {
    let cells = (0..n * n)
        .map(|k| {
            let (r, t) = (
                (k % n) as f64 / (n - 1) as f64,
                (k / n) as f64 / (n - 1) as f64,
            );
            std::array::from_fn(|ch| f(ch, r, t))
        })
        .collect();
    FittedTable {
        n,
        cells,
        half: None,
    }
}

/// Polynomials of degree ≤ 5 in r and in t, one per channel (the last three positive,
/// for the log transform: their logarithms are the polynomials).
fn poly(ch: usize, r: f64, t: f64) -> f64 {
    let c = ch as f64;
    0.3 + 0.1 * c + r.powi(3) - 2.0 * r * t * t + (0.5 - c / 7.0) * t.powi(5) + 0.25 * r.powi(5) * t
}

const MIXED: [Transform; 6] = [
    Transform::Raw,
    Transform::Raw,
    Transform::Raw,
    Transform::Log,
    Transform::Log,
    Transform::Log,
];

/// The channel the mixed transforms' fit should reproduce.
fn mixed(ch: usize, r: f64, t: f64) -> f64 {
    if ch < 3 {
        poly(ch, r, t)
    } else {
        poly(ch, r, t).exp()
    }
}

/// A single Chebyshev product T_k(2r − 1)·T_l(2t − 1) as a p×p series.
fn unit(p: usize, k: usize, l: usize) -> Compact {
    let mut coeffs = vec![0.0; p * p];
    coeffs[k + p * l] = 1.0;
    Compact {
        alpha_min: 0.0,
        p,
        channels: (0..6)
            .map(|_| Series {
                transform: Transform::Raw,
                coeffs: coeffs.clone(),
            })
            .collect(),
    }
}

/// (r, t) over the whole input range: the ends of [0, 1] often, values outside (clamped
/// by the form) sometimes.
fn place() -> impl Strategy<Value = f64> {
    prop_oneof![
        2 => Just(0.0),
        2 => Just(1.0),
        1 => Just(1e-12),
        1 => Just(1.0 - 1e-12),
        1 => -10.0f64..0.0,
        1 => 1.0f64..10.0,
        12 => 0.0f64..=1.0,
    ]
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// The recurrence sums T_k(x)·T_l(y) with T_k(x) = cos(k·acos x) (x = 2r − 1 and
    /// y = 2t − 1, r and t clamped to [0, 1]).
    #[test]
    fn series_sum_the_trigonometric_chebyshev_products(
        k in 0usize..24, l in 0usize..24, r in place(), t in place()
    ) {
        let c = unit(24, k, l);
        let (x, y) = (2.0 * r.clamp(0.0, 1.0) - 1.0, 2.0 * t.clamp(0.0, 1.0) - 1.0);
        let want = (k as f64 * x.acos()).cos() * (l as f64 * y.acos()).cos();
        let got = c.eval(r, t)[0];
        prop_assert!((got - want).abs() <= 1e-12, "T_{k}·T_{l} at ({r}, {t}): {got} vs {want}");
    }

    /// The f32 shading form is within its bound of the f64 reference over the whole
    /// input range: |f32 − f64| ≤ 8·p·ε₃₂·Σ|c| for a raw channel (Clenshaw's recurrence
    /// in each direction; the coefficients' own f32 rounding included), for the series
    /// fitted to polynomial channels at p = 6, 12 and 24.
    #[test]
    fn f32_form_is_within_its_bound(pi in 0usize..3, r in place(), t in place()) {
        let p = [6, 12, 24][pi];
        let c = Compact::fit(&table_of(64, poly), p, [Transform::Raw; 6]).unwrap();
        let c32 = c.coeffs_f32();
        let a = c.eval(r, t);
        let b = c.eval_f32(&c32, r as f32, t as f32);
        for ch in 0..6 {
            let sum: f64 = c.channels[ch].coeffs.iter().map(|v| v.abs()).sum();
            let bound = 8.0 * p as f64 * f64::from(f32::EPSILON) * sum;
            let err = (f64::from(b[ch]) - a[ch]).abs();
            prop_assert!(err <= bound, "p = {p}, channel {ch} at ({r}, {t}): {err:e} > {bound:e}");
        }
    }
}

/// A table of polynomials of degree ≤ 5 in each variable is reproduced by the fit at any
/// p ≥ 6, raw and through the log transform (whose channels are exponentials of them),
/// at points between the texel centres too.
#[test]
fn the_fit_reproduces_polynomials_within_its_degree() {
    for p in [6, 9, 16] {
        let c = Compact::fit(&table_of(64, mixed), p, MIXED).unwrap();
        assert_eq!(c.coefficients(), 6 * p * p);
        for q in 0..=40 {
            for s in 0..=40 {
                let (r, t) = (q as f64 / 40.0, s as f64 / 40.0);
                let v = c.eval(r, t);
                for (ch, got) in v.iter().enumerate() {
                    let want = mixed(ch, r, t);
                    assert!(
                        (got - want).abs() <= 1e-11 * want.abs().max(1.0),
                        "p = {p}, channel {ch} at ({r}, {t}): {got} vs {want}"
                    );
                }
            }
        }
    }
    // below the polynomials' degree the fit cannot reproduce them
    let c = Compact::fit(&table_of(64, poly), 4, [Transform::Raw; 6]).unwrap();
    let worst = (0..=40)
        .map(|q| {
            let r = q as f64 / 40.0;
            (c.eval(r, 0.9)[0] - poly(0, r, 0.9)).abs()
        })
        .fold(0.0, f64::max);
    assert!(
        worst > 1e-4,
        "a degree-5 polynomial fitted at p = 4: {worst:e}"
    );
}

/// The rebuilt table holds the series at the texel centres, and its binary16 entries
/// are the nearest binary16 of each.
#[test]
fn the_rebuild_is_the_series_at_the_texel_centres() {
    let c = Compact::fit(&table_of(64, mixed), 8, MIXED).unwrap();
    let t = c.rebuild(32).unwrap();
    assert!(c.rebuild(1).is_err() && c.rebuild(0).is_err());
    assert_eq!(t.n, 32);
    let half = t.half.as_ref().unwrap();
    for k in 0..32 * 32 {
        let (r, s) = ((k % 32) as f64 / 31.0, (k / 32) as f64 / 31.0);
        assert_eq!(t.cells[k], c.eval(r, s));
        for ch in 0..6 {
            let v = t.cells[k][ch];
            let h = half[k][ch].to_f64();
            // no binary16 lies nearer: the neighbours one ulp either side are farther
            let up = half::f16::from_bits(half[k][ch].to_bits() + 1).to_f64();
            let down = half::f16::from_bits(half[k][ch].to_bits().wrapping_sub(1)).to_f64();
            assert!((h - v).abs() <= (up - v).abs() && (h - v).abs() <= (down - v).abs());
        }
    }
}

/// Degrees out of range, entries that are not finite and a log channel with an entry
/// ≤ 0 are typed errors.
#[test]
fn bad_input_is_a_typed_error() {
    let good = table_of(16, mixed);
    assert!(Compact::fit(&good, 0, MIXED).is_err());
    assert!(Compact::fit(&good, 17, MIXED).is_err());
    assert!(Compact::fit(&good, 16, MIXED).is_ok());
    let mut nan = good.clone();
    nan.cells[37][1] = f64::NAN;
    assert!(Compact::fit(&nan, 4, MIXED).is_err());
    let mut neg = good.clone();
    neg.cells[5][4] = 0.0;
    let e = Compact::fit(&neg, 4, MIXED).unwrap_err().to_string();
    assert!(e.contains("channel 4"), "{e}");
    // the same entry is fine for a raw channel
    assert!(Compact::fit(&neg, 4, [Transform::Raw; 6]).is_ok());
    let broken = FittedTable {
        n: 16,
        cells: vec![[1.0; 6]; 10],
        half: None,
    };
    assert!(Compact::fit(&broken, 4, MIXED).is_err());
}

/// The study judges the full table's stored binary16 entries as results/ltc-compare.json
/// judged them on Bevy's path (our ltc_ggx.ktx2, every place reached): at the places both
/// judged, the figures agree within their two bars, and the shipped figures it quotes are
/// that file's.
#[test]
fn the_study_agrees_with_the_stored_comparison() {
    use ndfbench::fit::spec::FitSpec;
    use std::path::Path;
    let spec = FitSpec::parse(
        "name = \"ltc-compact\"\nseed = 0\ntolerance = { max_rel = 1.0 }\n[params]\ndegrees = [4]\nevery = 32\nheld_out_rel = 2e-3\nmax_coefficients = 1000\nwithin_points = 1.0\nlobe_degrees = []\nlobe_nodes = 2\nlobe_iterations = 1\nlobe_passes = 1\n",
        "test",
    )
    .unwrap();
    let computed = common::compute_study(
        &spec,
        Path::new("results"),
        ndfbench::integrate::Preset::Default,
    )
    .unwrap();
    let mut set = ndfbench::io::Outputs::new();
    let d = std::env::temp_dir().join(format!("ndfbench-compact-{}", std::process::id()));
    computed.render(&mut set, &d).unwrap();
    let out: serde_json::Value =
        serde_json::from_slice(set.get(&d.join("fits/ltc-compact.json")).unwrap()).unwrap();
    let cmp: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("results/ltc-compare.json").unwrap())
            .unwrap();
    let bevy = cmp["forms"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"].as_str().unwrap().contains("Bevy"))
        .unwrap();
    // places: cells (0, 32)² and squares (0, 32)²
    let mean = |key: &str, who: &str, n: usize| {
        let (mut v, mut e) = (0.0, 0.0);
        for j in [0, 32] {
            for i in [0, 32] {
                let x = &bevy[key][i + n * j][who]["l2"];
                v += x["value"].as_f64().unwrap() / 4.0;
                e += x["error"].as_f64().unwrap() / 4.0;
            }
        }
        (v, e)
    };
    let ggx = &out["families"][0];
    assert_eq!(ggx["table"], "ltc-ggx");
    for (key, n) in [("cells", 64), ("squares", 63)] {
        let got = &ggx["full"][key]["mean"];
        let (gv, ge) = (
            got["value"].as_f64().unwrap(),
            got["error"].as_f64().unwrap(),
        );
        let (v, e) = mean(key, "ours", n);
        assert!(
            (gv - v).abs() <= ge + e,
            "{key}: {gv} ± {ge} against the comparison's {v} ± {e}"
        );
        let path = ggx["shipped"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["path"].as_str().unwrap().contains("Bevy"))
            .unwrap();
        let (sv, _) = mean(key, "shipped", n);
        let quoted = path["shipped"][key]["mean"]["value"].as_f64().unwrap();
        assert!(
            (quoted - sv).abs() <= 1e-15 * sv,
            "{key}: {quoted} against {sv}"
        );
    }
    // one form per transform set at p = 4, each with 6·16 coefficients
    for f in ggx["forms"].as_array().unwrap() {
        assert_eq!(f["coefficients"], 96);
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A series read back from a file is checked by its shape and values, not trusted: a
/// wrong channel count, a coefficient count other than p², p out of range or a
/// coefficient that is not finite is an error naming it; the committed file reads back.
#[test]
fn a_series_read_back_is_checked() {
    let good = Compact::fit(&table_of(16, mixed), 3, MIXED).unwrap();
    let json = serde_json::to_value(&good).unwrap();
    let back: Compact = serde_json::from_value(json.clone()).unwrap();
    assert_eq!(back, good);
    let broken = |f: &dyn Fn(&mut serde_json::Value)| {
        let mut v = json.clone();
        f(&mut v);
        serde_json::from_value::<Compact>(v)
            .unwrap_err()
            .to_string()
    };
    assert!(broken(&|v| v["channels"].as_array_mut().unwrap().truncate(5)).contains("5 channels"));
    assert!(broken(&|v| v["p"] = 4.into()).contains("needs 16"));
    assert!(broken(&|v| v["p"] = 0.into()).contains("p = 0"));
    assert!(broken(&|v| v["p"] = 65.into()).contains("p = 65"));
    // JSON holds no NaN or infinity (serde_json writes them as null, which is no f64)
    assert!(broken(&|v| v["channels"][2]["coeffs"][1] = serde_json::Value::Null).contains("null"));
    // made in code, a coefficient that is not finite fails the same check
    let mut nan = good.clone();
    nan.channels[4].coeffs[0] = f64::NAN;
    assert!(nan.check().unwrap_err().to_string().contains("channel 4"));
    let text = std::fs::read_to_string("results/fits/ltc-compact.json").unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    for f in v["families"].as_array().unwrap() {
        let c: Compact = serde_json::from_value(f["series"].clone()).unwrap();
        assert!(c.check().is_ok() && c.coefficients() == 6 * c.p * c.p);
    }
}

/// `Compact::resized` keeps coefficient (k, l) where both are below the new degree and adds
/// zeros elsewhere: up then down gives the series back; up evaluates the same in f64 (the
/// added terms are zero); p = 0 and p above the cap are typed errors.
#[test]
fn resizing_a_series_keeps_its_coefficients_in_place() {
    let text = std::fs::read_to_string("results/fits/ltc-compact.json").unwrap();
    let v: ndfbench::results::ltc_compact::LtcCompact = serde_json::from_str(&text).unwrap();
    let c = &v.families[0].series;
    let up = c.resized(c.p + 5).unwrap();
    assert_eq!(&up.resized(c.p).unwrap(), c);
    for k in 0..200 {
        let (r, t) = (
            (k as f64 * 0.618_034).fract(),
            (k as f64 * 0.754_878).fract(),
        );
        let (a, b) = (c.eval(r, t), up.eval(r, t));
        for ch in 0..6 {
            assert!(
                (a[ch] - b[ch]).abs() <= 1e-12 * a[ch].abs().max(1.0),
                "ch {ch} at ({r}, {t})"
            );
        }
    }
    let down = c.resized(4).unwrap();
    assert_eq!(
        down.channels[2].coeffs[1 + 4 * 3],
        c.channels[2].coeffs[1 + c.p * 3]
    );
    assert!(c.resized(0).is_err());
    assert!(c.resized(ndfbench::ltc::compact::MAX_P + 1).is_err());
}

/// The compact study's polygon lights (results/fits/ltc-compact.json) are the GGX study's
/// own rows (results/fits/ltc-ggx.json: the same cells, lights and Monte Carlo truths, in
/// its order), and the full table shaded through them gives that study's LTC values
/// (computed there from the f64 cell by `ltc::polygon::check_cell`) to within the binary16
/// storage the compact study reads: so the cell, the frame and the light are the ones the
/// truth was drawn for. Each error figure is the stated estimator of its values: the mean
/// of (value − MC)² − s.e.².
#[test]
fn the_polygon_lights_are_the_ggx_studys_own() {
    let text = std::fs::read_to_string("results/fits/ltc-compact.json").unwrap();
    let v: ndfbench::results::ltc_compact::LtcCompact = serde_json::from_str(&text).unwrap();
    let f = v.families.iter().find(|f| f.table == "ltc-ggx").unwrap();
    let p = f
        .polygons
        .as_ref()
        .expect("the GGX family's polygon lights");
    let text = std::fs::read_to_string("results/fits/ltc-ggx.json").unwrap();
    let g: ndfbench::results::ltc::Ggx = serde_json::from_str(&text).unwrap();
    assert_eq!(p.truth.len(), g.polygons.len());
    for (k, ((a, th, light, mc), row)) in p.truth.iter().zip(&g.polygons).enumerate() {
        assert_eq!(
            (*a, *th, light.as_str()),
            (row.alpha, row.theta, row.light.as_str())
        );
        assert_eq!((mc.value, mc.error), (row.mc.value, row.mc.error));
        let full = p.full.values[k];
        assert!(
            (full - row.ltc_exact).abs() <= 2e-3 * row.ltc_exact.abs() + 1e-9,
            "row {k} ({light}, α {a}, θ {th}): the full table gives {full}, the GGX study {}",
            row.ltc_exact
        );
    }
    let mse = |x: &ndfbench::results::ltc_compact::PolygonFigures| {
        assert_eq!(x.values.len(), p.truth.len());
        let s: f64 = x
            .values
            .iter()
            .zip(&p.truth)
            .map(|(v, (_, _, _, t))| (v - t.value).powi(2) - t.error * t.error)
            .sum();
        s / x.values.len() as f64
    };
    for x in std::iter::once(&p.full)
        .chain(&p.rebuilt)
        .chain(&p.texture_free)
    {
        let want = mse(x);
        assert!(
            (x.mse.value - want).abs() <= 1e-12 * want.abs().max(1e-12),
            "{} vs {want}",
            x.mse.value
        );
        assert!(x.mse.error > 0.0 && x.values.iter().all(|v| v.is_finite()));
    }
    assert_eq!(p.rebuilt.len(), f.forms.len());
    assert_eq!(p.texture_free.len(), f.forms.len());
}

/// The committed report is what the report step renders from the committed result file
/// (the study's typed result and its markdown cannot drift apart).
#[test]
fn the_committed_report_is_rendered_from_the_committed_result() {
    let text = std::fs::read_to_string("results/fits/ltc-compact.json").unwrap();
    let v: ndfbench::results::ltc_compact::LtcCompact = serde_json::from_str(&text).unwrap();
    let md = ndfbench::studies::ltc_compact::report::markdown(&v);
    let committed = std::fs::read_to_string("results/ltc-compact.md").unwrap();
    assert!(
        committed == md,
        "results/ltc-compact.md is stale with respect to results/fits/ltc-compact.json: run `cargo run --release -- regen --only ltc-compact`"
    );
}

/// Both sheen families carry the polygon lights of their own study (results/fits/
/// ltc-sheen*.json's report: (α, θ°, albedo, check)): the same rows and Monte Carlo truths,
/// and the full table shaded through them gives that study's LTC values within 2 %: the
/// study shades its cell's fit, before the bilinear pass moved the cell and binary16
/// storage chose its entries (measured: up to 1.4 %); a light placed for another θ (a
/// degree taken for a radian) or another cell's entries is off by far more.
#[test]
fn the_sheen_families_carry_their_studys_polygon_lights() {
    let text = std::fs::read_to_string("results/fits/ltc-compact.json").unwrap();
    let v: ndfbench::results::ltc_compact::LtcCompact = serde_json::from_str(&text).unwrap();
    for table in ["ltc-sheen", "ltc-sheen-neubelt"] {
        let f = v.families.iter().find(|f| f.table == table).unwrap();
        let p = f
            .polygons
            .as_ref()
            .unwrap_or_else(|| panic!("{table}: no polygon lights"));
        let study: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(format!("results/fits/{table}.json")).unwrap(),
        )
        .unwrap();
        let rows = study["report"]["polygons"].as_array().unwrap();
        assert_eq!(p.truth.len(), rows.len(), "{table}");
        assert!(!rows.is_empty());
        for (k, ((a, th, light, mc), row)) in p.truth.iter().zip(rows).enumerate() {
            assert_eq!(*a, row[0].as_f64().unwrap());
            assert!((th.to_degrees() - row[1].as_f64().unwrap()).abs() <= 1e-12);
            assert_eq!(light.as_str(), row[3]["light"].as_str().unwrap());
            assert_eq!(mc.value, row[3]["mc"]["value"].as_f64().unwrap());
            let exact = row[3]["ltc_exact"].as_f64().unwrap();
            let full = p.full.values[k];
            assert!(
                (full - exact).abs() <= 2e-2 * exact.abs() + 1e-9,
                "{table} row {k} ({light}): the full table gives {full}, the sheen study {exact}"
            );
        }
        assert_eq!(p.rebuilt.len(), f.forms.len());
        assert_eq!(p.texture_free.len(), f.forms.len());
    }
}
