use nalgebra::{DMatrix, DVector};
fn main() {
    let d: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("results/fits/multiscale-convolution.json").unwrap(),
    )
    .unwrap();
    let load = |k: &str| -> Vec<(f64, f64, f64, serde_json::Value)> {
        d[k].as_array()
            .unwrap()
            .iter()
            .map(|p| {
                (
                    p["alpha_mi"].as_f64().unwrap(),
                    p["alpha_me"].as_f64().unwrap(),
                    p["moment_unclipped"].as_f64().unwrap(),
                    p.clone(),
                )
            })
            .collect()
    };
    let (tr, ho) = (load("metric_grid"), load("metric_grid_held_out"));
    let bases: Vec<(&str, Box<dyn Fn(f64, f64) -> Vec<f64>>)> = vec![
        (
            "g,gd2,p,p2,p3,gp",
            Box::new(|x: f64, y: f64| {
                let s = x / (x + y);
                let g = 4.0 * s * (1.0 - s);
                let dd = (s - 0.5).powi(2);
                let p = x * y;
                vec![g, g * dd, p, p * p, p * p * p, g * p]
            }),
        ),
        (
            "g,gd2,gg,p,p2,p3,gp",
            Box::new(|x: f64, y: f64| {
                let s = x / (x + y);
                let g = 4.0 * s * (1.0 - s);
                let dd = (s - 0.5).powi(2);
                let p = x * y;
                vec![g, g * dd, g * g, p, p * p, p * p * p, g * p]
            }),
        ),
        (
            "g,gd2,gg,p,p2,gp,gp2,gpd2",
            Box::new(|x: f64, y: f64| {
                let s = x / (x + y);
                let g = 4.0 * s * (1.0 - s);
                let dd = (s - 0.5).powi(2);
                let p = x * y;
                vec![g, g * dd, g * g, p, p * p, g * p, g * p * p, g * p * dd]
            }),
        ),
        (
            "g-family + p via sqrt",
            Box::new(|x: f64, y: f64| {
                let s = x / (x + y);
                let g = 4.0 * s * (1.0 - s);
                let dd = (s - 0.5).powi(2);
                let p = x * y;
                let q = p.sqrt();
                vec![g, g * dd, g * g, p, p * p, g * p, g * q, q * p]
            }),
        ),
        (
            "sqrt family + g ln m",
            Box::new(|x: f64, y: f64| {
                let s = x / (x + y);
                let g = 4.0 * s * (1.0 - s);
                let dd = (s - 0.5).powi(2);
                let p = x * y;
                let q = p.sqrt();
                let l = (x.hypot(y)).ln();
                vec![g, g * dd, g * g, p, p * p, g * p, g * q, q * p, g * l]
            }),
        ),
        (
            "sqrt family + g ln m + g ln² m",
            Box::new(|x: f64, y: f64| {
                let s = x / (x + y);
                let g = 4.0 * s * (1.0 - s);
                let dd = (s - 0.5).powi(2);
                let p = x * y;
                let q = p.sqrt();
                let l = (x.hypot(y)).ln();
                vec![
                    g,
                    g * dd,
                    g * g,
                    p,
                    p * p,
                    g * p,
                    g * q,
                    q * p,
                    g * l,
                    g * l * l,
                ]
            }),
        ),
    ];
    for k in ["moment_clipped", "l2", "caps"] {
        for (name, b) in &bases {
            let rows: Vec<Vec<f64>> = tr.iter().map(|(x, y, _, _)| b(*x, *y)).collect();
            let a = DMatrix::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j]);
            let t = DVector::from_iterator(
                tr.len(),
                tr.iter()
                    .map(|(_, _, m, p)| (p[k].as_f64().unwrap() / m).ln()),
            );
            let c = a.svd(true, true).solve(&t, 1e-14).unwrap();
            let ev = |x: f64, y: f64, m: f64| {
                m * b(x, y)
                    .iter()
                    .zip(c.iter())
                    .map(|(u, v)| u * v)
                    .sum::<f64>()
                    .exp()
            };
            let err = |set: &[(f64, f64, f64, serde_json::Value)]| {
                set.iter()
                    .map(|(x, y, m, p)| (ev(*x, *y, *m) / p[k].as_f64().unwrap() - 1.0).abs())
                    .fold(0.0, f64::max)
            };
            println!("{k:15} {name:28} in {:.2e} held {:.2e}", err(&tr), err(&ho));
        }
    }
}
