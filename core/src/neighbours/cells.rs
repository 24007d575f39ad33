//! Uniform cell grid by counting sort (count, prefix sum, scatter), the same algorithm the GPU
//! `cells` search runs, over the one grid geometry both executors use ([`CellBox`]). The cell
//! size is the query radius × [`CELL_FACTOR`] so that rounding in the image transforms can never
//! push a true neighbour two cells away.

use crate::real::{Real, V2};

/// Cell size / query radius.
pub const CELL_FACTOR: f64 = 1.01;

/// The geometry of a cell grid over the bounding box of the particles, one cell of margin on
/// each side: the CPU grid's and the GPU's `cells` search's (fixed there at construction:
/// walls do not move and fluids stay in the box; positions outside are clamped into the border
/// cells).
#[derive(Clone, Copy, Debug)]
pub struct CellBox<T> {
    /// Lower corner.
    pub origin: V2<T>,
    /// 1 / cell size.
    pub inv_cell: T,
    /// Cells along x.
    pub nx: u32,
    /// Cells along y.
    pub ny: u32,
}

impl<T: Real> CellBox<T> {
    /// The grid over the bounding box of `pos` for query radius `radius`.
    pub fn over(pos: &[V2<T>], radius: T) -> Self {
        let cell = radius * T::c(CELL_FACTOR);
        let (mut lo, mut hi) = (V2::new(T::infinity(), T::infinity()), V2::new(T::neg_infinity(), T::neg_infinity()));
        for p in pos {
            lo = V2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = V2::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        if pos.is_empty() {
            (lo, hi) = (V2::zero(), V2::zero());
        }
        let origin = lo - V2::new(cell, cell);
        let inv_cell = T::one() / cell;
        let nx = (((hi.x - origin.x) * inv_cell).f64().floor() as i64 + 2).max(1) as u32;
        let ny = (((hi.y - origin.y) * inv_cell).f64().floor() as i64 + 2).max(1) as u32;
        Self { origin, inv_cell, nx, ny }
    }
    /// Number of cells.
    pub fn cells(&self) -> usize {
        (self.nx * self.ny) as usize
    }
    /// An upper estimate of the cells over particles spanning `width × height`, for the resource
    /// plan (in `f64`, finite for any finite extent).
    pub fn cells_over(width: f64, height: f64, radius: f64) -> f64 {
        let cell = CELL_FACTOR * radius;
        ((width / cell).floor() + 3.0) * ((height / cell).floor() + 3.0)
    }
}

/// A cell grid over the bounding box of the particles.
#[derive(Clone, Debug)]
pub struct CellGrid<T> {
    origin: V2<T>,
    inv_cell: T,
    nx: i64,
    ny: i64,
    /// `sorted[start[c]..start[c+1]]` are the particles of cell c, in increasing index.
    start: Vec<u32>,
    sorted: Vec<u32>,
}

impl<T: Real> CellGrid<T> {
    /// Builds the grid for query radius `radius`.
    pub fn build(pos: &[V2<T>], radius: T) -> Self {
        let CellBox { origin, inv_cell, nx, ny } = CellBox::over(pos, radius);
        let (nx, ny) = (nx as i64, ny as i64);
        let mut g =
            Self { origin, inv_cell, nx, ny, start: vec![0; (nx * ny + 1) as usize], sorted: vec![0; pos.len()] };
        let ids: Vec<usize> = pos.iter().map(|&p| g.cell_of(p)).collect();
        for &c in &ids {
            g.start[c + 1] += 1;
        }
        for c in 0..(nx * ny) as usize {
            g.start[c + 1] += g.start[c];
        }
        let mut fill = g.start.clone();
        for (i, &c) in ids.iter().enumerate() {
            g.sorted[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        g
    }

    /// The cell ranges: `start` (n_cells + 1 offsets) and `sorted` (particles by cell, increasing
    /// within a cell), for the exact comparison with the GPU's counting sort.
    pub fn ranges(&self) -> (&[u32], &[u32]) {
        (&self.start, &self.sorted)
    }

    fn coords(&self, p: V2<T>) -> (i64, i64) {
        let fx = ((p.x - self.origin.x) * self.inv_cell).to_f64().unwrap_or(-1.0).floor();
        let fy = ((p.y - self.origin.y) * self.inv_cell).to_f64().unwrap_or(-1.0).floor();
        (fx.max(-2.0).min(self.nx as f64 + 1.0) as i64, fy.max(-2.0).min(self.ny as f64 + 1.0) as i64)
    }

    fn cell_of(&self, p: V2<T>) -> usize {
        let (cx, cy) = self.coords(p);
        (cx.clamp(0, self.nx - 1) + self.nx * cy.clamp(0, self.ny - 1)) as usize
    }

    /// Calls `f(j)` for every particle in the 3×3 cells around `q`.
    #[inline]
    pub fn for_each_candidate(&self, q: V2<T>, mut f: impl FnMut(usize)) {
        let (cx, cy) = self.coords(q);
        for y in (cy - 1).max(0)..=(cy + 1).min(self.ny - 1) {
            for x in (cx - 1).max(0)..=(cx + 1).min(self.nx - 1) {
                let c = (x + self.nx * y) as usize;
                for &j in &self.sorted[self.start[c] as usize..self.start[c + 1] as usize] {
                    f(j as usize);
                }
            }
        }
    }
}
