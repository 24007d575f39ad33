//! Realisations: the one convention for runs repeated from a jittered lattice (every particle
//! moved by up to [`JITTER`]·Δx, `domain.jitter`, seeds [`SEEDS`]; the run's id or folder gains
//! [`suffix`]) and the statistics of their scatter, shared by the convergence case, the
//! capillary wave's resolution study and the Young sweep's rows.

/// The lattice jitter of the realisations, as a fraction of Δx.
pub const JITTER: f64 = 0.05;
/// The realisations' seeds.
pub const SEEDS: [u64; 3] = [1, 2, 3];

/// The id or folder suffix of realisation `seed`: `-jitter0.05-seed<k>`.
pub fn suffix(seed: u64) -> String {
    format!("-jitter{JITTER}-seed{seed}")
}

/// The overrides of realisation `seed`.
pub fn sets(seed: u64) -> [String; 2] {
    [format!("domain.jitter={JITTER}"), format!("domain.seed={seed}")]
}

/// Mean, sample standard deviation (NaN for one value) and count.
pub fn stats(v: &[f64]) -> (f64, f64, usize) {
    let n = v.len();
    let m = v.iter().sum::<f64>() / n as f64;
    let s = if n > 1 { (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt() } else { f64::NAN };
    (m, s, n)
}

/// The pooled sample standard deviation over the groups with two or more values (None when
/// none has).
pub fn pooled_sd<'a>(groups: impl IntoIterator<Item = &'a [f64]>) -> Option<f64> {
    let (mut ss, mut dof) = (0.0, 0usize);
    for g in groups.into_iter().filter(|g| g.len() > 1) {
        let (m, _, n) = stats(g);
        ss += g.iter().map(|x| (x - m).powi(2)).sum::<f64>();
        dof += n - 1;
    }
    (dof > 0).then(|| (ss / dof as f64).sqrt())
}

/// The standard error of a mean of group means, group `g` the mean of `counts[g]` values that
/// scatter with sample sd `sd`: `sd·√(Σ 1/n_g) / G`.
pub fn mean_of_means_se(sd: f64, counts: &[usize]) -> f64 {
    sd * counts.iter().map(|&n| 1.0 / n as f64).sum::<f64>().sqrt() / counts.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pooled_sd_weights_groups_by_their_degrees_of_freedom() {
        let (m, s, n) = stats(&[1.0, 2.0, 3.0]);
        assert_eq!((m, s, n), (2.0, 1.0, 3));
        assert!(stats(&[4.0]).1.is_nan());
        // ss 2 (dof 2) and 8 (dof 1), a single value left out: sqrt(10 / 3)
        let g: [&[f64]; 3] = [&[1.0, 2.0, 3.0], &[0.0, 4.0], &[7.0]];
        assert!((pooled_sd(g).unwrap() - (10.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!(pooled_sd([&[7.0][..]]), None);
        assert_eq!(suffix(2), "-jitter0.05-seed2");
        // Two starts of 3 runs each, sd 0.6: 0.6/√6; of 2 and 4 runs: 0.6·√(3/4)/2.
        assert!((mean_of_means_se(0.6, &[3, 3]) - 0.6 / 6f64.sqrt()).abs() < 1e-12);
        assert!((mean_of_means_se(0.6, &[2, 4]) - 0.6 * 0.75f64.sqrt() / 2.0).abs() < 1e-12);
    }
}
