//! Run summaries: pretty JSON files, the commit sphlab was built from, and a UTC timestamp in
//! ISO 8601 (computed from `std::time::SystemTime` with a civil-from-days conversion, so no
//! date crate is needed).

use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

use serde::Serialize;

use super::{write_atomic, OutputError, Result};

/// Environment variable that, when set and non-empty, is returned by [`git_commit`] as is.
pub const GIT_COMMIT_ENV: &str = "SPHLAB_GIT_COMMIT";

/// Writes `value` as pretty-printed JSON (with a final newline) to `path`, creating the parent
/// directory if missing. The file is replaced atomically.
pub fn write_json(path: impl AsRef<Path>, value: &impl Serialize) -> Result<()> {
    let path = path.as_ref();
    let mut text =
        serde_json::to_string_pretty(value).map_err(|e| OutputError::Json { path: path.to_path_buf(), source: e })?;
    text.push('\n');
    write_atomic(path, text.as_bytes())
}

/// The commit sphlab was built from, baked in by `build.rs` (`abc1234567`, with `-dirty` when
/// the build had uncommitted changes; "unknown" when built outside a git checkout), whatever
/// directory the program runs in. `$SPHLAB_GIT_COMMIT`, when set and non-empty, replaces it
/// (for tests and for builds from a source archive).
pub fn git_commit() -> String {
    if let Ok(v) = std::env::var(GIT_COMMIT_ENV) {
        let v = v.trim();
        if !v.is_empty() {
            return v.to_string();
        }
    }
    crate::provenance::commit_label()
}

/// The current UTC time as `YYYY-MM-DDTHH:MM:SSZ`.
pub fn now_utc_iso8601() -> String {
    let secs = match SystemTime::now().duration_since(UNIX_EPOCH) {
        Ok(d) => d.as_secs() as i64,
        Err(e) => -(e.duration().as_secs_f64().ceil() as i64),
    };
    iso8601_from_unix(secs)
}

/// Formats seconds since the Unix epoch (UTC, negative before 1970) as `YYYY-MM-DDTHH:MM:SSZ`.
pub fn iso8601_from_unix(secs: i64) -> String {
    let days = secs.div_euclid(86_400);
    let sod = secs.rem_euclid(86_400);
    let (y, m, d) = civil_from_days(days);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", sod / 3600, (sod % 3600) / 60, sod % 60)
}

/// Proleptic Gregorian (year, month 1–12, day 1–31) of `days` since 1970-01-01
/// (H. Hinnant's `civil_from_days`).
pub fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097); // [0, 146096]
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365; // [0, 399]
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100); // [0, 365]
    let mp = (5 * doy + 2) / 153; // [0, 11], March-based
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}
