//! How the study's plots look alike: one colour per variant id across every plot (the CPU
//! baselines in greys, each GPU variant at its place in `VariantSpec::all`, spread over 20
//! colours so that neighbouring ids differ), and the note every plot carries: the adapter, and
//! "CPU emulation: ratios only" when the GPU adapter is a CPU.

use super::Record;
use crate::gpu::variant::VariantSpec;

/// Tableau 20.
const PALETTE: [(u8, u8, u8); 20] = [
    (31, 119, 180),
    (174, 199, 232),
    (255, 127, 14),
    (255, 187, 120),
    (44, 160, 44),
    (152, 223, 138),
    (214, 39, 40),
    (255, 152, 150),
    (148, 103, 189),
    (197, 176, 213),
    (140, 86, 75),
    (196, 156, 148),
    (227, 119, 194),
    (247, 182, 210),
    (127, 127, 127),
    (199, 199, 199),
    (188, 189, 34),
    (219, 219, 141),
    (23, 190, 207),
    (158, 218, 229),
];

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
            let k = VariantSpec::all()
                .iter()
                .position(|s| s.to_string() == id)
                .unwrap_or_else(|| id.bytes().fold(0usize, |h, b| h.wrapping_mul(31).wrapping_add(b as usize)));
            // Stride 7 (coprime with 20): consecutive ids land far apart on the palette.
            PALETTE[(k * 7) % PALETTE.len()]
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_id_keeps_one_colour_and_a_facet_has_no_repeat() {
        let ids: Vec<String> = VariantSpec::all().iter().map(|s| s.to_string()).collect();
        assert_eq!(colour_of(&ids[3]), colour_of(&ids[3].clone()));
        for family in ["cells.thread.", "cells.block-atomic.", "tracking.block-tree."] {
            let mut c: Vec<(u8, u8, u8)> = ids.iter().filter(|i| i.starts_with(family)).map(|i| colour_of(i)).collect();
            let n = c.len();
            c.sort();
            c.dedup();
            assert_eq!(c.len(), n, "{family}: a colour repeats");
        }
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
