//! The memory limits the process runs under, read from the machine: 80 % of `MemAvailable`
//! (`/proc/meminfo`), the address-space limit (`RLIMIT_AS`, the soft limit of
//! `/proc/self/limits`, minus the `VmSize` the process already maps once its worker threads hold
//! their allocator arenas), and the cgroup's memory limit minus its use (v2 `memory.max` −
//! `memory.current`, v1 `memory.limit_in_bytes` − `memory.usage_in_bytes`, over the process's
//! cgroup and every ancestor; reclaimable page cache, `inactive_file`, is not counted as use).
//! [`super::Limits`] takes the smallest of these and `--max-memory`.
//!
//! A source that is missing or unlimited (no `/proc`, `ulimit -v unlimited`, `memory.max` =
//! `max`, no memory cgroup) gives no limit. The parsers take text, so tests feed them.

use serde::Serialize;
use std::path::{Path, PathBuf};

/// Fraction of `MemAvailable` a run may plan to use.
pub const AVAILABLE_FRACTION: f64 = 0.8;
/// The `MemAvailable` source.
pub const MEM_AVAILABLE: &str = "80% of MemAvailable";
/// The source when `/proc/meminfo` cannot be read.
pub const FALLBACK: &str = "fallback 8 GiB (no /proc/meminfo)";
/// The `RLIMIT_AS` source.
pub const ADDRESS_SPACE: &str = "address-space limit (RLIMIT_AS)";
/// The cgroup source.
pub const CGROUP: &str = "cgroup memory limit";
/// The command-line source.
pub const MAX_MEMORY_FLAG: &str = "--max-memory";
/// cgroup v1 writes "no limit" as a huge number (`PAGE_COUNTER_MAX` pages); anything from here
/// on is unlimited.
const V1_UNLIMITED: u64 = 1 << 62;

/// One limit on the memory a run may use.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct MemoryLimit {
    /// Which limit ([`MEM_AVAILABLE`], [`ADDRESS_SPACE`], [`CGROUP`], [`MAX_MEMORY_FLAG`], …).
    pub source: &'static str,
    /// Bytes a run may still use under it.
    pub bytes: u64,
    /// How `bytes` was found, with the numbers (and what to change to raise it).
    pub detail: String,
}

/// Every limit the machine sets on this process now: `MemAvailable` (or the fallback), the
/// address-space limit and the cgroup limit where they exist.
pub fn machine_limits() -> Vec<MemoryLimit> {
    let mut v = Vec::new();
    match read("/proc/meminfo").as_deref().and_then(|t| meminfo_field(t, "MemAvailable:")) {
        Some(b) => v.push(MemoryLimit {
            source: MEM_AVAILABLE,
            bytes: (b as f64 * AVAILABLE_FRACTION) as u64,
            detail: format!("MemAvailable {b} bytes ({}) × {AVAILABLE_FRACTION}", fmt_bytes(b as f64)),
        }),
        None => v.push(MemoryLimit {
            source: FALLBACK,
            bytes: super::FALLBACK_MEMORY,
            detail: "/proc/meminfo has no MemAvailable".into(),
        }),
    }
    v.extend(address_space_limit());
    if let (Some(cg), Some(mi)) = (read("/proc/self/cgroup"), read("/proc/self/mountinfo")) {
        v.extend(cgroup_limit(&cg, &mi));
    }
    v
}

/// `MemAvailable` of `/proc/meminfo` in bytes.
pub fn available_memory() -> Option<u64> {
    meminfo_field(&read("/proc/meminfo")?, "MemAvailable:")
}

fn read(path: impl AsRef<Path>) -> Option<String> {
    std::fs::read_to_string(path).ok()
}

/// A `Name:  123 kB` field of `/proc/meminfo` or `/proc/self/status`, in bytes.
pub fn meminfo_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line[name.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kib * 1024)
}

/// The soft address-space limit of a `/proc/self/limits` text (`None`: unlimited).
pub fn soft_address_space(limits: &str) -> Option<u64> {
    let line = limits.lines().find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..].split_whitespace().next()?.parse().ok()
}

/// `RLIMIT_AS` minus what the process maps now. The worker threads are started first and each
/// allocates once, so that their stacks and allocator arenas (64 MiB of address space each with
/// glibc) are part of `VmSize` rather than taken later from the run's share.
pub fn address_space_limit() -> Option<MemoryLimit> {
    let soft = soft_address_space(&read("/proc/self/limits")?)?;
    rayon::broadcast(|_| drop(std::hint::black_box(Box::new(0u8))));
    let mapped = meminfo_field(&read("/proc/self/status")?, "VmSize:")?;
    Some(MemoryLimit {
        source: ADDRESS_SPACE,
        bytes: soft.saturating_sub(mapped),
        detail: format!(
            "soft limit {soft} bytes ({}) minus {mapped} bytes ({}) the process already maps; \
             raise it with `ulimit -v`",
            fmt_bytes(soft as f64),
            fmt_bytes(mapped as f64)
        ),
    })
}

/// The memory cgroup of a process: its directory and whether it is cgroup v2, from the texts
/// of `/proc/self/cgroup` and `/proc/self/mountinfo` (v2 preferred when it has the memory
/// controller, i.e. a `memory.max` file; else the v1 `memory` hierarchy).
pub fn cgroup_dir(proc_cgroup: &str, mountinfo: &str) -> Option<(PathBuf, PathBuf, bool)> {
    // (mount point, mount root) of the first mount of `fstype` whose super options satisfy `opts`.
    let mount = |fstype: &str, opts: &dyn Fn(&str) -> bool| {
        mountinfo.lines().find_map(|l| {
            let (pre, post) = l.split_once(" - ")?;
            let mut post = post.split_whitespace();
            let (ty, _src, sopts) = (post.next()?, post.next()?, post.next().unwrap_or(""));
            let pre: Vec<&str> = pre.split_whitespace().collect();
            (ty == fstype && opts(sopts) && pre.len() >= 5).then(|| (PathBuf::from(pre[4]), pre[3].to_string()))
        })
    };
    let join = |(point, root): (PathBuf, String), path: &str| {
        let rel = if root == "/" { path } else { path.strip_prefix(root.as_str()).unwrap_or("/") };
        (point.join(rel.trim_start_matches('/')), point)
    };
    let line = |want: &dyn Fn(&str, &str) -> bool| {
        proc_cgroup.lines().find_map(|l| {
            let mut f = l.splitn(3, ':');
            let (id, ctl, path) = (f.next()?, f.next()?, f.next()?);
            want(id, ctl).then(|| path.to_string())
        })
    };
    if let (Some(path), Some(m)) = (line(&|id, ctl| id == "0" && ctl.is_empty()), mount("cgroup2", &|_| true)) {
        let (dir, point) = join(m, &path);
        if dir.join("memory.max").exists() || ancestors(&dir, &point).any(|d| d.join("memory.max").exists()) {
            return Some((dir, point, true));
        }
    }
    let path = line(&|_, ctl| ctl.split(',').any(|c| c == "memory"))?;
    let m = mount("cgroup", &|o| o.split(',').any(|c| c == "memory"))?;
    let (dir, point) = join(m, &path);
    Some((dir, point, false))
}

/// `dir` and its parents up to and including `top`.
fn ancestors<'a>(dir: &'a Path, top: &'a Path) -> impl Iterator<Item = &'a Path> {
    dir.ancestors().take_while(move |d| d.starts_with(top))
}

/// A number of a cgroup file (`None`: missing, `max`, or v1's unlimited).
fn cgroup_number(path: &Path) -> Option<u64> {
    let v: u64 = read(path)?.trim().parse().ok()?;
    (v < V1_UNLIMITED).then_some(v)
}

/// The tightest cgroup limit over the process's memory cgroup and its ancestors: limit minus
/// use, use without the reclaimable `inactive_file` page cache of `memory.stat`.
pub fn cgroup_limit(proc_cgroup: &str, mountinfo: &str) -> Option<MemoryLimit> {
    let (dir, point, v2) = cgroup_dir(proc_cgroup, mountinfo)?;
    let (max_f, cur_f, cache) = if v2 {
        ("memory.max", "memory.current", "inactive_file")
    } else {
        ("memory.limit_in_bytes", "memory.usage_in_bytes", "total_inactive_file")
    };
    let mut best: Option<MemoryLimit> = None;
    for d in ancestors(&dir, &point) {
        let Some(max) = cgroup_number(&d.join(max_f)) else { continue };
        let current = cgroup_number(&d.join(cur_f)).unwrap_or(0);
        let inactive = read(d.join("memory.stat"))
            .and_then(|s| s.lines().find_map(|l| l.strip_prefix(cache)?.strip_prefix(' ')?.trim().parse::<u64>().ok()))
            .unwrap_or(0);
        let used = current.saturating_sub(inactive);
        let bytes = max.saturating_sub(used);
        if best.as_ref().is_none_or(|b| bytes < b.bytes) {
            best = Some(MemoryLimit {
                source: CGROUP,
                bytes,
                detail: format!(
                    "{max_f} {max} bytes ({}) of {} minus {used} bytes ({}) in use; a container's or \
                     job's memory limit (e.g. Slurm --mem)",
                    fmt_bytes(max as f64),
                    d.display(),
                    fmt_bytes(used as f64)
                ),
            });
        }
    }
    best
}

/// Formats bytes for people: `1.50 GiB`.
pub fn fmt_bytes(b: f64) -> String {
    const U: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut v = b;
    let mut i = 0;
    while v >= 1024.0 && i + 1 < U.len() {
        v /= 1024.0;
        i += 1;
    }
    if i == 0 {
        format!("{v:.0} B")
    } else if v < 1e6 {
        format!("{v:.2} {}", U[i])
    } else {
        format!("{b:.3e} B")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proc_texts_parse() {
        let meminfo = "MemTotal:       24000000 kB\nMemAvailable:    1000 kB\n";
        assert_eq!(meminfo_field(meminfo, "MemAvailable:"), Some(1024000));
        assert_eq!(meminfo_field("VmPeak:  10 kB\nVmSize:\t  218452 kB\n", "VmSize:"), Some(218452 * 1024));
        let limits = "Limit                     Soft Limit           Hard Limit           Units     \n\
                      Max address space         6144000000           unlimited            bytes     \n";
        assert_eq!(soft_address_space(limits), Some(6144000000));
        assert_eq!(soft_address_space(&limits.replace("6144000000", "unlimited")), None);
    }

    /// A fake cgroup tree under a temporary directory, mounted (per the mountinfo text) there.
    fn tree(files: &[(&str, &str)]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().expect("tempdir");
        for (path, text) in files {
            let p = dir.path().join(path);
            std::fs::create_dir_all(p.parent().expect("parent")).expect("mkdir");
            std::fs::write(p, text).expect("write");
        }
        dir
    }

    #[test]
    fn cgroup_v2_takes_the_tightest_ancestor_and_skips_max() {
        let t = tree(&[
            ("memory.stat", "anon 1\n"),
            ("job/memory.max", "8000\n"),
            ("job/memory.current", "3000\n"),
            ("job/memory.stat", "anon 5\ninactive_file 1000\nactive_file 7\n"),
            ("job/step/memory.max", "max\n"),
            ("job/step/memory.current", "2500\n"),
        ]);
        let mi = format!("41 31 0:38 / {} rw,relatime - cgroup2 cgroup2 rw\n", t.path().display());
        let l = cgroup_limit("0::/job/step\n", &mi).expect("a limit");
        // 8000 − (3000 − 1000 reclaimable) at `job`; `step` has no limit of its own.
        assert_eq!((l.source, l.bytes), (CGROUP, 6000));
        assert!(l.detail.contains("memory.max 8000") && l.detail.contains("job"), "{}", l.detail);
        // No limit anywhere: none.
        let free = tree(&[("a/memory.max", "max\n"), ("a/memory.current", "10\n")]);
        let mi = format!("41 31 0:38 / {} rw - cgroup2 cgroup2 rw\n", free.path().display());
        assert_eq!(cgroup_limit("0::/a\n", &mi), None);
    }

    #[test]
    fn cgroup_v1_memory_hierarchy_and_its_unlimited_value() {
        let t = tree(&[
            ("memory.limit_in_bytes", "9223372036854771712\n"),
            ("batch/memory.limit_in_bytes", "4096\n"),
            ("batch/memory.usage_in_bytes", "1096\n"),
        ]);
        let mi = format!(
            "31 23 0:28 / /sys/fs/cgroup rw - tmpfs tmpfs rw\n35 31 0:32 / {} rw - cgroup cgroup rw,memory\n\
             41 31 0:38 / /nonexistent/unified rw - cgroup2 cgroup2 rw\n",
            t.path().display()
        );
        let cg = "5:devices:/\n4:memory:/batch\n0::/\n";
        assert_eq!(cgroup_limit(cg, &mi).map(|l| l.bytes), Some(3000));
        let root_only = tree(&[("memory.limit_in_bytes", "9223372036854771712\n")]);
        let mi = format!("35 31 0:32 / {} rw - cgroup cgroup rw,memory\n", root_only.path().display());
        assert_eq!(cgroup_limit("4:memory:/\n", &mi), None);
        // No memory controller at all.
        assert_eq!(cgroup_limit("1:cpu:/\n", "32 31 0:29 / /sys/fs/cgroup/cpu rw - cgroup cgroup rw,cpu\n"), None);
    }
}
