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

/// Clock ticks per second of `/proc/stat` and `/proc/<pid>/stat` (Linux's USER_HZ, 100 on every
/// architecture sphlab builds for).
const USER_HZ: f64 = 100.0;

/// CPU time used so far by the whole machine (busy, not idle or waiting for I/O) and by this
/// process (all its threads: a GPU driver that emulates the device on the CPU runs in them),
/// in seconds, with the wall clock of the reading.
#[derive(Clone, Copy, Debug)]
pub struct CpuUse {
    machine_busy_s: f64,
    own_s: f64,
    at: std::time::Instant,
}

impl CpuUse {
    /// Reads `/proc/stat` and `/proc/self/stat`; `None` where they are missing.
    pub fn now() -> Option<CpuUse> {
        let stat = std::fs::read_to_string("/proc/stat").ok()?;
        let own = std::fs::read_to_string("/proc/self/stat").ok()?;
        Some(CpuUse { machine_busy_s: machine_busy(&stat)?, own_s: own_cpu(&own)?, at: std::time::Instant::now() })
    }

    /// Cores' worth of CPU that other processes used on average between `earlier` and `self`.
    pub fn others_since(&self, earlier: &CpuUse) -> f64 {
        let wall = self.at.duration_since(earlier.at).as_secs_f64().max(1e-9);
        ((self.machine_busy_s - earlier.machine_busy_s) - (self.own_s - earlier.own_s)).max(0.0) / wall
    }
}

/// Busy CPU seconds of the machine from `/proc/stat`'s `cpu` line: user, nice, system, irq,
/// softirq and steal (idle and iowait left out; guest time is inside user).
fn machine_busy(stat: &str) -> Option<f64> {
    let v: Vec<f64> = stat.lines().next()?.split_whitespace().skip(1).map(|x| x.parse().unwrap_or(0.0)).collect();
    let at = |k: usize| v.get(k).copied().unwrap_or(0.0);
    Some((at(0) + at(1) + at(2) + at(5) + at(6) + at(7)) / USER_HZ)
}

/// This process's CPU seconds (utime + stime, fields 14 and 15) from `/proc/self/stat`, read
/// after the command name's closing parenthesis (a name may hold spaces).
fn own_cpu(stat: &str) -> Option<f64> {
    let rest = &stat[stat.rfind(')')? + 1..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // After ")" come field 3 (state) onwards: utime is field 14, so index 11 here.
    Some((f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?) / USER_HZ)
}

/// What the machine was doing while one record was measured: the load average before and
/// after, and the other processes' CPU use in between.
pub struct Watch {
    load_before: Option<f64>,
    cpu_before: Option<CpuUse>,
}

impl Watch {
    /// Starts watching.
    pub fn start() -> Watch {
        Watch { load_before: load_average(), cpu_before: CpuUse::now() }
    }
    /// ((load before, load after), cores' worth of other processes' CPU in between).
    pub fn stop(self) -> ((Option<f64>, Option<f64>), Option<f64>) {
        let others = self.cpu_before.zip(CpuUse::now()).map(|(a, b)| b.others_since(&a));
        ((self.load_before, load_average()), others)
    }
}

/// The cores this process may use.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

#[cfg(test)]
mod tests {
    #[test]
    fn cpu_use_parses_proc_and_subtracts_the_process_own_time() {
        let stat = "cpu  100 5 50 1000 20 3 2 1 0 0\ncpu0 50 2 25 500 10 1 1 0 0 0\n";
        assert_eq!(machine_busy(stat), Some(1.61));
        let own = "4242 (sphlab (x)) R 1 2 3 4 5 6 7 8 9 10 70 30 0 0 20 0 9 0 100 0 0";
        assert_eq!(own_cpu(own), Some(1.0));
        let t0 = std::time::Instant::now();
        let a = CpuUse { machine_busy_s: 10.0, own_s: 4.0, at: t0 };
        let b = CpuUse { machine_busy_s: 13.0, own_s: 5.0, at: t0 + std::time::Duration::from_secs(2) };
        assert!((b.others_since(&a) - 1.0).abs() < 1e-12, "(3 − 1) s of others' CPU over 2 s");
        assert!(CpuUse::now().is_some(), "/proc/stat and /proc/self/stat are read on Linux");
    }

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
