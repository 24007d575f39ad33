//! The files a run leaves behind, written from plain data (no solver types):
//!
//! * [`snapshot`]: particle snapshots as CSV, and [`vtk`]: as VTK (`.vtu` files plus a
//!   ParaView `.pvd` time series), streamed: a writer holds one row or one data array at a time;
//! * [`series`]: a CSV time series of any `serde::Serialize` row, flushed after every row;
//! * [`summary`]: pretty JSON summaries, the git commit and a UTC timestamp;
//! * [`progress`]: a terminal progress bar that is silent when stderr is not a terminal.
//!
//! Every fallible function returns [`OutputError`], which names the path involved.

pub(crate) mod progress;
pub(crate) mod series;
pub(crate) mod snapshot;
pub mod summary;
pub(crate) mod vtk;

use std::path::{Path, PathBuf};

pub use progress::Progress;
pub use series::SeriesWriter;
pub use snapshot::{
    base64_into, particles_csv_name, vtu_name, vtu_text, write_particles_csv, write_vtu, PvdWriter, Snapshot,
    VTK_BINARY_MIN,
};
pub use summary::{git_commit, iso8601_from_unix, now_utc_iso8601, write_json};

/// An error while writing an output file; every variant names the path involved.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// Creating, writing, renaming or reading a file or directory failed.
    #[error("I/O error on {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The CSV writer failed (serialisation or I/O).
    #[error("CSV error on {}: {source}", path.display())]
    Csv {
        path: PathBuf,
        #[source]
        source: csv::Error,
    },
    /// JSON serialisation failed.
    #[error("JSON error on {}: {source}", path.display())]
    Json {
        path: PathBuf,
        #[source]
        source: serde_json::Error,
    },
    /// Drawing a plot failed, or the plot specification is unusable (e.g. a non-positive range
    /// on a log axis).
    #[error("plot error on {}: {message}", path.display())]
    Plot { path: PathBuf, message: String },
    /// The data handed over is inconsistent (e.g. snapshot arrays of different lengths).
    #[error("invalid data for {}: {message}", path.display())]
    Data { path: PathBuf, message: String },
    /// A buffer for the file could not be allocated.
    #[error("{source}, writing {}", path.display())]
    Alloc {
        path: PathBuf,
        #[source]
        source: crate::fallible::AllocError,
    },
}

/// Result type of the output module.
pub type Result<T> = std::result::Result<T, OutputError>;

impl OutputError {
    pub(crate) fn io(path: impl AsRef<Path>, source: std::io::Error) -> Self {
        OutputError::Io { path: path.as_ref().to_path_buf(), source }
    }
    pub(crate) fn csv(path: impl AsRef<Path>, source: csv::Error) -> Self {
        OutputError::Csv { path: path.as_ref().to_path_buf(), source }
    }
    pub(crate) fn plot(path: impl AsRef<Path>, message: impl Into<String>) -> Self {
        OutputError::Plot { path: path.as_ref().to_path_buf(), message: message.into() }
    }
    /// The path this error is about.
    pub fn path(&self) -> &Path {
        match self {
            OutputError::Io { path, .. }
            | OutputError::Csv { path, .. }
            | OutputError::Json { path, .. }
            | OutputError::Plot { path, .. }
            | OutputError::Data { path, .. }
            | OutputError::Alloc { path, .. } => path,
        }
    }
}

/// Longest file-name component most file systems accept (bytes).
pub const MAX_NAME_BYTES: usize = 255;

/// Checks, without creating anything, that `dir` can be an output directory: a non-empty path,
/// no component longer than [`MAX_NAME_BYTES`], not an existing non-directory, not under a
/// virtual file system (`/proc`, `/sys`, `/dev`), and its nearest existing ancestor a directory.
/// The message says what is wrong with the path (the caller names the option).
pub fn check_out_dir(dir: &Path) -> std::result::Result<(), String> {
    if dir.as_os_str().is_empty() {
        return Err("the output directory is an empty path".into());
    }
    for c in dir.components() {
        let len = c.as_os_str().len();
        if len > MAX_NAME_BYTES {
            return Err(format!(
                "a path component has {len} bytes, over the {MAX_NAME_BYTES}-byte limit of file names: {}",
                dir.display()
            ));
        }
    }
    if let Ok(m) = std::fs::metadata(dir) {
        if !m.is_dir() {
            return Err(format!("{} exists and is not a directory", dir.display()));
        }
    }
    let mut anc = dir.to_path_buf();
    while !anc.exists() {
        match anc.parent() {
            Some(p) if !p.as_os_str().is_empty() => anc = p.to_path_buf(),
            _ => {
                anc = PathBuf::from(".");
                break;
            }
        }
    }
    let real = std::fs::canonicalize(&anc).unwrap_or(anc.clone());
    for v in ["/proc", "/sys", "/dev"] {
        if real.starts_with(v) {
            return Err(format!("{} lies under {v}, a virtual file system", dir.display()));
        }
    }
    if !real.is_dir() {
        return Err(format!("{} is not a directory, so {} cannot be created", anc.display(), dir.display()));
    }
    match std::fs::metadata(&real) {
        Ok(m) if m.permissions().readonly() => {
            Err(format!("{} is read-only, so {} cannot be created", real.display(), dir.display()))
        }
        _ => Ok(()),
    }
}

/// Creates `dir` (and its parents) if missing.
pub(crate) fn ensure_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::io(dir, e))
}

/// Creates the parent directory of `path` if it has one and it is missing.
pub(crate) fn ensure_parent(path: &Path) -> Result<()> {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => ensure_dir(p),
        _ => Ok(()),
    }
}

/// Writes `contents` to `path` via a temporary sibling file and a rename, so a reader (or a run
/// that dies mid-write) never sees a half-written file.
pub(crate) fn write_atomic(path: &Path, contents: &[u8]) -> Result<()> {
    ensure_parent(path)?;
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    std::fs::write(&tmp, contents).map_err(|e| OutputError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| OutputError::io(path, e))
}
