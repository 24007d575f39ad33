//! Per-stage wall time of the CPU reference, one thread vs all threads (a profile, not a
//! benchmark): `cargo run --release --example profile_stages -- [nx] [steps]`.
use sphlab::backend::Backend;
use sphlab::cpu::CpuSolver;
use sphlab::exec::Exec;
use sphlab::neighbours::SearchKind;
use sphlab::scene::{build::build_layout, builtin::builtin, overrides::apply_overrides};

fn main() {
    let mut args = std::env::args().skip(1);
    let nx: u32 = args.next().and_then(|s| s.parse().ok()).unwrap_or(100);
    let steps: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(20);
    let sets = [format!("domain.nx={nx}"), "relax.t=0".into(), format!("time.dt={}", 3e-3 / nx as f64)];
    let scene = apply_overrides(&builtin("oscillating-drop").expect("built-in"), &sets).expect("valid");
    let layout = build_layout(&scene).expect("layout");
    for exec in [Exec::Serial, Exec::Parallel] {
        let mut s = CpuSolver::<f64>::new(&scene, &layout, exec, SearchKind::Cells);
        s.profile = true;
        let t = std::time::Instant::now();
        for _ in 0..steps {
            s.step().expect("step");
        }
        let total = t.elapsed().as_secs_f64() * 1e3 / steps as f64;
        println!("{} ({} particles): {total:.2} ms/step", exec.name(), layout.pos.len());
        for (name, d) in &s.clock.totals {
            println!("  {name:<20} {:8.3} ms/step", d.as_secs_f64() * 1e3 / steps as f64);
        }
    }
}
