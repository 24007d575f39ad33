//! Neighbour searches (`core/src/neighbours/`): `direct`, `cells` and `tracking` must give identical
//! `NeighbourList`s (offsets and packed `(j, image)` entries, same order), equal to a brute-force
//! oracle written here (double loop over j and every existing image code with its own image
//! transform), on random clouds of awkward sizes, on particles placed exactly on cell edges and
//! at exactly the support radius, with mirror and periodic images, in f64 and f32, after
//! tracking updates below and above skin/2, and for `Exec::Serial` vs `Exec::Parallel`.

use sphlab::exec::Exec;
use sphlab::model::{AxisMap, Images};
use sphlab::neighbours::{cells, direct, pack, unpack, NeighbourList, Search, SearchKind};
use sphlab::real::{Real, V2};

/// Deterministic pseudo-random numbers in [0, 1).
struct Lcg(u64);
impl Lcg {
    fn new(seed: u64) -> Self {
        let mut l = Lcg(seed ^ 0x9E37_79B9_7F4A_7C15);
        l.next();
        l
    }
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Box [0, L]² with the given side maps.
#[derive(Clone, Copy, Debug)]
enum Bc {
    None,
    /// Mirrors on x-low and y-low (the oscillating-drop quarter).
    MirrorLow,
    /// Mirrors on all four sides.
    MirrorAll,
    /// Periodic in x and y.
    Periodic,
    /// Mirror at x-low, periodic in y.
    Mixed,
}

fn images<T: Real>(bc: Bc, l: f64) -> Images<T> {
    let m = |p: f64| Some(AxisMap::Mirror(T::c(p)));
    let s = |d: f64| Some(AxisMap::Shift(T::c(d)));
    match bc {
        Bc::None => Images { x: [None, None], y: [None, None] },
        Bc::MirrorLow => Images { x: [m(0.0), None], y: [m(0.0), None] },
        Bc::MirrorAll => Images { x: [m(0.0), m(l)], y: [m(0.0), m(l)] },
        Bc::Periodic => Images { x: [s(-l), s(l)], y: [s(-l), s(l)] },
        Bc::Mixed => Images { x: [m(0.0), None], y: [s(-l), s(l)] },
    }
}

/// Oracle image of one coordinate, written independently of `model.rs`.
fn oracle_map<T: Real>(m: Option<AxisMap<T>>, c: T) -> Option<T> {
    match m {
        None => None,
        Some(AxisMap::Mirror(p)) => Some(p + p - c),
        Some(AxisMap::Shift(s)) => Some(c + s),
    }
}

/// Brute force: every j, every code c = ax + 3·ay whose maps exist, `|x_i − image(x_j)|² < r²`.
fn oracle<T: Real>(im: &Images<T>, pos: &[V2<T>], r: T) -> NeighbourList {
    let r2 = r * r;
    let mut lists = Vec::new();
    for &xi in pos {
        let mut l = Vec::new();
        for ay in 0..3u32 {
            for ax in 0..3u32 {
                for (j, &xj) in pos.iter().enumerate() {
                    let x = if ax == 0 { Some(xj.x) } else { oracle_map(im.x[ax as usize - 1], xj.x) };
                    let y = if ay == 0 { Some(xj.y) } else { oracle_map(im.y[ay as usize - 1], xj.y) };
                    if let (Some(x), Some(y)) = (x, y) {
                        let (dx, dy) = (xi.x - x, xi.y - y);
                        if dx * dx + dy * dy < r2 {
                            l.push(pack(j, ax + 3 * ay));
                        }
                    }
                }
            }
        }
        l.sort_unstable();
        lists.push(l);
    }
    NeighbourList::from_lists(lists)
}

fn random_cloud<T: Real>(n: usize, l: f64, seed: u64) -> Vec<V2<T>> {
    let mut rng = Lcg::new(seed);
    (0..n).map(|_| V2::from_f64(rng.next() * l, rng.next() * l)).collect()
}

/// First particle whose list differs, for a readable failure message.
fn first_diff(a: &NeighbourList, b: &NeighbourList) -> String {
    if a.offsets.len() != b.offsets.len() {
        return format!("{} vs {} rows", a.offsets.len() - 1, b.offsets.len() - 1);
    }
    for i in 0..a.offsets.len() - 1 {
        if a.of(i) != b.of(i) {
            let d = |x: &[u32]| x.iter().map(|&e| unpack(e)).collect::<Vec<_>>();
            return format!("particle {i}: {:?} vs {:?}", d(a.of(i)), d(b.of(i)));
        }
    }
    "offsets/entries differ".into()
}

fn assert_same(what: &str, a: &NeighbourList, b: &NeighbourList) {
    assert!(a == b, "{what}: lists differ ({}); entries {} vs {}", first_diff(a, b), a.entries.len(), b.entries.len());
}

/// All searches (both execs, a fresh tracking search) against the oracle.
fn check_all<T: Real>(what: &str, im: &Images<T>, pos: &[V2<T>], r: T) -> NeighbourList {
    let o = oracle(im, pos, r);
    assert!(o.entries.len() >= pos.len(), "{what}: oracle lost self entries");
    for exec in [Exec::Serial, Exec::Parallel] {
        let d = direct(exec, im, pos, r * r);
        assert_same(&format!("{what} direct {exec:?} vs oracle"), &d, &o);
        let c = cells(exec, im, pos, r);
        assert_same(&format!("{what} cells {exec:?} vs oracle"), &c, &o);
        for kind in [SearchKind::Direct, SearchKind::Cells, SearchKind::Tracking] {
            let mut s = Search::<T>::new(kind);
            let l = s.update(exec, im, pos, r);
            assert_same(&format!("{what} Search::{kind:?} {exec:?} vs oracle"), &l, &o);
        }
    }
    o
}

#[test]
fn random_clouds_all_searches_equal_oracle() {
    let l = 1.0;
    for (n, seed) in [(1usize, 1u64), (2, 2), (17, 3), (250, 4), (1013, 5), (1013, 6)] {
        for bc in [Bc::None, Bc::MirrorLow, Bc::MirrorAll, Bc::Periodic, Bc::Mixed] {
            // mean neighbour count about 30 for N = 1013
            let r = 0.0971;
            let pos = random_cloud::<f64>(n, l, seed);
            let o = check_all(&format!("N={n} seed={seed} {bc:?}"), &images(bc, l), &pos, r);
            if n == 1013 {
                println!(
                    "N={n} seed={seed} {bc:?}: {} entries, mean {:.2}, max {}",
                    o.entries.len(),
                    o.mean_count(),
                    o.max_count()
                );
                let imaged = o.entries.iter().filter(|&&e| unpack(e).1 != 0).count();
                if !matches!(bc, Bc::None) {
                    assert!(imaged > 0, "{bc:?}: no image entries at all ({imaged})");
                }
            }
        }
    }
}

#[test]
fn random_clouds_f32() {
    for (n, seed) in [(1013usize, 21u64), (333, 22)] {
        for bc in [Bc::MirrorLow, Bc::Periodic, Bc::Mixed] {
            let pos = random_cloud::<f32>(n, 1.0, seed);
            check_all(&format!("f32 N={n} {bc:?}"), &images::<f32>(bc, 1.0), &pos, 0.0971f32);
        }
    }
}

#[test]
fn large_radius_and_tiny_radius() {
    // radius comparable to the box (a particle sees its periodic images and itself mirrored)
    // and a radius below the mean spacing (almost only self entries).
    let pos = random_cloud::<f64>(301, 1.0, 31);
    for bc in [Bc::Periodic, Bc::MirrorAll, Bc::Mixed] {
        check_all(&format!("r=0.45 {bc:?}"), &images(bc, 1.0), &pos, 0.45);
        let o = check_all(&format!("r=0.004 {bc:?}"), &images(bc, 1.0), &pos, 0.004);
        assert!(o.entries.len() < 2 * pos.len(), "tiny radius gave {} entries", o.entries.len());
    }
}

#[test]
fn particles_on_cell_edges_and_at_exact_radius() {
    let r = 0.25f64;
    let cell = r * 1.01;
    for bc in [Bc::None, Bc::MirrorLow, Bc::MirrorAll, Bc::Periodic, Bc::Mixed] {
        // lattice of multiples of the cell size (the grid origin is lo − cell, so these sit on
        // cell edges) and of the radius (pairs at exactly r: strict < excludes them)
        for (name, step) in [("cell", cell), ("radius", r), ("half-radius", 0.5 * r), ("third-radius", r / 3.0)] {
            let n = (1.0 / step).floor() as usize;
            let mut pos = Vec::new();
            for a in 0..=n {
                for b in 0..=n {
                    pos.push(V2::new(a as f64 * step, b as f64 * step));
                }
            }
            let o = check_all(&format!("{name} lattice {bc:?}"), &images(bc, 1.0), &pos, r);
            if name == "radius" {
                // no pair at exactly r may be counted: each particle has only itself at code 0
                // (plus mirror images of itself when it sits on a plane: distance 0)
                let within0 = o.entries.iter().filter(|&&e| unpack(e).1 == 0).count();
                assert_eq!(within0, pos.len(), "{bc:?}: pairs at exactly r counted ({within0} identity entries)");
            }
        }
        // duplicates: two particles at the same point
        let pos = vec![V2::new(0.3, 0.3), V2::new(0.3, 0.3), V2::new(0.0, 0.0), V2::new(1.0, 1.0), V2::new(0.5, 1.0)];
        check_all(&format!("duplicates {bc:?}"), &images(bc, 1.0), &pos, r);
    }
    // a particle exactly at r/2 from a mirror: its own image is at exactly r, excluded
    let im = images::<f64>(Bc::MirrorLow, 1.0);
    let pos = vec![V2::new(0.125, 0.6), V2::new(0.1249, 0.3)];
    let o = check_all("r/2 from mirror", &im, &pos, r);
    assert_eq!(o.of(0), &[pack(0, 0)], "image at exactly r must be excluded: {:?}", o.of(0));
    assert_eq!(o.of(1), &[pack(1, 0), pack(1, 1)], "image just inside r must be included: {:?}", o.of(1));
}

#[test]
fn tracking_after_displacements_equals_direct() {
    let l = 1.0;
    let r = 0.0971;
    let skin = r * 0.25; // TrackingCfg::default().skin_ratio
    for bc in [Bc::None, Bc::MirrorLow, Bc::Periodic, Bc::Mixed] {
        let im = images::<f64>(bc, l);
        // (label, per-step amplitude per component, expected rebuild range over 10 updates)
        let cases = [
            ("below skin/2", 0.03 * skin, 1..=1),
            ("crossing skin/2 now and then", 0.1 * skin, 2..=9),
            ("above skin/2", 0.4 * skin, 10..=10),
        ];
        for (label, amp, expect) in cases {
            let mut rng = Lcg::new(99);
            let mut pos = random_cloud::<f64>(1013, l, 41);
            let mut tr = Search::<f64>::new(SearchKind::Tracking);
            let mut tr_par = Search::<f64>::new(SearchKind::Tracking);
            for step in 0..10 {
                if step > 0 {
                    for p in pos.iter_mut() {
                        p.x = (p.x + amp * (2.0 * rng.next() - 1.0)).abs().min(l);
                        p.y = (p.y + amp * (2.0 * rng.next() - 1.0)).abs().min(l);
                    }
                }
                let t = tr.update(Exec::Serial, &im, &pos, r);
                let tp = tr_par.update(Exec::Parallel, &im, &pos, r);
                let d = direct(Exec::Serial, &im, &pos, r * r);
                assert_same(&format!("{bc:?} {label} step {step}: tracking vs direct"), &t, &d);
                assert_same(&format!("{bc:?} {label} step {step}: tracking parallel vs direct"), &tp, &d);
                if step == 9 {
                    assert_same(&format!("{bc:?} {label}: direct vs oracle"), &d, &oracle(&im, &pos, r));
                }
            }
            println!("{bc:?} {label}: {} rebuilds in 10 updates", tr.rebuilds);
            // 10 steps of ≤ 0.03·skin per component stay below skin/2 (|d| ≤ 0.42 skin): no
            // rebuild after the first; 0.4·skin per step crosses skin/2 every step
            assert!(expect.contains(&tr.rebuilds), "{bc:?} {label}: {} rebuilds, expected {expect:?}", tr.rebuilds);
        }
    }
}

#[test]
fn tracking_forced_rebuild_every_k_and_invalidate() {
    let im = images::<f64>(Bc::Periodic, 1.0);
    let pos = random_cloud::<f64>(500, 1.0, 5);
    let mut tr = Search::<f64>::new(SearchKind::Tracking);
    let d = direct(Exec::Serial, &im, &pos, 0.1 * 0.1);
    for _ in 0..45 {
        let t = tr.update(Exec::Serial, &im, &pos, 0.1);
        assert_same("static tracking", &t, &d);
    }
    assert_eq!(tr.rebuilds, 3, "45 evaluations with every = 20 should rebuild 3 times, got {}", tr.rebuilds);
    tr.invalidate();
    tr.update(Exec::Serial, &im, &pos, 0.1);
    assert_eq!(tr.rebuilds, 4, "invalidate() must force a rebuild, got {}", tr.rebuilds);
    // moved by hand far beyond the skin: particles teleported (the invalidate use case)
    let mut moved = pos.clone();
    moved.reverse();
    let t = tr.update(Exec::Serial, &im, &moved, 0.1);
    assert_same("teleported particles", &t, &direct(Exec::Serial, &im, &moved, 0.01));
}

#[test]
fn serial_equals_parallel() {
    let pos = random_cloud::<f64>(2027, 2.0, 77);
    for bc in [Bc::MirrorLow, Bc::Periodic] {
        let im = images::<f64>(bc, 2.0);
        for kind in [SearchKind::Direct, SearchKind::Cells, SearchKind::Tracking] {
            let a = Search::<f64>::new(kind).update(Exec::Serial, &im, &pos, 0.13);
            let b = Search::<f64>::new(kind).update(Exec::Parallel, &im, &pos, 0.13);
            assert_same(&format!("{kind:?} {bc:?} serial vs parallel"), &a, &b);
        }
    }
}

#[test]
fn lists_are_sorted_and_contain_self() {
    let im = images::<f64>(Bc::Mixed, 1.0);
    let pos = random_cloud::<f64>(1013, 1.0, 8);
    let l = cells(Exec::Parallel, &im, &pos, 0.0971);
    for i in 0..pos.len() {
        let row = l.of(i);
        assert!(row.windows(2).all(|w| w[0] < w[1]), "row {i} not strictly sorted");
        assert!(row.contains(&pack(i, 0)), "row {i} lacks the self entry");
    }
}
