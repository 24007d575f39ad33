use sphlab::backend::Backend;
use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::neighbours::SearchKind;
use sphlab::scene::{build::build_layout, builtin::builtin};
fn main() {
    let name = std::env::args().nth(1).unwrap_or("oscillating-drop".into());
    let steps: u64 = std::env::args().nth(2).map(|s| s.parse().unwrap()).unwrap_or(100);
    let mut scene = builtin(&name).unwrap();
    scene.relax = None;
    let sets: Vec<String> = std::env::args().skip(3).collect();
    let mut scene = sphlab::scene::overrides::apply_overrides(&scene, &sets).unwrap();
    let layout = build_layout(&scene).unwrap();
    println!("n = {} fluid {} wall {}", layout.pos.len(), layout.n_fluid, layout.n_wall());
    let mut s = CpuSolver::<f64>::new(&scene, &layout, Exec::Parallel, SearchKind::Cells);
    println!("stages {:?}", s.model.stages.names());
    let t0 = std::time::Instant::now();
    for k in 0..steps {
        if let Err(e) = s.step() { println!("{e}"); break; }
        if k % (steps / 10).max(1) == 0 {
            let f = s.frame();
            let (mut ke, mut mx, mut my, mut m) = (0.0, 0.0, 0.0, 0.0);
            let mut maxrho: f64 = 0.0;
            for i in 0..f.n_fluid { if f.phase[i]==0 { ke += 0.5*f.mass[i]*(f.vel[i][0].powi(2)+f.vel[i][1].powi(2)); mx += f.mass[i]*f.pos[i][0]; my += f.mass[i]*f.pos[i][1]; m += f.mass[i]; }
              maxrho = maxrho.max((f.rho[i]/ if f.phase[i]==0 {scene.phases[0].rho0} else {scene.phases[f.phase.len().min(1)].rho0} - 1.0).abs()); }
            let vmax = (0..f.n_fluid).map(|i| (f.vel[i][0].powi(2)+f.vel[i][1].powi(2)).sqrt()).fold(0.0, f64::max);
            println!("step {} t {:.4} dt {:.2e} ke {:.3e} cx {:.5} cy {:.5} maxdrho {:.3e} vmax {:.3e} contacts {:?} nbrs {:.1}", s.step, s.t, s.dt, ke, mx/m.max(1e-300), my/m.max(1e-300), maxrho, vmax, f.contacts, s.nbrs.mean_count());
        }
    }
    println!("{:.3} ms/step", t0.elapsed().as_secs_f64()*1e3/steps as f64);
}
