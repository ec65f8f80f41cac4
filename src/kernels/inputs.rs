//! Deterministic benchmark and accuracy inputs of the kernels (fixed seed, so every bench
//! and accuracy figure is reproducible).

/// Deterministic benchmark / accuracy inputs: 31 columns of `n` pixels — l (3), v (3),
/// α (log-uniform in [1e-3, 1]), Δn_u (3), Δn_v (3), y_me, y_mi (of α log-uniform in
/// [1e-3, 1]), then an LTC M⁻¹ (a, b, c, d) (15–18) and a quad light's 12 vertex
/// coordinates (19–30) above the horizon. Directions are unit and above the horizon.
pub struct BenchInputs {
    pub cols: Vec<Vec<f32>>,
}

pub fn bench_inputs(n: usize) -> BenchInputs {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut cols = vec![Vec::with_capacity(n); 39];
    let dir = |rng: &mut rand_chacha::ChaCha8Rng| {
        let t = rng.random::<f64>() * 1.5;
        let p = rng.random::<f64>() * std::f64::consts::TAU;
        [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()]
    };
    for _ in 0..n {
        let l = dir(&mut rng);
        let v = dir(&mut rng);
        for k in 0..3 {
            cols[k].push(l[k] as f32);
            cols[3 + k].push(v[k] as f32);
        }
        cols[6].push(10f64.powf(-3.0 * rng.random::<f64>()) as f32);
        for k in 0..6 {
            cols[7 + k].push(((rng.random::<f64>() - 0.5) * 0.4) as f32);
        }
        let y = |rng: &mut rand_chacha::ChaCha8Rng| {
            crate::multiscale::mrl::mrl_pair(10f64.powf(-3.0 * rng.random::<f64>())).1 as f32
        };
        cols[13].push(y(&mut rng));
        cols[14].push(y(&mut rng));
        // an LTC inverse like the table's: a, d > 0, b ≤ 0, c ≥ 0
        let al = 10f64.powf(-2.0 * rng.random::<f64>());
        cols[15].push((1.0 / al) as f32 * 0.5);
        cols[16].push(-(rng.random::<f64>() * 0.2 / al) as f32);
        cols[17].push((rng.random::<f64>() * 0.5) as f32);
        cols[18].push(1.0);
        // a quad: centre above the horizon, random size and orientation
        let cx = (rng.random::<f64>() - 0.5) * 2.0;
        let cy = (rng.random::<f64>() - 0.5) * 2.0;
        let cz = 0.5 + rng.random::<f64>();
        let (hu, hw) = (
            0.1 + rng.random::<f64>() * 0.5,
            0.1 + rng.random::<f64>() * 0.5,
        );
        let corners = [(-hu, -hw), (hu, -hw), (hu, hw), (-hu, hw)];
        for (k, (du, dw)) in corners.iter().enumerate() {
            cols[19 + 3 * k].push((cx + du) as f32);
            cols[20 + 3 * k].push((cy + dw) as f32);
            cols[21 + 3 * k].push(cz as f32);
        }
        // LEADR slope statistics (31–35) and a view (36–38)
        cols[31].push(((rng.random::<f64>() - 0.5) * 0.6) as f32);
        cols[32].push(((rng.random::<f64>() - 0.5) * 0.6) as f32);
        cols[33].push((0.05 + 0.45 * rng.random::<f64>()) as f32);
        cols[34].push((0.05 + 0.45 * rng.random::<f64>()) as f32);
        cols[35].push(((rng.random::<f64>() - 0.5) * 1.2) as f32);
        let vv = dir(&mut rng);
        for k in 0..3 {
            cols[36 + k].push(vv[k] as f32);
        }
    }
    BenchInputs { cols }
}
