//! Observed order and Richardson extrapolation from three resolutions whose refinement ratios
//! need not be equal: with f(h) = f* + C·h^p, the two differences f1 − f2 and f2 − f3 fix p
//! (by bisection) and then f*. Used by the convergence case (docs/PHYSICS.md §9(d)).

/// What three resolutions say about a quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Extrapolation {
    /// Monotone convergence: the observed order p and the extrapolated value f*.
    Order { p: f64, limit: f64 },
    /// The two differences have opposite signs (or one is zero): no order.
    Oscillates,
    /// The differences do not shrink fast enough for an order in (0, [`MAX_ORDER`]]:
    /// below the smallest order (the finer difference too large, or growing), or above it.
    OutOfRange,
}

/// The largest observed order searched.
pub const MAX_ORDER: f64 = 20.0;
/// The smallest observed order searched.
const MIN_ORDER: f64 = 1e-3;

/// The extrapolation from `(h, f)` at three spacings, coarse to fine (h1 > h2 > h3 > 0).
pub fn extrapolate(h: [f64; 3], f: [f64; 3]) -> Extrapolation {
    let (d1, d2) = (f[0] - f[1], f[1] - f[2]);
    if !(h[0] > h[1] && h[1] > h[2] && h[2] > 0.0) {
        return Extrapolation::OutOfRange;
    }
    // NaN differences land here too: no order.
    if d1 * d2 <= 0.0 || (d1 * d2).is_nan() {
        return Extrapolation::Oscillates;
    }
    let want = d1 / d2;
    // (h1^p − h2^p)/(h2^p − h3^p) grows with p, from ln(h1/h2)/ln(h2/h3) at p → 0.
    let ratio = |p: f64| {
        let s = |x: f64| (x / h[2]).powf(p);
        (s(h[0]) - s(h[1])) / (s(h[1]) - 1.0)
    };
    let (mut lo, mut hi) = (MIN_ORDER, MAX_ORDER);
    if want < ratio(lo) || want > ratio(hi) {
        return Extrapolation::OutOfRange;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if ratio(mid) < want {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let p = 0.5 * (lo + hi);
    let limit = f[2] - d2 / ((h[1] / h[2]).powf(p) - 1.0);
    Extrapolation::Order { p, limit }
}

impl std::fmt::Display for Extrapolation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Extrapolation::Order { p, limit } => write!(f, "observed order {p:.2}, extrapolated {limit:.4}"),
            Extrapolation::Oscillates => write!(f, "not monotone: no order"),
            Extrapolation::OutOfRange => write!(f, "no observed order in (0, {MAX_ORDER}]"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_order_and_limit_at_unequal_ratios() {
        for (p, c) in [(1.0, 3.0), (2.0, -40.0), (0.5, 0.7)] {
            let h = [1.0 / 33.0, 1.0 / 45.0, 1.0 / 65.0];
            let f = h.map(|x: f64| 60.0 + c * x.powf(p));
            match extrapolate(h, f) {
                Extrapolation::Order { p: q, limit } => {
                    assert!((q - p).abs() < 1e-6, "order {q} for {p}");
                    assert!((limit - 60.0).abs() < 1e-6, "limit {limit}");
                }
                other => panic!("{other:?} for p = {p}"),
            }
        }
    }

    #[test]
    fn oscillation_and_growth_give_no_order() {
        let h = [0.03, 0.02, 0.01];
        assert_eq!(extrapolate(h, [1.0, 2.0, 1.5]), Extrapolation::Oscillates);
        assert_eq!(extrapolate(h, [1.0, 1.0, 1.5]), Extrapolation::Oscillates);
        // the finer difference larger than the coarser: the error grows with refinement
        assert_eq!(extrapolate(h, [1.0, 1.1, 1.5]), Extrapolation::OutOfRange);
    }
}
