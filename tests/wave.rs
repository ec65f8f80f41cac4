//! Wave-optics NDF images (seed 002 Eq 3–4): the FFT equals the direct sum, the energy is
//! the window's (Parseval), the image tends to the geometric slope distribution as the
//! wavelength shrinks, and colour tends to neutral for a λ-independent surface.

use ndfbench::tensor::wave::{
    bin, energy, gndf_direct, gndf_fft, slope_image, to_rgb, tv_distance, wave_image, Footprint,
    Waves, WAVELENGTHS,
};

fn surface() -> Waves {
    Waves::new(16, 4, 32.0, 0.15, 9).unwrap()
}

#[test]
fn the_fft_equals_the_direct_sum() {
    let hf = surface().sample(256); // dx = 0.125 µm
    for (lambda, sigma_c, u) in [(0.5, 1.0, (3.3, 7.9)), (0.7, 1.9, (20.0, 1.0))] {
        let g = gndf_fft(&hf, u, sigma_c, lambda, 128).unwrap();
        let peak = g.values.iter().cloned().fold(0.0, f64::max);
        let nodes: Vec<(i64, i64)> = vec![(0, 0), (3, -5), (-64, 63), (17, 2), (-9, -30)];
        let psi: Vec<(f64, f64)> = nodes
            .iter()
            .map(|&(a, b)| (a as f64 * g.dpsi, b as f64 * g.dpsi))
            .collect();
        let direct = gndf_direct(&hf, u, sigma_c, lambda, 128, &psi).unwrap();
        for (&(a, b), d) in nodes.iter().zip(direct) {
            let v = g.values[((b + 64) * 128 + a + 64) as usize];
            assert!(
                (v - d).abs() <= 1e-10 * peak,
                "λ {lambda}, node ({a}, {b}): FFT {v}, direct {d}"
            );
        }
    }
}

#[test]
fn the_energy_is_the_windows_by_parseval() {
    for sigma_c in [0.8, 1.5, 3.0] {
        for lambda in [0.42, 0.7] {
            let n = 512;
            let hf = surface().sample(n); // dx = 0.0625 µm
            let m = (8.0 * sigma_c / hf.dx).ceil().max(8.0) as usize;
            let m = m.next_power_of_two();
            let g = gndf_fft(&hf, (5.0, 11.0), sigma_c, lambda, m).unwrap();
            let (lhs, rhs) = energy(&g, &hf, sigma_c, (5.0, 11.0)).unwrap();
            assert!(
                (lhs - rhs).abs() <= 1e-12 * rhs,
                "σ_c {sigma_c}, λ {lambda}: {lhs} vs {rhs}"
            );
            // ∫ G_c² ds = π σ_c² = A_c: the truncated ±4σ_c window misses ~3e-8 of it
            assert!(
                (rhs - 1.0).abs() <= 1e-6,
                "σ_c {sigma_c}: window energy {rhs}"
            );
        }
    }
}

#[test]
fn the_image_tends_to_the_geometric_slope_distribution() {
    let w = surface();
    let fp = Footprint {
        x: (10.0, 6.0),
        sigma_p: 2.0,
        step: 2.0,
    };
    let (sigma_c, res) = (2.0, 64);
    let geo = slope_image(&w, &fp, sigma_c, 0.02, res).unwrap();
    let geo2 = slope_image(&w, &fp, sigma_c, 0.04, res).unwrap();
    let quad = tv_distance(&geo, &geo2, res);
    let mut tv = Vec::new();
    for lambda in [0.8, 0.4, 0.2] {
        let n = (w.period / (lambda / 4.0)).ceil() as usize;
        let hf = w.sample(n.next_power_of_two());
        let m = ((8.0 * sigma_c / hf.dx).ceil() as usize).next_power_of_two();
        let img = wave_image(&hf, &fp, sigma_c, lambda, m, res).unwrap();
        tv.push((lambda, tv_distance(&img, &geo, res)));
    }
    eprintln!("TV against the slope image: {tv:?}; quadrature {quad:.2e}");
    assert!(quad < 0.01, "the slope image is not converged: {quad}");
    assert!(tv.windows(2).all(|p| p[1].1 < p[0].1), "{tv:?}");
    assert!(tv[2].1 < 0.5 * tv[0].1, "{tv:?}");
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
