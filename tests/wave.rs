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
}
