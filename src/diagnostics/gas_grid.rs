//! Coarse cell grid of the gas particles for the nearest-gas-neighbour queries of the
//! contact-angle measurement (docs/PHYSICS.md §10.1–§10.2): O(n) build, O(1) query. Only the gas
//! within the query radius of the liquid's bounding box is gridded, and the cells are capped
//! by the particles gridded, so the grid is sized by the drop it samples, never by the domain
//! ([`GasGrid::max_bytes`] bounds it for the resource plan); its arrays are allocated fallibly.

use crate::fallible::{self, AllocError};
use crate::scene::build::WALL;

/// Phase id of the liquid.
pub(crate) const LIQUID: u32 = 0;

/// Any fluid phase other than the liquid counts as gas.
pub(crate) fn is_gas(p: u32) -> bool {
    p != LIQUID && p != WALL
}

/// Most cells per gridded particle (plus [`MIN_CELLS`]); past it the cell edge doubles.
const CELLS_PER_PARTICLE: usize = 4;
/// Cells any grid may have.
const MIN_CELLS: usize = 4096;
/// What the grid's arrays are called in an allocation failure.
const WHAT: &str = "the contact-angle gas grid";

/// Bounding box `[x0, y0, x1, y1]` of the finite positions of `pos` whose phase passes `keep`.
fn bbox(pos: &[[f64; 2]], phase: &[u32], keep: impl Fn(u32) -> bool) -> Option<[f64; 4]> {
    let mut b: Option<[f64; 4]> = None;
    for (p, &ph) in pos.iter().zip(phase) {
        if keep(ph) && p[0].is_finite() && p[1].is_finite() {
            let v = b.get_or_insert([p[0], p[1], p[0], p[1]]);
            *v = [v[0].min(p[0]), v[1].min(p[1]), v[2].max(p[0]), v[3].max(p[1])];
        }
    }
    b
}

/// Coarse uniform grid over the gas particles near the liquid (cell ≥ the query radius) for
/// nearest-gas queries within radius `r ≤ cell`; stored as CSR (cell start offsets + particle
/// ids). Cells are numbered on the lattice of the whole gas box (origin: its lower corner), so
/// which cell a particle falls in does not depend on the part gridded.
pub(crate) struct GasGrid {
    x0: f64,
    y0: f64,
    cell: f64,
    /// First gridded cell column and row on the lattice of the whole gas box.
    ox: usize,
    oy: usize,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
    ids: Vec<u32>,
}

impl GasGrid {
    /// Upper bound of the bytes a grid over `n` particles allocates (cell starts and ids).
    pub(crate) fn max_bytes(n: f64) -> f64 {
        4.0 * n + 4.0 * (CELLS_PER_PARTICLE as f64 * n + MIN_CELLS as f64 + 1.0)
    }

    /// The grid of the gas particles within `r` of the liquid's bounding box (`None`: no
    /// liquid, no gas there, or `r` not positive).
    pub(crate) fn new(pos: &[[f64; 2]], phase: &[u32], r: f64) -> Result<Option<Self>, AllocError> {
        let n = pos.len().min(phase.len());
        let (pos, phase) = (&pos[..n], &phase[..n]);
        let (Some(gas), Some(liq)) = (bbox(pos, phase, is_gas), bbox(pos, phase, |p| p == LIQUID)) else {
            return Ok(None);
        };
        if !(r > 0.0) {
            return Ok(None);
        }
        let [x0, y0, x1, y1] = gas;
        let near = |p: [f64; 2]| p[0] >= liq[0] - r && p[0] <= liq[2] + r && p[1] >= liq[1] - r && p[1] <= liq[3] + r;
        let gridded = (0..n).filter(|&i| is_gas(phase[i]) && near(pos[i])).count();
        if gridded == 0 {
            return Ok(None);
        }
        // Cap the cells (outliers would blow up a dense grid): enlarge the cell, first as over the
        // whole gas box (16 per gas particle), then for the part gridded.
        let cap = |m: usize| (CELLS_PER_PARTICLE * m + MIN_CELLS) as f64;
        let total_gas = (0..n).filter(|&i| is_gas(phase[i])).count();
        let mut cell = r;
        let lattice = |cell: f64| {
            let col = |x: f64| ((x - x0) / cell).max(0.0) as usize;
            let row = |y: f64| ((y - y0) / cell).max(0.0) as usize;
            let (ox, oy) = (col(liq[0] - r), row(liq[1] - r));
            let (ex, ey) = (col((liq[2] + r).min(x1)), row((liq[3] + r).min(y1)));
            (ox, oy, ex.max(ox) - ox + 1, ey.max(oy) - oy + 1)
        };
        while ((x1 - x0) / cell + 1.0) * ((y1 - y0) / cell + 1.0) > (16 * total_gas + 4096) as f64 {
            cell *= 2.0;
        }
        let (mut ox, mut oy, mut nx, mut ny) = lattice(cell);
        while (nx as f64) * (ny as f64) > cap(gridded) {
            cell *= 2.0;
            (ox, oy, nx, ny) = lattice(cell);
        }
        let key = |p: [f64; 2]| {
            let ix = (((p[0] - x0) / cell) as usize).saturating_sub(ox).min(nx - 1);
            let iy = (((p[1] - y0) / cell) as usize).saturating_sub(oy).min(ny - 1);
            iy * nx + ix
        };
        // Counting sort: counts, running ends, then each particle (last first) into its cell's
        // next free slot from the end, which leaves every cell's ids ascending and `start` at the
        // cells' beginnings.
        let mut start = fallible::filled(nx * ny + 1, 0u32, WHAT)?;
        let mut ids = fallible::filled(gridded, 0u32, WHAT)?;
        let gas_near = |i: usize| is_gas(phase[i]) && near(pos[i]);
        for i in (0..n).filter(|&i| gas_near(i)) {
            start[key(pos[i])] += 1;
        }
        for c in 1..=nx * ny {
            start[c] += start[c - 1];
        }
        for i in (0..n).rev().filter(|&i| gas_near(i)) {
            let k = key(pos[i]);
            start[k] -= 1;
            ids[start[k] as usize] = i as u32;
        }
        Ok(Some(Self { x0, y0, cell, ox, oy, nx, ny, start, ids }))
    }

    /// Nearest gas particle within `r` (`r` ≤ the radius the grid was built for) of `p`, a
    /// liquid particle (gas farther than that from the liquid is not gridded).
    pub(crate) fn nearest(&self, pos: &[[f64; 2]], p: [f64; 2], r: f64) -> Option<usize> {
        let fx = ((p[0] - self.x0) / self.cell).floor() - self.ox as f64;
        let fy = ((p[1] - self.y0) / self.cell).floor() - self.oy as f64;
        let mut best = (r * r, None);
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (cx, cy) = (fx + dx as f64, fy + dy as f64);
                if cx < 0.0 || cy < 0.0 || cx >= self.nx as f64 || cy >= self.ny as f64 {
                    continue;
                }
                let c = cy as usize * self.nx + cx as usize;
                for &j in &self.ids[self.start[c] as usize..self.start[c + 1] as usize] {
                    let j = j as usize;
                    let d2 = (pos[j][0] - p[0]).powi(2) + (pos[j][1] - p[1]).powi(2);
                    if d2 <= best.0 {
                        best = (d2, Some(j));
                    }
                }
            }
        }
        best.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A liquid square of side `k` particles at the bottom left of a gas box `w` × `h` particles.
    fn drop_in_gas(k: usize, w: usize, h: usize) -> (Vec<[f64; 2]>, Vec<u32>) {
        let (mut pos, mut phase) = (Vec::new(), Vec::new());
        for j in 0..h {
            for i in 0..w {
                pos.push([i as f64 + 0.5, j as f64 + 0.5]);
                phase.push(if i < k && j < k { LIQUID } else { 1 });
            }
        }
        (pos, phase)
    }

    /// The distance to the nearest gas particle within `r` of `p`, by brute force.
    fn brute(pos: &[[f64; 2]], phase: &[u32], p: [f64; 2], r: f64) -> Option<f64> {
        let d = (0..pos.len()).filter(|&j| is_gas(phase[j])).map(|j| (pos[j][0] - p[0]).hypot(pos[j][1] - p[1]));
        d.filter(|&d| d <= r).reduce(f64::min)
    }

    #[test]
    fn a_tall_domain_grids_only_the_gas_near_the_drop() {
        let (pos, phase) = drop_in_gas(20, 40, 4000);
        let g = GasGrid::new(&pos, &phase, 1.5).unwrap().expect("grid");
        // Gas within 1.5 of the drop's box [0.5, 19.5]²: x and y up to 20.5, 21 × 21 − 400.
        assert_eq!(g.ids.len(), 41);
        assert!(((g.start.len() + g.ids.len()) * 4) as f64 <= GasGrid::max_bytes(g.ids.len() as f64));
        for i in (0..pos.len()).filter(|&i| phase[i] == LIQUID) {
            let got = g.nearest(&pos, pos[i], 1.5).map(|j| (pos[j][0] - pos[i][0]).hypot(pos[j][1] - pos[i][1]));
            assert_eq!(got, brute(&pos, &phase, pos[i], 1.5), "particle {i}");
        }
    }

    #[test]
    fn outliers_and_empty_inputs() {
        let (mut pos, phase) = drop_in_gas(5, 10, 10);
        pos[99] = [1e12, -1e12];
        let g = GasGrid::new(&pos, &phase, 1.5).unwrap().expect("grid");
        assert!(g.nx * g.ny <= CELLS_PER_PARTICLE * g.ids.len() + MIN_CELLS);
        assert!(g.nearest(&pos, pos[0], 1.5).is_none(), "the drop's corner is 5 from the gas");
        assert!(g.nearest(&pos, pos[44], 1.5).is_some());
        assert!(GasGrid::new(&pos, &[LIQUID; 100], 1.5).unwrap().is_none());
        assert!(GasGrid::new(&pos, &phase, 0.0).unwrap().is_none());
    }
}
