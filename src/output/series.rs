//! A CSV time series: one `serde::Serialize` row struct per line, the header taken from the
//! first row's field names. Every row is flushed to the file at once, so a run that blows up
//! (or is killed) keeps every row written so far.

use std::fs::File;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::{ensure_parent, OutputError, Result};

/// Writes rows of a `Serialize` struct (flat fields only: numbers, strings, bools, options) to
/// a CSV file, flushing after each row.
#[derive(Debug)]
pub struct SeriesWriter {
    path: PathBuf,
    writer: csv::Writer<File>,
    rows: u64,
}

impl SeriesWriter {
    /// Creates (truncates) the file at `path`, creating its parent directory if missing.
    pub fn create(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref().to_path_buf();
        ensure_parent(&path)?;
        let file = File::create(&path).map_err(|e| OutputError::io(&path, e))?;
        Ok(SeriesWriter { writer: csv::Writer::from_writer(file), path, rows: 0 })
    }

    /// Appends one row (the first row also writes the header) and flushes it to the file.
    pub fn write<R: Serialize>(&mut self, row: &R) -> Result<()> {
        self.writer.serialize(row).map_err(|e| OutputError::csv(&self.path, e))?;
        self.writer.flush().map_err(|e| OutputError::io(&self.path, e))?;
        self.rows += 1;
        Ok(())
    }

    /// Number of rows written (not counting the header).
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Path of the file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes and closes the file, returning its path.
    pub fn finish(mut self) -> Result<PathBuf> {
        self.writer.flush().map_err(|e| OutputError::io(&self.path, e))?;
        Ok(self.path)
    }
}
