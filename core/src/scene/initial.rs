//! A scene's initial velocities: each shape's own velocity, and on the phase it names the
//! analytic oscillating-rod field (T84 of docs/PHYSICS.md; PySPH's `oscillating_rod.py`).

use super::build::Layout;
use super::{InitialVelocity, Scene};
use crate::backend::Frame;

/// The fluid velocities at t = 0: shape velocities, with the analytic field (T84) on its phase.
pub fn initial_velocities(scene: &Scene, layout: &Layout, fr: Option<&Frame>) -> Vec<[f64; 2]> {
    let pos: Vec<[f64; 2]> = match fr {
        Some(f) => f.pos[..f.n_fluid].to_vec(),
        None => layout.pos[..layout.n_fluid].to_vec(),
    };
    let mut vel: Vec<[f64; 2]> = match fr {
        Some(_) => vec![[0.0, 0.0]; pos.len()],
        None => layout.vel[..layout.n_fluid].to_vec(),
    };
    if let Some(InitialVelocity::RodOscillation { v0, r0, centre, phase }) = &scene.initial_velocity {
        // `phase = "*"` applies the field to every fluid particle (as PySPH's oscillating_rod).
        let ph = if phase == "*" { None } else { Some(scene.phase_index(phase).expect("validated") as u32) };
        let h = scene.h();
        for (i, p) in pos.iter().enumerate() {
            if ph.is_some_and(|ph| layout.phase[i] != ph) {
                continue;
            }
            vel[i] = rod_velocity(*v0, *r0, p[0] - centre[0], p[1] - centre[1], h);
        }
    }
    vel
}

/// The oscillating-rod field (T84) at `(x, y)` from the drop centre (`h` regularises r = 0).
pub fn rod_velocity(v0: f64, r0: f64, x: f64, y: f64, h: f64) -> [f64; 2] {
    let r = (x * x + y * y + 1e-4 * h * h).sqrt();
    let e = (-r / r0).exp();
    [v0 * (x / r0) * (1.0 - y * y / (r0 * r)) * e, -v0 * (y / r0) * (1.0 - x * x / (r0 * r)) * e]
}
