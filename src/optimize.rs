//! One-dimensional minimisation shared by the fits and the models: a grid scan for the
//! bracket, then Brent's method (argmin) inside it.

/// Minimise a 1D function: evaluate it on `xs` (sorted), then refine with Brent's method
/// (argmin) inside the bracket of the best grid point. `tol` = (eps, t) of Brent.
pub fn scan_brent(f: &dyn Fn(f64) -> f64, xs: &[f64], tol: (f64, f64), max_iters: u64) -> f64 {
    use argmin::core::{CostFunction, Executor, State};
    use argmin::solver::brent::BrentOpt;
    struct C<'a>(&'a dyn Fn(f64) -> f64);
    impl CostFunction for C<'_> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, x: &f64) -> std::result::Result<f64, argmin::core::Error> {
            Ok((self.0)(*x))
        }
    }
    let (mut bi, mut bv) = (0, f64::INFINITY);
    for (i, &x) in xs.iter().enumerate() {
        let v = f(x);
        if v < bv {
            bv = v;
            bi = i;
        }
    }
    let (a, b) = (xs[bi.saturating_sub(1)], xs[(bi + 1).min(xs.len() - 1)]);
    Executor::new(C(f), BrentOpt::new(a, b).set_tolerance(tol.0, tol.1))
        .configure(|s| s.max_iters(max_iters))
        .run()
        .ok()
        .and_then(|r| r.state().get_best_param().copied())
        .unwrap_or(xs[bi])
}
