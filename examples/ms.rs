use ndfbench::integrate::quad::Tol;
use ndfbench::multiscale::convolution::*;
use ndfbench::multiscale::mrl::mrl;
fn main() {
    for (me, mi) in [
        (0.5, 0.3),
        (0.1, 0.05),
        (1.0, 1.0),
        (0.01, 0.5),
        (0.5, 0.01),
    ] {
        let t0 = std::time::Instant::now();
        let c = Convolution::new(me, mi).unwrap();
        let m = c.moments_quad(Tol::new(1e-9, 1e-9, 5_000_000));
        let (lb, mu, mc) = c.moments_mc(1 << 18, 3);
        println!("me={me} mi={mi}: total {} below {} mrl {} prod {:.12} clipped {:.8} | MC below {} mrl {} clipped {} [{:?}]", m.mass_total, m.mass_below, m.mrl_unclipped, mrl(me) * mrl(mi), m.mrl_clipped, lb, mu, mc, t0.elapsed());
    }
}
