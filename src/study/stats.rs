//! The study's sample statistics (docs/STUDY.md §5): percentiles of the timed blocks, a
//! bootstrap 95 % interval of their median with a fixed seed (the same blocks give the same
//! interval), and the machine's load average read before and after each record.

/// Seed of the bootstrap: fixed, so the interval of a record is reproducible from its blocks.
pub const BOOTSTRAP_SEED: u64 = 0x5eed_5eed_5eed_5eed;
/// Bootstrap resamples.
pub const BOOTSTRAP_RESAMPLES: usize = 2000;

/// The q-quantile (0 ≤ q ≤ 1) of a sorted, non-empty slice, linearly interpolated between the
/// closest ranks.
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    let pos = (sorted.len() - 1) as f64 * q.clamp(0.0, 1.0);
    let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
    sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - lo as f64)
}

/// splitmix64: a small deterministic generator for the bootstrap.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

/// The percentile bootstrap 95 % interval of the median of `samples` (any order, non-empty):
/// [`BOOTSTRAP_RESAMPLES`] resamples with replacement drawn from [`BOOTSTRAP_SEED`].
pub fn bootstrap_median_ci(samples: &[f64]) -> (f64, f64) {
    let n = samples.len();
    let mut rng = SplitMix(BOOTSTRAP_SEED);
    let mut medians = Vec::with_capacity(BOOTSTRAP_RESAMPLES);
    let mut draw = vec![0.0; n];
    for _ in 0..BOOTSTRAP_RESAMPLES {
        for d in draw.iter_mut() {
            *d = samples[(rng.next() % n as u64) as usize];
        }
        draw.sort_by(f64::total_cmp);
        medians.push(percentile(&draw, 0.5));
    }
    medians.sort_by(f64::total_cmp);
    (percentile(&medians, 0.025), percentile(&medians, 0.975))
}

/// The 1-minute load average (`/proc/loadavg`), `None` where the file is missing.
pub fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg").ok()?.split_whitespace().next()?.parse().ok()
}

/// The cores this process may use.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_between_ranks() {
        let s = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(percentile(&s, 0.5), 3.0);
        assert_eq!(percentile(&s, 0.0), 1.0);
        assert_eq!(percentile(&s, 1.0), 5.0);
        assert!((percentile(&s, 0.1) - 1.4).abs() < 1e-12);
        assert!((percentile(&s, 0.9) - 4.6).abs() < 1e-12);
        assert_eq!(percentile(&[1.0, 3.0], 0.5), 2.0);
    }

    #[test]
    fn bootstrap_interval_is_deterministic_and_brackets_the_median() {
        let s = [10.0, 12.0, 11.0, 30.0, 10.5, 11.5, 9.5];
        let (lo, hi) = bootstrap_median_ci(&s);
        assert_eq!((lo, hi), bootstrap_median_ci(&s), "same blocks, same interval");
        let mut sorted = s;
        sorted.sort_by(f64::total_cmp);
        let m = percentile(&sorted, 0.5);
        assert!(lo <= m && m <= hi && lo >= 9.5 && hi <= 30.0, "[{lo}, {hi}] around {m}");
        assert!(hi < 30.0, "one outlier block does not set the median's interval: {hi}");
        assert_eq!(bootstrap_median_ci(&[4.0; 5]), (4.0, 4.0));
    }
}
