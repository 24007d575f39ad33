//! Particle snapshots: the arrays of one snapshot ([`Snapshot`]), their file names, and one
//! CSV file per snapshot (`particles_<step>.csv`). The same data as VTK XML with a ParaView
//! collection is [`super::vtk`] (re-exported here).

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::{ensure_dir, OutputError, Result};

/// Phase index marking a wall particle.
pub const WALL_PHASE: u32 = u32::MAX;

/// One saved state of all particles, in plain arrays (structure of arrays, all of the same
/// length; `grad_c` may also be empty, then it is written as zeros).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Snapshot {
    /// Step number of the state.
    pub step: u64,
    /// Simulated time (s).
    pub t: f64,
    /// Positions (m).
    pub pos: Vec<[f64; 2]>,
    /// Velocities (m/s).
    pub vel: Vec<[f64; 2]>,
    /// Densities (kg/m³).
    pub rho: Vec<f64>,
    /// Pressures (Pa).
    pub p: Vec<f64>,
    /// Phase index; [`WALL_PHASE`] (`u32::MAX`) marks a wall particle.
    pub phase: Vec<u32>,
    /// Colour-function gradient (1/m).
    pub grad_c: Vec<[f64; 2]>,
    /// Masses (may be empty: written as zeros).
    pub mass: Vec<f64>,
    /// Smoothing length h (one for every particle).
    pub h: f64,
}

/// Particle count from which VTK files are written binary (base64) instead of ASCII.
pub const VTK_BINARY_MIN: usize = 20_000;

impl Snapshot {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True when the snapshot holds no particle.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Checks that every array has one entry per particle (`grad_c` may be empty).
    pub fn check(&self, path: &Path) -> Result<()> {
        let n = self.pos.len();
        let lens = [("vel", self.vel.len()), ("rho", self.rho.len()), ("p", self.p.len()), ("phase", self.phase.len())];
        let mut bad: Vec<String> =
            lens.iter().filter(|(_, l)| *l != n).map(|(name, l)| format!("{name} has {l}")).collect();
        if !self.grad_c.is_empty() && self.grad_c.len() != n {
            bad.push(format!("grad_c has {}", self.grad_c.len()));
        }
        if !self.mass.is_empty() && self.mass.len() != n {
            bad.push(format!("mass has {}", self.mass.len()));
        }
        if bad.is_empty() {
            Ok(())
        } else {
            Err(OutputError::Data {
                path: path.to_path_buf(),
                message: format!("snapshot has {n} positions but {}", bad.join(", ")),
            })
        }
    }

    pub(super) fn grad_c_at(&self, i: usize) -> [f64; 2] {
        self.grad_c.get(i).copied().unwrap_or([0.0, 0.0])
    }

    /// Phase as a signed integer: walls are -1.
    pub(super) fn phase_i64(&self, i: usize) -> i64 {
        match self.phase[i] {
            WALL_PHASE => -1,
            ph => ph as i64,
        }
    }
}

/// File name of the CSV snapshot of `step`: `particles_<step, 8 digits>.csv`.
pub fn particles_csv_name(step: u64) -> String {
    format!("particles_{step:08}.csv")
}

/// File name of the VTK snapshot of `step`: `particles_<step, 8 digits>.vtu`.
pub fn vtu_name(step: u64) -> String {
    format!("particles_{step:08}.vtu")
}

#[derive(Serialize)]
struct ParticleRow {
    id: usize,
    x: f64,
    y: f64,
    vx: f64,
    vy: f64,
    rho: f64,
    p: f64,
    phase: i64,
    gcx: f64,
    gcy: f64,
}

/// Writes `DIR/particles_<step>.csv` with header `id,x,y,vx,vy,rho,p,phase,gcx,gcy`, one row
/// per particle (walls have phase -1). Creates `dir` if missing; returns the file's path.
pub fn write_particles_csv(dir: impl AsRef<Path>, snap: &Snapshot) -> Result<PathBuf> {
    let dir = dir.as_ref();
    let path = dir.join(particles_csv_name(snap.step));
    snap.check(&path)?;
    ensure_dir(dir)?;
    let mut w = csv::Writer::from_path(&path).map_err(|e| OutputError::csv(&path, e))?;
    if snap.is_empty() {
        // serde writes the header with the first row; with no row, write it by hand.
        w.write_record(["id", "x", "y", "vx", "vy", "rho", "p", "phase", "gcx", "gcy"])
            .map_err(|e| OutputError::csv(&path, e))?;
    }
    for i in 0..snap.len() {
        let g = snap.grad_c_at(i);
        let row = ParticleRow {
            id: i,
            x: snap.pos[i][0],
            y: snap.pos[i][1],
            vx: snap.vel[i][0],
            vy: snap.vel[i][1],
            rho: snap.rho[i],
            p: snap.p[i],
            phase: snap.phase_i64(i),
            gcx: g[0],
            gcy: g[1],
        };
        w.serialize(&row).map_err(|e| OutputError::csv(&path, e))?;
    }
    w.flush().map_err(|e| OutputError::io(&path, e))?;
    Ok(path)
}

pub use super::vtk::{base64_into, vtk_buffer_bytes, vtu_text, write_vtu, PvdWriter};
