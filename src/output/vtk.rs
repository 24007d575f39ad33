//! Particle snapshots as VTK XML (`particles_<step>.vtu`, UnstructuredGrid, one VTK_VERTEX
//! cell per particle, point data with particle id, mass and smoothing length) with a ParaView
//! time-series collection (`particles.pvd`) listing every `.vtu` written so far.
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

use super::snapshot::{vtu_name, Snapshot, VTK_BINARY_MIN};
use super::{ensure_dir, write_atomic, OutputError, Result};
use crate::fallible::AllocError;

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
    let mut b = Base64::new(out);
    b.push(bytes);
    b.finish();
}

/// Streaming base64: bytes in, text appended to a string, padding at [`Base64::finish`].
struct Base64<'a> {
    out: &'a mut String,
    carry: [u8; 3],
    held: usize,
}

impl<'a> Base64<'a> {
    const ALPHABET: &'static [u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

    fn new(out: &'a mut String) -> Self {
        Base64 { out, carry: [0; 3], held: 0 }
    }

    /// Encodes the held bytes (1–3), padding a short group with `=`.
    fn flush(&mut self) {
        let c = &self.carry;
        let v = (c[0] as u32) << 16 | (c[1] as u32) << 8 | c[2] as u32;
        for k in 0..4 {
            if k <= self.held {
                self.out.push(Self::ALPHABET[(v >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                self.out.push('=');
            }
        }
        (self.carry, self.held) = ([0; 3], 0);
    }

    fn push(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.carry[self.held] = b;
            self.held += 1;
            if self.held == 3 {
                self.flush();
            }
        }
    }

    fn finish(mut self) {
        if self.held > 0 {
            self.flush();
        }
    }
}

/// One value of a point-data array.
#[derive(Clone, Copy)]
enum Value {
    F64(f64),
    Int(i64),
}

/// One `DataArray`: its VTK type (`Float64`, `Int64`, `Int32`, `UInt8`), components per tuple,
/// number of values (tuples × components) and the value at each flat index.
struct Array<'a> {
    name: &'a str,
    ty: &'static str,
    comps: usize,
    len: usize,
    value: &'a dyn Fn(usize) -> Value,
}

impl Array<'_> {
    /// Bytes of one value in binary form.
    fn width(&self) -> usize {
        match self.ty {
            "Int32" => 4,
            "UInt8" => 1,
            _ => 8,
        }
    }
}

/// Values per line of an ASCII array: one tuple per line for floats, ten values for integers.
fn per_line(ty: &str, comps: usize) -> usize {
    if ty == "Float64" {
        comps.max(1)
    } else {
        10
    }
}

/// Upper bound of the text of an array of `len` values (`comps` per tuple, `width` bytes each
/// in binary) besides its tags: base64 of the byte count and the values, or at most 25
/// characters per ASCII value plus indentation and line ends.
fn text_bytes(len: usize, comps: usize, width: usize, ty: &str, binary: bool) -> usize {
    if binary {
        (8 + len * width).div_ceil(3) * 4 + 12
    } else {
        let per = per_line(ty, comps);
        len.div_ceil(per) * (11 + 25 * per)
    }
}

/// Bytes the VTK writer holds for a snapshot of `n` particles: the text of its largest data
/// array (3 f64 components per particle), with tags.
pub fn vtk_buffer_bytes(n: f64) -> f64 {
    let n = n.clamp(0.0, 1e15) as usize;
    (text_bytes(3 * n, 3, 8, "Float64", n >= VTK_BINARY_MIN) + 256) as f64
}

/// Appends one `DataArray`, ASCII or binary, after reserving its text fallibly.
fn data_array(out: &mut String, a: &Array, binary: bool) -> std::result::Result<(), AllocError> {
    crate::fallible::reserve_str(
        out,
        text_bytes(a.len, a.comps, a.width(), a.ty, binary) + 256,
        "the VTK text of one data array",
    )?;
    let _ = write!(out, "        <DataArray type=\"{}\" Name=\"{}\"", a.ty, a.name);
    if a.comps > 1 {
        let _ = write!(out, " NumberOfComponents=\"{}\"", a.comps);
    }
    let _ = writeln!(out, " format=\"{}\">", if binary { "binary" } else { "ascii" });
    if binary {
        out.push_str("          ");
        let mut b = Base64::new(out);
        b.push(&((a.len * a.width()) as u64).to_le_bytes());
        for i in 0..a.len {
            match ((a.value)(i), a.ty) {
                (Value::F64(x), _) => b.push(&x.to_le_bytes()),
                (Value::Int(x), "Int32") => b.push(&(x as i32).to_le_bytes()),
                (Value::Int(x), "UInt8") => b.push(&[x as u8]),
                (Value::Int(x), _) => b.push(&x.to_le_bytes()),
            }
        }
        b.finish();
        out.push('\n');
    } else {
        let per = per_line(a.ty, a.comps);
        for start in (0..a.len).step_by(per) {
            out.push_str("          ");
            for i in start..(start + per).min(a.len) {
                if i > start {
                    out.push(' ');
                }
                match (a.value)(i) {
                    Value::F64(x) => vtk_f64(out, x),
                    Value::Int(x) => {
                        let _ = write!(out, "{x}");
                    }
                }
            }
            out.push('\n');
        }
    }
    out.push_str("        </DataArray>\n");
    Ok(())
}

/// An error of [`vtu_pieces`]: an allocation, or what `emit` returned.
enum PieceError<E> {
    Alloc(AllocError),
    Emit(E),
}

/// The VTK XML UnstructuredGrid text of a snapshot (binary data arrays when `binary`), handed
/// to `emit` in pieces of at most one data array each, so a writer holds one array's text at
/// a time ([`vtk_buffer_bytes`]).
fn vtu_pieces<E>(
    snap: &Snapshot,
    binary: bool,
    emit: &mut dyn FnMut(&str) -> std::result::Result<(), E>,
) -> std::result::Result<(), PieceError<E>> {
    let n = snap.len();
    let mut s = String::with_capacity(1024);
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
    let v3 = |f: fn(&Snapshot, usize) -> [f64; 2]| {
        move |k: usize| Value::F64(if k % 3 == 2 { 0.0 } else { f(snap, k / 3)[k % 3] })
    };
    let (vel, grad, pts) = (v3(|s, i| s.vel[i]), v3(|s, i| s.grad_c_at(i)), v3(|s, i| s.pos[i]));
    let (rho, p) = (|i: usize| Value::F64(snap.rho[i]), |i: usize| Value::F64(snap.p[i]));
    let mass = |i: usize| Value::F64(snap.mass.get(i).copied().unwrap_or(0.0));
    let (h, phase) = (|_| Value::F64(snap.h), |i: usize| Value::Int(snap.phase_i64(i)));
    let (id, offset, vertex) =
        (|i: usize| Value::Int(i as i64), |i: usize| Value::Int(i as i64 + 1), |_| Value::Int(1));
    let arr = |name, ty, comps, value| Array { name, ty, comps, len: comps * n, value };
    let point_data = [
        arr("id", "Int64", 1, &id as &dyn Fn(usize) -> Value),
        arr("velocity", "Float64", 3, &vel),
        arr("rho", "Float64", 1, &rho),
        arr("p", "Float64", 1, &p),
        arr("mass", "Float64", 1, &mass),
        arr("h", "Float64", 1, &h),
        arr("phase", "Int32", 1, &phase),
        arr("grad_c", "Float64", 3, &grad),
    ];
    // VTK_VERTEX = 1
    let cells =
        [arr("connectivity", "Int64", 1, &id), arr("offsets", "Int64", 1, &offset), arr("types", "UInt8", 1, &vertex)];
    let mut put = |s: &mut String, a: &Array| -> std::result::Result<(), PieceError<E>> {
        emit(s).map_err(PieceError::Emit)?;
        s.clear();
        data_array(s, a, binary).map_err(PieceError::Alloc)
    };
    for a in &point_data {
        put(&mut s, a)?;
    }
    s.push_str("      </PointData>\n");
    s.push_str("      <Points>\n");
    put(&mut s, &arr("Points", "Float64", 3, &pts))?;
    s.push_str("      </Points>\n");
    s.push_str("      <Cells>\n");
    for a in &cells {
        put(&mut s, a)?;
    }
    s.push_str("      </Cells>\n");
    s.push_str("    </Piece>\n");
    s.push_str("  </UnstructuredGrid>\n");
    s.push_str("</VTKFile>\n");
    emit(&s).map_err(PieceError::Emit)
}

/// The VTK XML UnstructuredGrid text of a snapshot (binary data arrays when `binary`), whole.
pub fn vtu_text(snap: &Snapshot, binary: bool) -> String {
    let mut text = String::new();
    let _ = vtu_pieces::<()>(snap, binary, &mut |piece| {
        text.push_str(piece);
        Ok(())
    });
    text
}

/// Writes `DIR/particles_<step>.vtu` (VTK XML UnstructuredGrid; binary from
/// [`VTK_BINARY_MIN`] particles, else ASCII): points with z = 0, one VTK_VERTEX cell per
/// particle, point data `id` (Int64), `velocity` (3 components), `rho`, `p`, `mass`, `h`,
/// `phase` (Int32, walls -1) and `grad_c` (3 components); the time is stored as field data
/// `TimeValue`. The text is written one data array at a time ([`vtk_buffer_bytes`]); a buffer
/// that cannot be allocated is [`OutputError::Alloc`]. Creates `dir` if missing; returns the
/// file's path.
pub fn write_vtu(dir: impl AsRef<Path>, snap: &Snapshot) -> Result<PathBuf> {
    let dir = dir.as_ref();
    let path = dir.join(vtu_name(snap.step));
    snap.check(&path)?;
    ensure_dir(dir)?;
    let file = File::create(&path).map_err(|e| OutputError::io(&path, e))?;
    let mut w = BufWriter::new(file);
    vtu_pieces(snap, snap.len() >= VTK_BINARY_MIN, &mut |piece| w.write_all(piece.as_bytes())).map_err(
        |e| match e {
            PieceError::Alloc(source) => OutputError::Alloc { path: path.clone(), source },
            PieceError::Emit(e) => OutputError::io(&path, e),
        },
    )?;
    w.flush().map_err(|e| OutputError::io(&path, e))?;
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
