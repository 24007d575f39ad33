//! The capillary wave's sensitivity band (case `capillary-wave`, full size only): every run whose
//! rows are judged, made again under the capillary rule's α × 0.5 and × 2 (docs/PHYSICS.md §3.1:
//! p_b × 0.5 and × 2, c0 unchanged, since c0 does not depend on α). Each judged row is built
//! again from the band's runs in place of the rule's, with the same criterion; those rows are
//! shown as the band of the row they repeat, not counted, and the judge sets them beside it.

use super::band_rows::{as_band, at_end, BAND};
use super::case::CaseRun;
use super::report::Row;
use super::scatter::{self, SEEDS};
use super::wave_resolution::{id_at, EXTRA_NX, TANGENTIAL, TANGENTIAL_NX};

/// Committed runs that are band members under other names: the same p_b and c0 set explicitly
/// (the rule's values × 0.5 or × 2), made before the band had its own runs.
const NAMED: [(&str, &str, &str); 4] = [
    ("ratio1", "-alpha1", "ratio1-pb-half"),
    ("ratio1", "-alpha4", "ratio1-pb-double"),
    ("ratio1-nx64", "-alpha4", "ratio1-nx64-pb2"),
    ("ratio1-nx64-tangential", "-alpha1", "ratio1-nx64-tangential-pb0.5"),
];

/// The runs the band repeats: both density ratios and viscous forms at the scene's Δx, the
/// equal-density resolution study (both forms), the tangential form's runs and the jittered
/// starts.
pub fn bases() -> Vec<String> {
    let mut ids: Vec<String> =
        ["ratio1", "ratio1-projected", "ratio1000", "ratio1000-projected"].map(String::from).to_vec();
    for nx in EXTRA_NX {
        ids.extend(["", "-projected"].map(|form| id_at(nx, form)));
    }
    ids.extend(TANGENTIAL_NX.map(|nx| format!("{}{TANGENTIAL}", id_at(nx, ""))));
    ids.extend(SEEDS.map(|s| format!("ratio1{}", scatter::suffix(s))));
    ids
}

/// The id of `base`'s run at the band's end `suffix` (one of [`BAND`]'s).
pub fn member(base: &str, suffix: &str) -> String {
    NAMED
        .iter()
        .find(|(b, s, _)| *b == base && *s == suffix)
        .map_or_else(|| format!("{base}{suffix}"), |(_, _, id)| id.to_string())
}

/// Which band end `id` is a member of, and the run it repeats: (index into [`BAND`], base id).
pub fn of(id: &str) -> Option<(usize, String)> {
    bases().into_iter().find_map(|b| (0..BAND.len()).find(|&k| member(&b, BAND[k].0) == id).map(|k| (k, b)))
}

/// The band's own runs, made from `base_runs` (the case's): each base's spec under α × 0.5 and
/// × 2, with the base's label; members committed under another name are not made again.
pub fn runs(base_runs: &[CaseRun]) -> Vec<CaseRun> {
    let bases = bases();
    let mut out = Vec::new();
    for run in base_runs.iter().filter(|r| bases.contains(&r.spec.id)) {
        for (k, (suffix, _, _)) in BAND.iter().enumerate() {
            if member(&run.spec.id, suffix) != format!("{}{suffix}", run.spec.id) {
                continue;
            }
            let spec = at_end(&run.spec, k);
            out.push(CaseRun::new(spec, run.label.clone()));
        }
    }
    out
}

/// The entries of `v` (each named by the id `id` gives) of the band end `suffix`'s runs, each
/// renamed to the id of the run it repeats, so a row built for the rule's runs reads them.
pub fn under_base_ids<T: Clone>(v: &[T], suffix: &str, id: impl Fn(&mut T) -> &mut String) -> Vec<T> {
    bases()
        .into_iter()
        .filter_map(|b| {
            let m = member(&b, suffix);
            v.iter().cloned().find_map(|mut e| {
                let i = id(&mut e);
                if *i != m {
                    return None;
                }
                *i = b.clone();
                Some(e)
            })
        })
        .collect()
}

/// The rows of band run `key` (labelled `own_label`), measured into `rows` as its base `base`
/// (labelled `label`): the judged ones as band rows of the end `k`; a committed run standing in
/// under another name also keeps its own rows (the 3-period rms, and the fits where its id has
/// them) under its own label, as information.
pub fn member_rows(k: usize, (key, own_label): (&str, &str), base: &str, label: &str, rows: Vec<Row>) -> Vec<Row> {
    let mut out = Vec::new();
    if key != format!("{base}{}", BAND[k].0) {
        let fits = key.starts_with("ratio1-nx");
        let own = rows.iter().filter(|r| {
            r.quantity.starts_with("rms of a/a0 − Prosperetti, t ≤ ")
                || (fits && r.quantity.contains("(damped-cosine fit"))
        });
        out.extend(own.map(|r| {
            let q = r.quantity.strip_suffix(label).map_or(r.quantity.clone(), |head| format!("{head}{own_label}"));
            Row { quantity: q, verdict: "info".into(), ..r.clone() }
        }));
    }
    out.extend(rows.into_iter().filter_map(|r| as_band(k, r)));
    out
}

/// The method note naming the band's runs.
pub fn method_note() -> String {
    let named: Vec<String> = NAMED.iter().map(|(b, s, id)| format!("`{id}` for `{b}{s}`")).collect();
    format!(
        "Sensitivity band: the runs {} made again under the capillary rule's α × 0.5 and × 2 as `<run>-alpha1` and \
         `<run>-alpha4` (p_b × 0.5 / × 2, c0 unchanged), except where a committed run has the same p_b and c0 set \
         explicitly ({}); every judged row built again from each end's runs is shown as the row's band (\"{}: …\", \
         \"{}: …\"), not counted.",
        bases().iter().map(|b| format!("`{b}`")).collect::<Vec<_>>().join(", "),
        named.join(", "),
        BAND[0].2,
        BAND[1].2
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn members_map_to_their_base_and_end_both_ways_including_the_named_ones() {
        assert_eq!(member("ratio1", "-alpha1"), "ratio1-pb-half");
        assert_eq!(member("ratio1-projected", "-alpha4"), "ratio1-projected-alpha4");
        assert_eq!(of("ratio1-pb-double"), Some((1, "ratio1".to_string())));
        assert_eq!(of("ratio1-nx64-pb2"), Some((1, "ratio1-nx64".to_string())));
        assert_eq!(of("ratio1-nx64-tangential-pb0.5"), Some((0, "ratio1-nx64-tangential".to_string())));
        assert_eq!(of("ratio1-jitter0.05-seed2-alpha1"), Some((0, "ratio1-jitter0.05-seed2".to_string())));
        assert_eq!(of("ratio1-nx64-pb0.75"), None);
        assert_eq!(of("ratio1"), None);
    }
}
