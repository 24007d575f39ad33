//! Controls shared by the sweeps (`sphlab study`, `sphlab stability`): `--shard i/n` (run the
//! i-th of n disjoint parts, every n-th point in a fixed order, so an array job or a CI matrix
//! spreads one sweep over machines) and `--budget` durations (`90`, `90s`, `8m`, `1h`).

/// Part `index` of `count` disjoint parts of a sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// This part, 0 ≤ index < count.
    pub index: usize,
    /// Number of parts.
    pub count: usize,
}

impl Default for Shard {
    fn default() -> Self {
        Shard { index: 0, count: 1 }
    }
}

impl Shard {
    /// Parses `i/n` with 0 ≤ i < n; the error names `--shard` and the accepted form.
    pub fn parse(text: &str) -> Result<Shard, String> {
        text.split_once('/')
            .and_then(|(i, n)| Some((i.trim().parse::<usize>().ok()?, n.trim().parse::<usize>().ok()?)))
            .filter(|&(i, n)| n >= 1 && i < n)
            .map(|(index, count)| Shard { index, count })
            .ok_or(format!("--shard: `{text}` is not i/n with 0 ≤ i < n"))
    }

    /// True when point `k` of the sweep (in its fixed order) belongs to this part.
    pub fn owns(&self, k: usize) -> bool {
        k % self.count == self.index
    }

    /// `i/n`.
    pub fn label(&self) -> String {
        format!("{}/{}", self.index, self.count)
    }
}

/// A duration in seconds from `90`, `90s`, `8m` or `1h` (positive and finite); the error names
/// `--budget` and the accepted forms.
pub fn parse_duration(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let (num, unit) = match t.char_indices().last() {
        Some((i, 's')) => (&t[..i], 1.0),
        Some((i, 'm')) => (&t[..i], 60.0),
        Some((i, 'h')) => (&t[..i], 3600.0),
        _ => (t, 1.0),
    };
    num.trim()
        .parse::<f64>()
        .ok()
        .map(|x| x * unit)
        .filter(|s| s.is_finite() && *s > 0.0)
        .ok_or(format!("--budget: `{text}` is not a positive duration (e.g. 90, 90s, 8m, 1h)"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_are_disjoint_and_cover_the_sweep() {
        let parts: Vec<Shard> = (0..3).map(|i| Shard::parse(&format!("{i}/3")).unwrap()).collect();
        for k in 0..20 {
            assert_eq!(parts.iter().filter(|s| s.owns(k)).count(), 1, "point {k}");
        }
        for bad in ["3/3", "1", "a/2", "0/0", "-1/2"] {
            assert!(Shard::parse(bad).unwrap_err().contains("--shard"), "{bad}");
        }
    }

    #[test]
    fn durations() {
        assert_eq!(parse_duration("90").unwrap(), 90.0);
        assert_eq!(parse_duration("20s").unwrap(), 20.0);
        assert_eq!(parse_duration("8m").unwrap(), 480.0);
        assert_eq!(parse_duration("1.5h").unwrap(), 5400.0);
        for bad in ["", "0", "-3m", "xm", "inf"] {
            assert!(parse_duration(bad).unwrap_err().contains("--budget"), "{bad}");
        }
    }
}
