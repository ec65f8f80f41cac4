use ndfbench::multiscale::alpha_me::*;
fn main() {
    let train = training_alphas(400, 1e-3, 1.0);
    let ho = held_out_alphas(2000, 1e-3, 1.0);
    for k in 2..=8 {
        let c = fit_ours(k, &train).unwrap();
        let h = held_out(&ho, &|_b, y| ours_eval(&c, y));
        println!(
            "K={k} {c:?} max {:.3e} rms {:.3e} worst {:.4} endpoints {:.2e} {:.2e}",
            h.max_rel, h.rms_rel, h.worst_alpha, h.rel_at_min, h.rel_at_max
        );
    }
    let wide = held_out_alphas(2000, 1e-6, 1.0);
    let c = fit_ours(5, &train).unwrap();
    println!(
        "K=5 on [1e-6,1]: {:?}",
        held_out(&wide, &|_b, y| ours_eval(&c, y))
    );
}
