//! Neighbour searches (docs/PHYSICS.md §12 step 1, thesis §6.3). Three searches with identical
//! results: `direct` (all pairs), `cells` (uniform grid by counting sort, rebuilt every
//! evaluation) and `tracking` (the thesis's tracking lists: cells + a per-particle candidate
//! list within support + skin, rebuilt every k evaluations or when a particle has moved more
//! than skin/2). Boundary images (mirror/periodic) are found as `(j, image code)` pairs.
//!
//! A neighbour of i is `(j, c)` with `|x_i − image(c, x_j)|² < (κh)²`, computed by exactly the
//! same expression in every search; each list is sorted by the packed value, so every search
//! yields the same lists in the same order and the physics is bit-identical.

pub mod cells;

pub use cells::CellGrid;

use crate::exec::Exec;
use crate::model::Images;
use crate::real::{Real, V2};
use serde::{Deserialize, Serialize};

/// Bits of the packed entry that hold the image code.
pub const IMAGE_SHIFT: u32 = 28;
/// Mask of the particle index.
pub const INDEX_MASK: u32 = (1 << IMAGE_SHIFT) - 1;

/// Packs `(j, image code)` into one u32.
#[inline(always)]
pub fn pack(j: usize, c: u32) -> u32 {
    j as u32 | (c << IMAGE_SHIFT)
}

/// Unpacks an entry into `(j, image code)`.
#[inline(always)]
pub fn unpack(e: u32) -> (usize, u32) {
    ((e & INDEX_MASK) as usize, e >> IMAGE_SHIFT)
}

/// Neighbour lists in compressed rows (self included as `(i, 0)`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NeighbourList {
    /// `entries[offsets[i]..offsets[i+1]]` are the neighbours of i.
    pub offsets: Vec<u32>,
    /// Packed `(j, image)` entries.
    pub entries: Vec<u32>,
}

impl NeighbourList {
    /// The neighbours of i.
    #[inline(always)]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.entries[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }
    /// Builds from per-particle lists.
    pub fn from_lists(lists: Vec<Vec<u32>>) -> Self {
        let mut offsets = Vec::with_capacity(lists.len() + 1);
        offsets.push(0u32);
        let total: usize = lists.iter().map(Vec::len).sum();
        let mut entries = Vec::with_capacity(total);
        for l in lists {
            entries.extend_from_slice(&l);
            offsets.push(entries.len() as u32);
        }
        Self { offsets, entries }
    }
    /// Builds the lists by calling `f(i, out)` for every particle, which appends i's entries
    /// to `out`; each list is then sorted. Work is done in chunks of particles, each filling
    /// one flat buffer (no allocation per particle, which made the parallel search slower than
    /// the serial one on 2 cores).
    pub fn build(exec: Exec, n: usize, f: impl Fn(usize, &mut Vec<u32>) + Sync + Send) -> Self {
        const CHUNK: usize = 256;
        let chunk = |c: usize| {
            let (a, b) = (c * CHUNK, ((c + 1) * CHUNK).min(n));
            let mut entries = Vec::with_capacity((b - a) * 48);
            let mut counts = Vec::with_capacity(b - a);
            for i in a..b {
                let start = entries.len();
                f(i, &mut entries);
                entries[start..].sort_unstable();
                counts.push((entries.len() - start) as u32);
            }
            (counts, entries)
        };
        let n_chunks = n.div_ceil(CHUNK);
        let parts: Vec<(Vec<u32>, Vec<u32>)> = match exec {
            Exec::Parallel => {
                use rayon::prelude::*;
                (0..n_chunks).into_par_iter().map(chunk).collect()
            }
            Exec::Serial => (0..n_chunks).map(chunk).collect(),
        };
        let total: usize = parts.iter().map(|p| p.1.len()).sum();
        let mut offsets = Vec::with_capacity(n + 1);
        let mut entries = Vec::with_capacity(total);
        offsets.push(0u32);
        for (counts, e) in parts {
            for c in counts {
                let last = *offsets.last().expect("non-empty");
                offsets.push(last + c);
            }
            entries.extend_from_slice(&e);
        }
        Self { offsets, entries }
    }

    /// Largest neighbour count.
    pub fn max_count(&self) -> usize {
        self.offsets.windows(2).map(|w| (w[1] - w[0]) as usize).max().unwrap_or(0)
    }
    /// Mean neighbour count.
    pub fn mean_count(&self) -> f64 {
        self.entries.len() as f64 / (self.offsets.len().max(2) - 1) as f64
    }
}

/// The search algorithms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum SearchKind {
    /// Every particle tests every particle (and its images).
    Direct,
    /// Uniform grid, counting sort, every evaluation.
    Cells,
    /// Tracking lists with a skin.
    Tracking,
}

impl SearchKind {
    /// Every search, in a stable order.
    pub const ALL: &'static [SearchKind] = &[SearchKind::Direct, SearchKind::Cells, SearchKind::Tracking];
    /// Stable id.
    pub fn name(self) -> &'static str {
        match self {
            SearchKind::Direct => "direct",
            SearchKind::Cells => "cells",
            SearchKind::Tracking => "tracking",
        }
    }
    /// Parses a stable id.
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "direct" => SearchKind::Direct,
            "cells" => SearchKind::Cells,
            "tracking" => SearchKind::Tracking,
            _ => return None,
        })
    }
}

impl std::fmt::Display for SearchKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for SearchKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::parse(s).ok_or_else(|| format!("unknown search `{s}` (direct, cells, tracking)"))
    }
}

/// Tracking-list settings.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct TrackingCfg {
    /// Skin as a fraction of the support radius.
    pub skin_ratio: f64,
    /// Rebuild at least every this many evaluations.
    pub every: u32,
}

impl Default for TrackingCfg {
    fn default() -> Self {
        Self { skin_ratio: 0.25, every: 20 }
    }
}

/// Is `(j, c)` a neighbour of a particle at `xi`? The one distance test every search uses.
#[inline(always)]
pub fn within<T: Real>(images: &Images<T>, xi: V2<T>, xj: V2<T>, c: u32, r2max: T) -> bool {
    (xi - images.image_pos(c, xj)).norm2() < r2max
}

/// Direct search: O(N²·images).
pub fn direct<T: Real>(exec: Exec, images: &Images<T>, pos: &[V2<T>], r2max: T) -> NeighbourList {
    let codes = images.codes();
    NeighbourList::build(exec, pos.len(), |i, l| {
        for &c in &codes {
            for (j, &xj) in pos.iter().enumerate() {
                if within(images, pos[i], xj, c, r2max) {
                    l.push(pack(j, c));
                }
            }
        }
    })
}

/// Cell-grid search.
pub fn cells<T: Real>(exec: Exec, images: &Images<T>, pos: &[V2<T>], radius: T) -> NeighbourList {
    let grid = CellGrid::build(pos, radius);
    let r2max = radius * radius;
    let codes = images.codes();
    NeighbourList::build(exec, pos.len(), |i, l| {
        for &c in &codes {
            let q = images.inverse_pos(c, pos[i]);
            grid.for_each_candidate(q, |j| {
                if within(images, pos[i], pos[j], c, r2max) {
                    l.push(pack(j, c));
                }
            });
        }
    })
}

/// A neighbour search with its state (tracking lists keep candidates between evaluations).
#[derive(Clone, Debug)]
pub struct Search<T> {
    /// The algorithm.
    pub kind: SearchKind,
    /// Tracking settings.
    pub tracking: TrackingCfg,
    candidates: NeighbourList,
    ref_pos: Vec<V2<T>>,
    since_build: u32,
    /// Number of tracking-list rebuilds so far.
    pub rebuilds: u64,
}

impl<T: Real> Search<T> {
    /// A new search of the given kind.
    pub fn new(kind: SearchKind) -> Self {
        Self {
            kind,
            tracking: TrackingCfg::default(),
            candidates: NeighbourList::default(),
            ref_pos: Vec::new(),
            since_build: 0,
            rebuilds: 0,
        }
    }

    /// Forces a rebuild at the next evaluation (after particles were moved by hand).
    pub fn invalidate(&mut self) {
        self.ref_pos.clear();
    }

    /// Computes the neighbour lists of `pos` for support radius `radius`.
    pub fn update(&mut self, exec: Exec, images: &Images<T>, pos: &[V2<T>], radius: T) -> NeighbourList {
        match self.kind {
            SearchKind::Direct => direct(exec, images, pos, radius * radius),
            SearchKind::Cells => cells(exec, images, pos, radius),
            SearchKind::Tracking => {
                let skin = radius * T::c(self.tracking.skin_ratio);
                let half2 = T::c(0.25) * skin * skin;
                let moved = self.ref_pos.len() != pos.len()
                    || self.since_build >= self.tracking.every
                    || pos.iter().zip(&self.ref_pos).any(|(a, b)| (*a - *b).norm2() > half2);
                if moved {
                    self.candidates = cells(exec, images, pos, radius + skin);
                    self.ref_pos = pos.to_vec();
                    self.since_build = 0;
                    self.rebuilds += 1;
                }
                self.since_build += 1;
                let r2max = radius * radius;
                let cand = &self.candidates;
                // Candidates are sorted, so the filtered lists are too (the sort in `build` is
                // then a no-op pass).
                NeighbourList::build(exec, pos.len(), |i, l| {
                    l.extend(cand.of(i).iter().copied().filter(|&e| {
                        let (j, c) = unpack(e);
                        within(images, pos[i], pos[j], c, r2max)
                    }))
                })
            }
        }
    }
}
