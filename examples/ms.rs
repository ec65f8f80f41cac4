use ndfbench::multiscale::overall::*;
fn main() {
    for (mi, me) in [(0.1, 0.1), (0.5, 0.3), (0.03, 0.6), (1.0, 1.0), (0.2, 0.02)] {
        let t0 = std::time::Instant::now();
        let f = fit_pair(mi, me).unwrap();
        println!(
            "{f:?} eq7 {:.4} sumsq {:.4} vmf2 {:.4} vmf1 {:.4} vmf.5 {:.4} [{:?}]",
            eq7(mi, me),
            sum_of_squares(mi, me),
            vmf(mi, me, 2.0),
            vmf(mi, me, 1.0),
            vmf(mi, me, 0.5),
            t0.elapsed()
        );
    }
}
