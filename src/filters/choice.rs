//! The automatic choice among approximations by their measured error and cost (what
//! `scene` does with `auto`): within an error budget, a cost is only "cheaper" where
//! criterion can tell it from the cheapest's, so options whose 95 % cost intervals meet
//! are a tie, broken by the smaller error.

/// One option of an automatic choice: its measured error (mean, s.e.) and its cost (mean
/// and 95 % interval), each where measured.
#[derive(Clone, Copy, Debug)]
pub struct Candidate {
    pub error: Option<(f64, f64)>,
    pub cost: Option<(f64, (f64, f64))>,
}

/// The automatic choice among `c`: of the options whose error mean + s.e. is within
/// `budget`, the cheapest by mean cost, together with every one whose cost interval
/// reaches down to the cheapest's upper bound (a cost criterion cannot tell from it);
/// of those, the smallest error mean (then the smaller mean cost, then the first). An
/// option without a measured cost is chosen only when none has one. `None` when no
/// option meets the budget.
pub fn pick(c: &[Candidate], budget: f64) -> Option<usize> {
    let ok: Vec<usize> = (0..c.len())
        .filter(|&k| c[k].error.is_some_and(|(m, se)| m + se <= budget))
        .collect();
    let mean = |k: usize| c[k].cost.map_or(f64::INFINITY, |x| x.0);
    let err = |k: usize| c[k].error.map_or(f64::INFINITY, |x| x.0);
    let cheapest = ok
        .iter()
        .copied()
        .min_by(|&a, &b| mean(a).total_cmp(&mean(b)))?;
    let reach = c[cheapest].cost.map_or(f64::INFINITY, |x| x.1 .1);
    ok.iter()
        .copied()
        .filter(|&k| k == cheapest || c[k].cost.map_or(reach.is_infinite(), |x| x.1 .0 <= reach))
        .min_by(|&a, &b| {
            err(a)
                .total_cmp(&err(b))
                .then(mean(a).total_cmp(&mean(b)))
                .then(a.cmp(&b))
        })
}

#[cfg(test)]
mod tests {
    use super::{pick, Candidate};

    fn c(err: f64, cost: f64, lo: f64, hi: f64) -> Candidate {
        Candidate {
            error: Some((err, 0.0)),
            cost: Some((cost, (lo, hi))),
        }
    }

    /// A cost that criterion cannot tell from the cheapest's does not decide: the more
    /// accurate option wins. One measurably dearer does not, whatever its error.
    #[test]
    fn costs_within_their_intervals_are_a_tie_broken_by_error() {
        // 1.00 ns (0.98–1.02) and 1.01 ns (0.99–1.03): the second is more accurate
        let tied = [c(0.20, 1.00, 0.98, 1.02), c(0.10, 1.01, 0.99, 1.03)];
        assert_eq!(pick(&tied, 0.5), Some(1));
        // 1.30 ns (1.25–1.35) is measurably dearer than 1.00 (0.98–1.02)
        let apart = [c(0.20, 1.00, 0.98, 1.02), c(0.10, 1.30, 1.25, 1.35)];
        assert_eq!(pick(&apart, 0.5), Some(0));
        // points without intervals: the cheaper, as before
        let points = [c(0.20, 1.00, 1.00, 1.00), c(0.10, 1.01, 1.01, 1.01)];
        assert_eq!(pick(&points, 0.5), Some(0));
    }

    /// The budget filters first (mean + s.e.); nothing within it is `None`; an option
    /// with no measured cost is taken only when nothing within budget has one.
    #[test]
    fn the_budget_and_missing_measurements() {
        let mut over = c(0.10, 0.5, 0.5, 0.5);
        over.error = Some((0.29, 0.02));
        let opts = [over, c(0.25, 2.0, 1.9, 2.1)];
        assert_eq!(pick(&opts, 0.3), Some(1));
        assert_eq!(pick(&opts, 0.2), None);
        let unmeasured = Candidate {
            error: Some((0.05, 0.0)),
            cost: None,
        };
        assert_eq!(pick(&[unmeasured, c(0.2, 3.0, 2.0, 4.0)], 0.5), Some(1));
        assert_eq!(pick(&[unmeasured], 0.5), Some(0));
        // nothing measured: the most accurate
        let rougher = Candidate {
            error: Some((0.15, 0.0)),
            cost: None,
        };
        assert_eq!(pick(&[rougher, unmeasured], 0.5), Some(1));
        let no_error = Candidate {
            error: None,
            cost: Some((0.1, (0.1, 0.1))),
        };
        assert_eq!(pick(&[no_error], 0.5), None);
    }
}
