//! Particle snapshots: one CSV file per snapshot, and the same data as VTK XML
//! (`particles_<step>.vtu`, UnstructuredGrid, one VTK_VERTEX cell per particle, point data
//! with particle id, mass and smoothing length) with a ParaView time-series collection
//! (`particles.pvd`) listing every `.vtu` written so far.
//!
//! The XML is written by hand (no XML/VTK crate): the format needed here is small and fixed.
//! Snapshots of fewer than [`VTK_BINARY_MIN`] particles are ASCII, where non-finite values are
//! written as `nan`, `inf`, `-inf` (what `strtod` reads), so a blown-up state still loads and
//! shows where it went wrong; larger ones are inline binary (base64 of a UInt64 byte count
//! followed by the little-endian values), about 3× smaller and much faster to read.

use std::fmt::Write as _;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::{ensure_dir, write_atomic, OutputError, Result};

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

    fn grad_c_at(&self, i: usize) -> [f64; 2] {
        self.grad_c.get(i).copied().unwrap_or([0.0, 0.0])
    }

    /// Phase as a signed integer: walls are -1.
    fn phase_i64(&self, i: usize) -> i64 {
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

/// Formats a float for VTK ASCII: shortest round-trip form, non-finite as `nan`/`inf`/`-inf`.
fn vtk_f64(out: &mut String, v: f64) {
    if v.is_nan() {
        out.push_str("nan");
    } else if v.is_infinite() {
        out.push_str(if v > 0.0 { "inf" } else { "-inf" });
    } else {
        let _ = write!(out, "{v}");
    }
}

/// Standard base64 (RFC 4648, with padding) of `bytes`, appended to `out`.
pub fn base64_into(out: &mut String, bytes: &[u8]) {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for c in bytes.chunks(3) {
        let b = [c[0], *c.get(1).unwrap_or(&0), *c.get(2).unwrap_or(&0)];
        let v = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[(v >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
}

/// The values of one point-data array, flattened (tuple-major).
enum Values {
    /// `Float64`.
    F64(Vec<f64>),
    /// An integer type (`Int32`, `Int64`, `UInt8`) given by name, stored as i64.
    Int(&'static str, Vec<i64>),
}

/// Appends one `DataArray` with `comps` components per tuple, ASCII or binary.
fn data_array(out: &mut String, name: &str, comps: usize, values: Values, binary: bool) {
    let ty = match &values {
        Values::F64(_) => "Float64",
        Values::Int(t, _) => t,
    };
    let _ = write!(out, "        <DataArray type=\"{ty}\" Name=\"{name}\"");
    if comps > 1 {
        let _ = write!(out, " NumberOfComponents=\"{comps}\"");
    }
    let _ = writeln!(out, " format=\"{}\">", if binary { "binary" } else { "ascii" });
    if binary {
        let mut bytes: Vec<u8> = Vec::new();
        match &values {
            Values::F64(v) => v.iter().for_each(|x| bytes.extend_from_slice(&x.to_le_bytes())),
            Values::Int("Int32", v) => v.iter().for_each(|x| bytes.extend_from_slice(&(*x as i32).to_le_bytes())),
            Values::Int("UInt8", v) => v.iter().for_each(|x| bytes.push(*x as u8)),
            Values::Int(_, v) => v.iter().for_each(|x| bytes.extend_from_slice(&x.to_le_bytes())),
        }
        let mut all = (bytes.len() as u64).to_le_bytes().to_vec();
        all.extend_from_slice(&bytes);
        out.push_str("          ");
        base64_into(out, &all);
        out.push('\n');
    } else {
        // One tuple per line for floats, ten values per line for integers.
        let per_line = match &values {
            Values::F64(_) => comps,
            Values::Int(..) => 10,
        };
        let n = match &values {
            Values::F64(v) => v.len(),
            Values::Int(_, v) => v.len(),
        };
        for start in (0..n).step_by(per_line.max(1)) {
            out.push_str("          ");
            for i in start..(start + per_line).min(n) {
                if i > start {
                    out.push(' ');
                }
                match &values {
                    Values::F64(v) => vtk_f64(out, v[i]),
                    Values::Int(_, v) => {
                        let _ = write!(out, "{}", v[i]);
                    }
                }
            }
            out.push('\n');
        }
    }
    out.push_str("        </DataArray>\n");
}

/// The VTK XML UnstructuredGrid text of a snapshot (binary data arrays when `binary`).
pub fn vtu_text(snap: &Snapshot, binary: bool) -> String {
    let n = snap.len();
    let mut s = String::with_capacity(256 + n * if binary { 150 } else { 250 });
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str(
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n",
    );
    s.push_str("  <UnstructuredGrid>\n");
    s.push_str("    <FieldData>\n");
    s.push_str(
        "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" \
         format=\"ascii\">",
    );
    vtk_f64(&mut s, snap.t);
    s.push_str("</DataArray>\n");
    let _ = writeln!(
        s,
        "      <DataArray type=\"Int64\" Name=\"Step\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>",
        snap.step
    );
    s.push_str("    </FieldData>\n");
    let _ = writeln!(s, "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{n}\">");
    s.push_str("      <PointData Scalars=\"rho\" Vectors=\"velocity\">\n");
    let v3 = |f: &dyn Fn(usize) -> [f64; 2]| {
        Values::F64(
            (0..n)
                .flat_map(|i| {
                    let v = f(i);
                    [v[0], v[1], 0.0]
                })
                .collect(),
        )
    };
    data_array(&mut s, "id", 1, Values::Int("Int64", (0..n as i64).collect()), binary);
    data_array(&mut s, "velocity", 3, v3(&|i| snap.vel[i]), binary);
    data_array(&mut s, "rho", 1, Values::F64(snap.rho.clone()), binary);
    data_array(&mut s, "p", 1, Values::F64(snap.p.clone()), binary);
    data_array(
        &mut s,
        "mass",
        1,
        Values::F64((0..n).map(|i| snap.mass.get(i).copied().unwrap_or(0.0)).collect()),
        binary,
    );
    data_array(&mut s, "h", 1, Values::F64(vec![snap.h; n]), binary);
    data_array(&mut s, "phase", 1, Values::Int("Int32", (0..n).map(|i| snap.phase_i64(i)).collect()), binary);
    data_array(&mut s, "grad_c", 3, v3(&|i| snap.grad_c_at(i)), binary);
    s.push_str("      </PointData>\n");
    s.push_str("      <Points>\n");
    data_array(&mut s, "Points", 3, v3(&|i| snap.pos[i]), binary);
    s.push_str("      </Points>\n");
    s.push_str("      <Cells>\n");
    data_array(&mut s, "connectivity", 1, Values::Int("Int64", (0..n as i64).collect()), binary);
    data_array(&mut s, "offsets", 1, Values::Int("Int64", (1..=n as i64).collect()), binary);
    // VTK_VERTEX = 1
    data_array(&mut s, "types", 1, Values::Int("UInt8", vec![1; n]), binary);
    s.push_str("      </Cells>\n");
    s.push_str("    </Piece>\n");
    s.push_str("  </UnstructuredGrid>\n");
    s.push_str("</VTKFile>\n");
    s
}

/// Writes `DIR/particles_<step>.vtu` (VTK XML UnstructuredGrid; binary from
/// [`VTK_BINARY_MIN`] particles, else ASCII): points with z = 0, one VTK_VERTEX cell per
/// particle, point data `id` (Int64), `velocity` (3 components), `rho`, `p`, `mass`, `h`,
/// `phase` (Int32, walls -1) and `grad_c` (3 components); the time is stored as field data
/// `TimeValue`. Creates `dir` if missing; returns the file's path.
pub fn write_vtu(dir: impl AsRef<Path>, snap: &Snapshot) -> Result<PathBuf> {
    let dir = dir.as_ref();
    let path = dir.join(vtu_name(snap.step));
    snap.check(&path)?;
    ensure_dir(dir)?;
    let text = vtu_text(snap, snap.len() >= VTK_BINARY_MIN);
    let file = File::create(&path).map_err(|e| OutputError::io(&path, e))?;
    let mut w = BufWriter::new(file);
    w.write_all(text.as_bytes()).and_then(|_| w.flush()).map_err(|e| OutputError::io(&path, e))?;
    Ok(path)
}

/// Escapes the five XML special characters for an attribute value.
fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// A ParaView time series (`DIR/particles.pvd`): collects `(t, file name)` entries and rewrites
/// the whole `.pvd` (atomically, via a temporary file) after each one, so a run that dies still
/// leaves a valid collection of every snapshot written so far. File names are relative to
/// `dir`.
#[derive(Debug, Clone)]
pub struct PvdWriter {
    dir: PathBuf,
    path: PathBuf,
    entries: Vec<(f64, String)>,
}

impl PvdWriter {
    /// File name of the collection.
    pub const FILE_NAME: &'static str = "particles.pvd";

    /// A collection in `dir` with no entry yet (nothing is written until [`add`](Self::add)).
    pub fn new(dir: impl AsRef<Path>) -> Self {
        let dir = dir.as_ref().to_path_buf();
        let path = dir.join(Self::FILE_NAME);
        PvdWriter { dir, path, entries: Vec::new() }
    }

    /// Path of the `.pvd` file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The `(t, file name)` entries so far.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// Adds an entry (a file name relative to the collection's directory) and rewrites the
    /// `.pvd`.
    pub fn add(&mut self, t: f64, file_name: impl Into<String>) -> Result<()> {
        self.entries.push((t, file_name.into()));
        self.write()
    }

    /// Writes the snapshot's `.vtu` with [`write_vtu`], adds it, rewrites the `.pvd`; returns
    /// the `.vtu` path.
    pub fn add_snapshot(&mut self, snap: &Snapshot) -> Result<PathBuf> {
        let vtu = write_vtu(&self.dir, snap)?;
        self.add(snap.t, vtu_name(snap.step))?;
        Ok(vtu)
    }

    /// Writes the `.pvd` with the current entries (also valid with none).
    pub fn write(&self) -> Result<()> {
        let mut s = String::with_capacity(160 + 80 * self.entries.len());
        s.push_str("<?xml version=\"1.0\"?>\n");
        s.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
        s.push_str("  <Collection>\n");
        for (t, name) in &self.entries {
            s.push_str("    <DataSet timestep=\"");
            vtk_f64(&mut s, *t);
            let _ = writeln!(s, "\" group=\"\" part=\"0\" file=\"{}\"/>", xml_escape(name));
        }
        s.push_str("  </Collection>\n");
        s.push_str("</VTKFile>\n");
        write_atomic(&self.path, s.as_bytes())
    }
}
