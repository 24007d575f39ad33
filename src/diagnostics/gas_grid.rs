//! Coarse cell grid of the gas particles for the nearest-gas-neighbour queries of the
//! contact-angle measurement (PHYSICS.md §10.1–§10.2): O(n) build, O(1) query.

use crate::scene::build::WALL;

/// Phase id of the liquid.
pub(crate) const LIQUID: u32 = 0;

/// Any fluid phase other than the liquid counts as gas.
pub(crate) fn is_gas(p: u32) -> bool {
    p != LIQUID && p != WALL
}

/// Coarse uniform grid over the gas particles (cell ≥ 1.5Δx) for nearest-gas queries within
/// radius `r ≤ cell`; stored as CSR (cell start offsets + particle ids).
pub(crate) struct GasGrid {
    x0: f64,
    y0: f64,
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<usize>,
    ids: Vec<usize>,
}

impl GasGrid {
    pub(crate) fn new(pos: &[[f64; 2]], phase: &[u32], r: f64) -> Option<Self> {
        let gas: Vec<usize> = (0..pos.len().min(phase.len()))
            .filter(|&i| is_gas(phase[i]) && pos[i][0].is_finite() && pos[i][1].is_finite())
            .collect();
        if gas.is_empty() || !(r > 0.0) {
            return None;
        }
        let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for &i in &gas {
            x0 = x0.min(pos[i][0]);
            y0 = y0.min(pos[i][1]);
            x1 = x1.max(pos[i][0]);
            y1 = y1.max(pos[i][1]);
        }
        // Cap the number of cells (outliers would blow up a dense grid): enlarge the cell.
        let max_cells = (16 * gas.len() + 4096) as f64;
        let mut cell = r;
        while ((x1 - x0) / cell + 1.0) * ((y1 - y0) / cell + 1.0) > max_cells {
            cell *= 2.0;
        }
        let nx = ((x1 - x0) / cell) as usize + 1;
        let ny = ((y1 - y0) / cell) as usize + 1;
        let key = |p: [f64; 2]| {
            let ix = (((p[0] - x0) / cell) as usize).min(nx - 1);
            let iy = (((p[1] - y0) / cell) as usize).min(ny - 1);
            iy * nx + ix
        };
        let mut start = vec![0usize; nx * ny + 1];
        for &i in &gas {
            start[key(pos[i]) + 1] += 1;
        }
        for c in 0..nx * ny {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut ids = vec![0usize; gas.len()];
        for &i in &gas {
            let k = key(pos[i]);
            ids[fill[k]] = i;
            fill[k] += 1;
        }
        Some(Self { x0, y0, cell, nx, ny, start, ids })
    }

    /// Nearest gas particle within `r` (`r` ≤ cell size) of `p`.
    pub(crate) fn nearest(&self, pos: &[[f64; 2]], p: [f64; 2], r: f64) -> Option<usize> {
        let fx = ((p[0] - self.x0) / self.cell).floor();
        let fy = ((p[1] - self.y0) / self.cell).floor();
        let mut best = (r * r, None);
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (cx, cy) = (fx + dx as f64, fy + dy as f64);
                if cx < 0.0 || cy < 0.0 || cx >= self.nx as f64 || cy >= self.ny as f64 {
                    continue;
                }
                let c = cy as usize * self.nx + cx as usize;
                for &j in &self.ids[self.start[c]..self.start[c + 1]] {
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
