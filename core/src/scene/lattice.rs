//! The particle lattice of a scene (docs/PHYSICS.md §6.1), computed once from the scene and used
//! by the layout builder ([`super::build::build_layout`]), the resource plan and the cell-grid
//! estimate: `nx × ny` cell-centred fluid positions of spacing Δx inside the box, and
//! `2·ceil(κh/Δx)` wall layers behind every wall side (twice the spec's n_L, so that every wall
//! particle the fluid sees has a complete neighbourhood), extended past corners where two walls
//! meet. Mirror and periodic sides get no layers. Counts are `f64`, so an absurd scene gives an
//! absurd but finite lattice instead of an overflow.

use super::{Scene, Side};

/// The lattice of one scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice {
    /// Spacing Δx = (x1 − x0)/nx.
    pub dx: f64,
    /// Fluid columns (domain.nx).
    pub nx: f64,
    /// Fluid rows, (y1 − y0)/Δx rounded.
    pub ny: f64,
    /// Wall layers behind each wall side, 2·ceil(κh/Δx).
    pub wall_layers: f64,
    /// Wall layers on the left, right, bottom and top sides (0 where the side is no wall).
    pub sides: [f64; 4],
}

impl Lattice {
    /// The lattice of `scene` (needs finite, positive extents and kernel support, as
    /// `Scene::validate` checks).
    pub fn of(scene: &Scene) -> Lattice {
        let d = &scene.domain;
        let dx = d.dx();
        let ny = ((d.y[1] - d.y[0]) / dx).round();
        // Wall particles within one support of the fluid interact with it; their own number
        // density must be complete too (a deficient σ_w gives them a negative T-wall pressure
        // that pulls the fluid onto the wall), so the lattice is two supports deep.
        let wall_layers = 2.0 * (scene.support() / dx - 1e-9).ceil().max(0.0);
        let ext = |s: Side| if s.is_wall() { wall_layers } else { 0.0 };
        let sides = [ext(d.left), ext(d.right), ext(d.bottom), ext(d.top)];
        Lattice { dx, nx: d.nx as f64, ny, wall_layers, sides }
    }
    /// Lattice columns, walls included.
    pub fn columns(&self) -> f64 {
        self.nx + self.sides[0] + self.sides[1]
    }
    /// Lattice rows, walls included.
    pub fn rows(&self) -> f64 {
        self.ny + self.sides[2] + self.sides[3]
    }
    /// Fluid particles.
    pub fn n_fluid(&self) -> f64 {
        self.nx * self.ny
    }
    /// Fluid and wall particles.
    pub fn n_total(&self) -> f64 {
        self.columns() * self.rows()
    }
}
