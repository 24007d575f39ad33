//! Where the convergence case's density error sits: the last snapshot's fluid particles split
//! into the interface band (|∇C|·Δx ≥ [`BAND_GRADIENT`]) and the rest. The capillary rule
//! (docs/PHYSICS.md §3.1) holds the band's tension at ε of ρ0c0², so the band's deficit is set
//! by ε at every Δx; what lies outside the band is what refinement can shrink.

use super::super::data::{read_snapshot, snapshot_files};
use crate::scene::build::WALL;
use std::path::Path;

/// |∇C|·Δx from which a particle counts as in the interface band (the band's core reaches
/// about 0.41 with the quintic at h = 1.2Δx, §3.1).
pub const BAND_GRADIENT: f64 = 0.1;

/// The last state's |ρ/ρ0 − 1| in the band and outside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandDensity {
    /// Max in the band.
    pub band_max: f64,
    /// Max outside the band.
    pub outside_max: f64,
    /// Mean outside the band.
    pub outside_mean: f64,
}

/// The split of the last snapshot in `dir` (None without one), `rho0` by phase, spacing `dx`.
pub fn last_state(dir: &Path, rho0: &[f64], dx: f64) -> Option<BandDensity> {
    let (step, path) = snapshot_files(dir).pop()?;
    let s = read_snapshot(&path, step, f64::NAN)?;
    let (mut band, mut out) = (Vec::new(), Vec::new());
    for i in 0..s.pos.len() {
        let ph = s.phase[i];
        if ph == WALL {
            continue;
        }
        let err = (s.rho[i] / rho0.get(ph as usize).copied()? - 1.0).abs();
        let g = s.grad_c[i][0].hypot(s.grad_c[i][1]) * dx;
        if g >= BAND_GRADIENT {
            band.push(err);
        } else {
            out.push(err);
        }
    }
    let max = |v: &[f64]| v.iter().copied().fold(f64::NAN, f64::max);
    Some(BandDensity {
        band_max: max(&band),
        outside_max: max(&out),
        outside_mean: out.iter().sum::<f64>() / out.len() as f64,
    })
}

/// [`last_state`] of a relax-60 run at `nx` in `dir` (the scene's ρ0 by phase, Δx = 0.5/nx).
pub fn relax_last_state(dir: &Path, nx: u32) -> Option<BandDensity> {
    let rho0: Vec<f64> = crate::scene::builtin::relax_60().phases.iter().map(|p| p.rho0).collect();
    last_state(dir, &rho0, 0.5 / nx as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_band_and_the_rest_are_split_by_the_colour_gradient() {
        let dir = std::env::temp_dir().join(format!("sphlab-band-density-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let dx = 0.01;
        let csv = "id,x,y,vx,vy,rho,p,phase,gcx,gcy\n\
                   0,0,0,0,0,0.99,0,0,30,0\n\
                   1,0,0,0,0,1.002,0,1,0,5\n\
                   2,0,0,0,0,2.004,0,1,1,0\n\
                   3,0,0,0,0,0.5,0,-1,0,0\n";
        std::fs::write(dir.join("particles_00000000.csv"), "id,x,y,vx,vy,rho,p,phase,gcx,gcy\n").unwrap();
        std::fs::write(dir.join("particles_00000010.csv"), csv).unwrap();
        let b = last_state(&dir, &[1.0, 2.0], dx).unwrap();
        std::fs::remove_dir_all(&dir).ok();
        assert!((b.band_max - 0.01).abs() < 1e-12, "{b:?}");
        // phase 1 against its own ρ0 = 2: 0.501 and 0.002 outside the band; the wall is left out
        assert!(
            (b.outside_max - 0.499).abs() < 1e-12 && (b.outside_mean - (0.499 + 0.002) / 2.0).abs() < 1e-12,
            "{b:?}"
        );
    }
}
