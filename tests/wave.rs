//! Wave-optics NDF images (seed 002 Eq 3–4): colour tends to neutral for a λ-independent
//! surface, and bad input is a typed error. The FFT, Parseval and geometric-limit
//! identities are proofs (tests/proofs.rs::wave_*).

use ndfbench::tensor::wave::{
    bin, gndf_direct, gndf_fft, slope_image, to_rgb, wave_image, Footprint, Waves, WAVELENGTHS,
};

fn surface() -> Waves {
    Waves::new(16, 4, 32.0, 0.15, 9).unwrap()
}

#[test]
fn colour_is_neutral_for_a_flat_spectrum_and_tends_to_it_in_the_limit() {
    let flat = vec![vec![0.25, 1.0, 3.0]; 8];
    let [r, g, b] = to_rgb(&flat).unwrap();
    for p in 0..3 {
        assert!(
            (r[p] - flat[0][p]).abs() < 1e-12
                && (g[p] - r[p]).abs() < 1e-12
                && (b[p] - r[p]).abs() < 1e-12
        );
    }
    // the same surface with features f times larger is the wavelength divided by f
    let chroma = |f: f64| -> f64 {
        let w = surface().magnified(f);
        let (sigma_c, res) = (1.0 * f, 32);
        let hf = w.sample(((w.period / 0.1).ceil() as usize).next_power_of_two());
        let m = ((8.0 * sigma_c / hf.dx).ceil() as usize).next_power_of_two();
        let spectral: Vec<Vec<f64>> = WAVELENGTHS
            .iter()
            .map(|&l| {
                bin(
                    &gndf_fft(&hf, (4.0 * f, 4.0 * f), sigma_c, l, m).unwrap(),
                    res,
                )
                .unwrap()
            })
            .collect();
        let [r, g, b] = to_rgb(&spectral).unwrap();
        let (mut spread, mut mean) = (0.0, 0.0);
        for p in 0..r.len() {
            let (hi, lo) = (r[p].max(g[p]).max(b[p]), r[p].min(g[p]).min(b[p]));
            spread += hi - lo;
            mean += (r[p] + g[p] + b[p]) / 3.0;
        }
        spread / mean
    };
    let (c1, c4) = (chroma(1.0), chroma(4.0));
    eprintln!("chroma: f = 1 {c1:.4}, f = 4 {c4:.4}");
    assert!(c4 < 0.5 * c1, "chroma {c1} → {c4}");
}

#[test]
fn bad_input_is_a_typed_error() {
    let hf = surface().sample(64); // dx = 0.5 µm
    let fp = Footprint {
        x: (4.0, 4.0),
        sigma_p: 1.0,
        step: 1.0,
    };
    for lambda in [0.0, -0.5, f64::NAN, f64::INFINITY] {
        assert!(
            gndf_fft(&hf, (1.0, 1.0), 1.0, lambda, 32).is_err(),
            "λ {lambda}"
        );
        assert!(gndf_direct(&hf, (1.0, 1.0), 1.0, lambda, 32, &[(0.0, 0.0)]).is_err());
    }
    for sigma_c in [0.0, -1.0, f64::NAN] {
        assert!(
            gndf_fft(&hf, (1.0, 1.0), sigma_c, 0.5, 32).is_err(),
            "σ_c {sigma_c}"
        );
    }
    // a patch that does not cover ±4σ_c, one larger than the field, one not a power of two
    assert!(gndf_fft(&hf, (1.0, 1.0), 3.0, 0.5, 16).is_err());
    assert!(gndf_fft(&hf, (1.0, 1.0), 1.0, 0.5, 128).is_err());
    assert!(gndf_fft(&hf, (1.0, 1.0), 1.0, 0.5, 24).is_err());
    // a ψ grid that does not reach the image edge (dx = 0.5 > λ/4)
    let g = gndf_fft(&hf, (1.0, 1.0), 1.0, 0.5, 32).unwrap();
    assert!(bin(&g, 16).is_err());
    assert!(wave_image(&hf, &fp, 1.0, 0.5, 32, 16).is_err());
    // footprints and surfaces
    for (sp, st) in [(0.0, 1.0), (1.0, 0.0), (f64::NAN, 1.0), (100.0, 1.0)] {
        let f = Footprint {
            x: (0.0, 0.0),
            sigma_p: sp,
            step: st,
        };
        assert!(f.centres().is_err(), "σ_P {sp}, step {st}");
    }
    assert!(slope_image(&surface(), &fp, 1.0, 0.0, 16).is_err());
    assert!(Waves::new(0, 4, 32.0, 0.1, 1).is_err());
    assert!(Waves::new(4, 4, f64::NAN, 0.1, 1).is_err());
    assert!(Waves::new(4, 4, 32.0, -0.1, 1).is_err());
    assert!(to_rgb(&vec![vec![1.0]; 7]).is_err());
    // a centre that is not a number, a grid spacing of 0: never a silent NaN image
    assert!(gndf_fft(&hf, (f64::NAN, 1.0), 1.0, 0.5, 32).is_err());
    let flat = ndfbench::tensor::wave::HeightField {
        n: 64,
        dx: 0.0,
        h: vec![0.0; 64 * 64],
    };
    assert!(gndf_fft(&flat, (1.0, 1.0), 1.0, 0.5, 32).is_err());
    let nan_fp = Footprint {
        x: (f64::NAN, 0.0),
        sigma_p: 1.0,
        step: 1.0,
    };
    assert!(nan_fp.centres().is_err());
    assert!(slope_image(&surface(), &nan_fp, 1.0, 0.1, 16).is_err());
    // a height field past 4096² is refused before it is allocated
    use ndfbench::tensor::wave::{field_side, sampled_for};
    assert_eq!(field_side(32.0, 0.1).unwrap(), 2048);
    for (period, lambda) in [(512.0, 0.05), (32.0, 0.0), (32.0, f64::NAN), (1e300, 0.5)] {
        assert!(field_side(period, lambda).is_err(), "{period}, {lambda}");
    }
    assert!(sampled_for(&surface().magnified(8.0), 0.05, 1.0).is_err());
}

#[test]
fn an_absurd_spec_is_refused_before_anything_runs() {
    let text = std::fs::read_to_string("fits/tensor-wave.toml").unwrap();
    let study = ndfbench::studies::find("tensor-wave").unwrap();
    let ok = ndfbench::fit::spec::FitSpec::parse(&text, "fits/tensor-wave.toml").unwrap();
    assert!(study.check(&ok).is_ok());
    for (from, to) in [
        ("period = 32.0 ", "period = 512.0 "),
        ("lambdas = [0.8, 0.4, 0.2, 0.1]", "lambdas = [0.8, 0.01]"),
        (
            "magnifications = [1.0, 2.0, 4.0]",
            "magnifications = [1.0, 1e12]",
        ),
        ("sigma_c = 2.0 ", "sigma_c = nan "),
        ("res = 64 ", "res = 0 "),
    ] {
        assert!(text.contains(from), "{from}");
        let bad = text.replacen(from, to, 1);
        let refused = ndfbench::fit::spec::FitSpec::parse(&bad, "bad.toml")
            .map_or(true, |spec| study.check(&spec).is_err());
        assert!(refused, "{to} was accepted");
    }
}
