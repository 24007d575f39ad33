//! How the study's plots look alike: one colour and one marker per variant id across every plot
//! (the CPU baselines in greys with ×, each GPU variant a hue from its place in
//! `VariantSpec::all`, a golden angle from its neighbour's, and a marker per thread mapping:
//! thread ○, block-atomic △, block-tree □, subgroup ◇), the thesis's ○ ∆ □ in Fig. 6.9, and the
//! note every plot carries: the adapter, and "CPU emulation: ratios only" when the GPU adapter is
//! a CPU.

use super::Record;
use crate::gpu::variant::VariantSpec;
use crate::plot::{Marker, Series};

/// A saturated colour of hue `h` (turns) and lightness `l` (HSL, saturation 0.7).
fn hsl(h: f64, l: f64) -> (u8, u8, u8) {
    let s = 0.7;
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let hp = (h.rem_euclid(1.0)) * 6.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - c / 2.0;
    let to = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    (to(r), to(g), to(b))
}

/// The colour of a backend id, the same in every plot.
pub fn colour_of(id: &str) -> (u8, u8, u8) {
    match id {
        "cpu1.cells.f64" => (0, 0, 0),
        "cpu1.tracking.f64" => (70, 70, 70),
        "cpu1.cells.f32" => (100, 100, 100),
        "cpu1.tracking.f32" => (130, 130, 130),
        "cpu1.direct.f64" => (160, 160, 160),
        "cpu.cells.f64" => (90, 60, 40),
        "cpu.cells.f32" => (150, 110, 80),
        _ => {
            // A workgroup-size id (`….wg256`) takes its variant's hue, darker: the pair reads as
            // one variant at two sizes.
            let (base, wg) = match id.rsplit_once('.') {
                Some((b, w)) if w.starts_with("wg") && w[2..].parse::<u32>().is_ok() => (b, true),
                _ => (id, false),
            };
            let k = VariantSpec::all()
                .iter()
                .position(|s| s.to_string() == base)
                .unwrap_or_else(|| base.bytes().fold(0usize, |h, b| h.wrapping_mul(31).wrapping_add(b as usize)));
            // Hues a golden angle apart: every id its own hue, neighbouring ids far apart; two
            // lightnesses, none pale.
            let l = if k % 2 == 0 { 0.42 } else { 0.55 };
            hsl(k as f64 * 0.618_033_988_75, if wg { l - 0.2 } else { l })
        }
    }
}

/// The marker of a backend id, the same in every plot: × for the CPU, else by thread mapping.
pub fn marker_of(id: &str) -> Marker {
    if id.starts_with("cpu") {
        return Marker::Cross;
    }
    match id.split('.').nth(1) {
        Some("thread") => Marker::Circle,
        Some("block-atomic") => Marker::Triangle,
        Some("block-tree") => Marker::Square,
        Some("subgroup") => Marker::Diamond,
        _ => Marker::TriangleDown,
    }
}

/// `s` in the colour and marker of backend id `id`.
pub fn styled(s: Series, id: &str) -> Series {
    s.with_colour(colour_of(id)).with_marker(marker_of(id))
}

/// The thesis's marker of a label starting with ○, ∆ or □ (its E3 configurations); circles
/// otherwise.
pub fn thesis_marker(label: &str) -> Marker {
    match label.chars().next() {
        Some('∆') => Marker::Triangle,
        Some('□') => Marker::Square,
        _ => Marker::Circle,
    }
}

/// The plots' note: the GPU adapter(s) of `recs` (or "CPU only"), and "CPU emulation: ratios
/// only" when one is a CPU.
pub fn adapter_note(recs: &[Record]) -> String {
    let mut names: Vec<&str> = recs.iter().filter(|r| r.backend == "gpu").map(|r| r.adapter.as_str()).collect();
    names.sort();
    names.dedup();
    let emulated = recs.iter().any(|r| r.backend == "gpu" && r.device_type == "Cpu");
    let head =
        if names.is_empty() { "adapter: CPU only".to_string() } else { format!("adapter: {}", names.join("; ")) };
    if emulated {
        format!("{head} — CPU emulation: ratios only")
    } else {
        head
    }
}

/// Where a record ran: its adapter for a GPU row, its CPU model and core count for a CPU row
/// (one model name covers machines of different sizes).
pub fn machine(r: &Record) -> String {
    if r.backend == "gpu" {
        r.adapter.clone()
    } else {
        format!("{}, {} cores", r.cpu_model, r.cores)
    }
}

/// Whether `recs` ran on more than one machine (adapters or CPU models): then a plot draws one
/// series per id and machine, never one line through both.
pub fn several_machines(recs: &[&Record]) -> bool {
    let mut gpus: Vec<String> = recs.iter().filter(|r| r.backend == "gpu").map(|r| machine(r)).collect();
    let mut cpus: Vec<String> = recs.iter().filter(|r| r.backend != "gpu").map(|r| machine(r)).collect();
    for v in [&mut gpus, &mut cpus] {
        v.sort();
        v.dedup();
    }
    gpus.len() > 1 || cpus.len() > 1
}

/// A series label: the id, and `@ machine` when the plot holds several machines.
pub fn label_at(id: &str, r: &Record, several: bool) -> String {
    if several {
        format!("{id} @ {}", machine(r))
    } else {
        id.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_of_two_machines_are_labelled_by_machine() {
        let at = |backend: &str, adapter: &str, cpu: &str, cores: usize| Record {
            backend: backend.into(),
            adapter: adapter.into(),
            cpu_model: cpu.into(),
            cores,
            ..Record::default()
        };
        let (lvp, h200) = (at("gpu", "llvmpipe", "Xeon", 2), at("gpu", "NVIDIA H200", "Xeon", 16));
        let (small, large) = (at("cpu1", "CPU", "Xeon", 2), at("cpu1", "CPU", "Xeon", 16));
        assert!(!several_machines(&[&lvp, &small]), "one adapter, one CPU");
        assert!(several_machines(&[&lvp, &h200]));
        assert!(several_machines(&[&small, &large]), "one model name, two hosts: two machines");
        assert_eq!(label_at("cpu1.cells.f64", &large, true), "cpu1.cells.f64 @ Xeon, 16 cores");
        assert_eq!(label_at("cells.thread", &h200, true), "cells.thread @ NVIDIA H200");
        assert_eq!(label_at("cells.thread", &h200, false), "cells.thread");
    }

    #[test]
    fn every_id_has_its_own_colour() {
        let mut ids: Vec<String> = VariantSpec::all().iter().map(|s| s.to_string()).collect();
        ids.extend(["cpu1.cells.f64", "cpu1.tracking.f32", "cpu.cells.f32"].map(String::from));
        let mut c: Vec<(u8, u8, u8)> = ids.iter().map(|i| colour_of(i)).collect();
        assert_eq!(colour_of(&ids[3]), c[3], "the same id, the same colour");
        let n = c.len();
        c.sort();
        c.dedup();
        assert_eq!(c.len(), n, "a colour repeats");
        assert_eq!(hsl(0.0, 0.5), (217, 38, 38));
    }

    #[test]
    fn a_workgroup_size_id_is_its_variant_darker() {
        let lum = |c: (u8, u8, u8)| u32::from(c.0) + u32::from(c.1) + u32::from(c.2);
        let ids: Vec<String> = VariantSpec::all().iter().map(|s| s.to_string()).collect();
        for base in ["cells.thread.recomputed.f32", "cells.thread.cached.f32", "tracking.thread.recomputed.f32"] {
            let (b, w) = (colour_of(base), colour_of(&format!("{base}.wg256")));
            assert!(lum(w) < lum(b), "{base}: {w:?} not darker than {b:?}");
            assert!(ids.iter().all(|i| colour_of(i) != w), "{base}.wg256 takes another id's colour");
        }
        // Two variants at one size differ as their variants do.
        assert_ne!(colour_of("cells.thread.cached.f32.wg256"), colour_of("cells.thread.recomputed.f32.wg256"));
    }

    #[test]
    fn markers_follow_the_mapping_and_the_thesis() {
        assert_eq!(marker_of("cpu1.tracking.f32"), Marker::Cross);
        assert_eq!(marker_of("cells.thread.recomputed.f32"), Marker::Circle);
        assert_eq!(marker_of("tracking.block-atomic.cas.cached.f32"), Marker::Triangle);
        assert_eq!(marker_of("cells.block-tree.fixed.recomputed.f64"), Marker::Square);
        assert_eq!(marker_of("direct.subgroup.recomputed.f32"), Marker::Diamond);
        assert_eq!(thesis_marker("∆ no atomics"), Marker::Triangle);
        assert_eq!(thesis_marker("□ tree"), Marker::Square);
        assert_eq!(thesis_marker("○ cached"), Marker::Circle);
        // Colour and marker together name an id: no two ids share both.
        let ids: Vec<String> = VariantSpec::all().iter().map(|s| s.to_string()).collect();
        let mut looks: Vec<_> = ids.iter().map(|i| (colour_of(i), marker_of(i) as u8)).collect();
        looks.sort();
        looks.dedup();
        assert_eq!(looks.len(), ids.len());
    }

    #[test]
    fn a_cpu_adapter_says_ratios_only() {
        let gpu = Record {
            backend: "gpu".into(),
            adapter: "llvmpipe".into(),
            device_type: "Cpu".into(),
            ..Default::default()
        };
        assert_eq!(adapter_note(std::slice::from_ref(&gpu)), "adapter: llvmpipe — CPU emulation: ratios only");
        let real = Record { device_type: "DiscreteGpu".into(), adapter: "H200".into(), ..gpu };
        assert_eq!(adapter_note(&[real]), "adapter: H200");
    }
}
