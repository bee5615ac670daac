//! Compliance tensors on disk, and a cache keyed by what determines them.
//!
//! **HDF5** (cargo feature `hdf5`, crate `hdf5-metno`, libhdf5 ≥ 1.10):
//! `<body>.compliance.h5` holds the group `/compliance` with the datasets
//!
//! | dataset | shape | content |
//! |---|---|---|
//! | `matrix` | 3N × 3N f64 | C, full symmetric, mm/N, DOF order node-major x, y, z |
//! | `node_ids` | N u64 | node numbers of the body's `<body>.inp` |
//! | `flank_uv` | N × 2 f64 | flank parameters (u, v) |
//! | `positions` | N × 3 f64 | node coordinates (mm) |
//! | `normals` | N × 3 f64 | outward unit normals |
//! | `flank_set` | N u32 | index of the node's flank set in the attribute `flank_sets` |
//! | `faces` | F × 8 i64 | flank faces, indices into `node_ids` (CalculiX face order; −1 pads tri6 faces) |
//!
//! and the attributes `format_version`, `body`, `mesh_hash`, `cache_key`,
//! `clamped_sets` (string array, e.g. `["BORE"]`), `flank_sets`, `material`
//! (text), `young_modulus_mpa` and `poisson_ratio` (one per material),
//! `units`, `method`, and `meta_json` (all of the above as JSON).
//!
//! **Native format** (always available; the default without the feature),
//! `<body>.compliance.bin`, all numbers little-endian:
//!
//! ```text
//! offset 0   8 bytes  magic "FLANKCMP"
//!        8   u32      format version (1)
//!        12  u32      header length H
//!        16  H bytes  header: UTF-8 JSON {"meta": …, "nodes": N, "faces": F, "dim": 3N,
//!                     "matrix": "packed lower triangle, row-major"}
//!        …   u64 × N  node ids;   u32 × N flank set;   f64 × 2N (u, v);
//!            f64 × 3N positions;  f64 × 3N normals;
//!            u32 × 9F faces (node count 6|8, then 8 indices, u32::MAX pads);
//!            u32 × F  face set;
//!            f64 × 3N(3N+1)/2  C, packed lower triangle row by row (row i: columns 0..=i)
//!        end u64      checksum: FNV-1a 64 of every preceding byte, taken as
//!                     little-endian 64-bit words (the last word zero-padded)
//! ```
//!
//! Reading checks the magic, the version (a newer file is refused with its
//! version named), the header, every length against the file size, the
//! checksum and that every value is finite; each failure is a
//! [`FlankError::Parse`] naming the file. Files are written to a temporary
//! name and renamed, so an interrupted run leaves no half-written cache.
//!
//! **Cache.** [`ComplianceCache`](super::tensor_cache::ComplianceCache) keeps tensors by
//! their [`crate::compliance::cache_key`] in memory and in a directory.

use std::io::Write;
use std::path::Path;

use crate::compliance::{ComplianceMeta, ComplianceTensor, FlankFace, FlankNodes, WordHash};
use crate::error::FlankError;

/// Version of the native format and of the HDF5 layout.
pub const FORMAT_VERSION: u32 = 1;
const MAGIC: &[u8; 8] = b"FLANKCMP";

/// On-disk format of a compliance file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum FileFormat {
    /// `<body>.compliance.h5` (feature `hdf5`).
    Hdf5,
    /// `<body>.compliance.bin`.
    Native,
}

impl FileFormat {
    /// HDF5 when built with the `hdf5` feature, native otherwise.
    pub fn default_format() -> Self {
        if cfg!(feature = "hdf5") {
            FileFormat::Hdf5
        } else {
            FileFormat::Native
        }
    }

    pub fn extension(self) -> &'static str {
        match self {
            FileFormat::Hdf5 => "compliance.h5",
            FileFormat::Native => "compliance.bin",
        }
    }

    /// `<body>.compliance.h5` / `<body>.compliance.bin`.
    pub fn file_name(self, body: &str) -> String {
        format!("{body}.{}", self.extension())
    }

    /// The format of a path by its extension.
    pub fn of_path(path: &Path) -> Option<Self> {
        match path.extension().and_then(|e| e.to_str()) {
            Some("h5") | Some("hdf5") => Some(FileFormat::Hdf5),
            Some("bin") => Some(FileFormat::Native),
            _ => None,
        }
    }
}

fn parse_err(path: &Path, message: impl Into<String>) -> FlankError {
    FlankError::Parse {
        file: path.to_path_buf(),
        line: 0,
        message: message.into(),
    }
}

/// Writes `tensor` to `path` in the format of its extension (`.h5` or `.bin`).
pub fn write(path: &Path, tensor: &ComplianceTensor) -> Result<(), FlankError> {
    check_tensor(tensor).map_err(|m| parse_err(path, format!("not written: {m}")))?;
    let format = FileFormat::of_path(path).ok_or_else(|| {
        parse_err(
            path,
            "unknown compliance file extension (use .compliance.h5 or .compliance.bin)",
        )
    })?;
    // a temporary name (unique per process and write) renamed over `path`
    crate::atomic_file::write_with(path, |tmp| match format {
        FileFormat::Native => write_native(tmp, tensor),
        FileFormat::Hdf5 => write_hdf5(tmp, tensor),
    })
}

/// Reads a compliance file written by [`write()`].
pub fn read(path: &Path) -> Result<ComplianceTensor, FlankError> {
    let t = match FileFormat::of_path(path) {
        Some(FileFormat::Native) => read_native(path)?,
        Some(FileFormat::Hdf5) => read_hdf5(path)?,
        None => {
            return Err(parse_err(
                path,
                "unknown compliance file extension (use .compliance.h5 or .compliance.bin)",
            ))
        }
    };
    check_tensor(&t).map_err(|m| parse_err(path, m))?;
    Ok(t)
}

/// Consistency of a tensor: lengths, indices, finite values, symmetry.
fn check_tensor(t: &ComplianceTensor) -> Result<(), String> {
    t.flank.validate().map_err(|e| e.to_string())?;
    let m = t.dim();
    if t.matrix.len() != m * m {
        return Err(format!(
            "matrix has {} entries for {} flank nodes",
            t.matrix.len(),
            t.node_count()
        ));
    }
    if let Some(i) = t.matrix.iter().position(|v| !v.is_finite()) {
        return Err(format!("matrix entry ({}, {}) is not finite", i / m, i % m));
    }
    if t.meta.flank_sets != t.flank.sets {
        return Err("flank sets of the header and of the nodes differ".into());
    }
    if let Some(u) = &t.meta.region_u_min {
        if u.len() != t.flank.sets.len() || u.iter().any(|x| x.is_nan() || *x == f64::INFINITY) {
            return Err(format!(
                "region_u_min has {} entries for {} flank sets, or a NaN / +∞ entry",
                u.len(),
                t.flank.sets.len()
            ));
        }
    }
    Ok(())
}

struct HashWriter<W: Write> {
    w: W,
    hash: WordHash,
}

impl<W: Write> HashWriter<W> {
    fn put(&mut self, b: &[u8]) -> std::io::Result<()> {
        self.hash.update(b);
        self.w.write_all(b)
    }
    fn f64s(&mut self, v: impl IntoIterator<Item = f64>) -> std::io::Result<()> {
        let mut buf = Vec::with_capacity(8192);
        for x in v {
            buf.extend_from_slice(&x.to_le_bytes());
            if buf.len() >= 8192 {
                self.put(&buf)?;
                buf.clear();
            }
        }
        self.put(&buf)
    }
    fn u32s(&mut self, v: impl IntoIterator<Item = u32>) -> std::io::Result<()> {
        let buf: Vec<u8> = v.into_iter().flat_map(|x| x.to_le_bytes()).collect();
        self.put(&buf)
    }
    fn u64s(&mut self, v: impl IntoIterator<Item = u64>) -> std::io::Result<()> {
        let buf: Vec<u8> = v.into_iter().flat_map(|x| x.to_le_bytes()).collect();
        self.put(&buf)
    }
}

#[derive(serde::Serialize, serde::Deserialize)]
struct NativeHeader {
    meta: ComplianceMeta,
    nodes: usize,
    faces: usize,
    dim: usize,
    matrix: String,
}

const PACKED: &str = "packed lower triangle, row-major";

fn write_native(path: &Path, t: &ComplianceTensor) -> Result<(), FlankError> {
    let io = |e| FlankError::io(path, e);
    let file = std::fs::File::create(path).map_err(io)?;
    let mut w = HashWriter {
        w: std::io::BufWriter::with_capacity(1 << 20, file),
        hash: WordHash::new(),
    };
    let n = t.node_count();
    let m = t.dim();
    let header = serde_json::to_vec(&NativeHeader {
        meta: t.meta.clone(),
        nodes: n,
        faces: t.flank.faces.len(),
        dim: m,
        matrix: PACKED.into(),
    })
    .map_err(|e| parse_err(path, format!("header: {e}")))?;
    let hl = u32::try_from(header.len()).map_err(|_| parse_err(path, "header too long"))?;
    w.put(MAGIC).map_err(io)?;
    w.put(&FORMAT_VERSION.to_le_bytes()).map_err(io)?;
    w.put(&hl.to_le_bytes()).map_err(io)?;
    w.put(&header).map_err(io)?;
    let f = &t.flank;
    w.u64s(f.labels.iter().copied()).map_err(io)?;
    w.u32s(f.set_of.iter().copied()).map_err(io)?;
    w.f64s(f.uv.iter().flatten().copied()).map_err(io)?;
    w.f64s(f.positions.iter().flatten().copied()).map_err(io)?;
    w.f64s(f.normals.iter().flatten().copied()).map_err(io)?;
    w.u32s(f.faces.iter().flat_map(|face| {
        let mut row = [u32::MAX; 9];
        row[0] = face.nodes.len() as u32;
        row[1..1 + face.nodes.len()].copy_from_slice(&face.nodes);
        row
    }))
    .map_err(io)?;
    w.u32s(f.faces.iter().map(|face| face.set)).map_err(io)?;
    w.f64s((0..m).flat_map(|i| t.matrix[i * m..i * m + i + 1].iter().copied()))
        .map_err(io)?;
    let sum = w.hash.finish();
    w.w.write_all(&sum.to_le_bytes()).map_err(io)?;
    let file = w.w.into_inner().map_err(|e| io(e.into_error()))?;
    file.sync_all().map_err(io)?;
    Ok(())
}

/// A cursor over the native file's bytes with length checks.
struct Cursor<'a> {
    b: &'a [u8],
    pos: usize,
    path: &'a Path,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], FlankError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.b.len());
        match end {
            Some(e) => {
                let s = &self.b[self.pos..e];
                self.pos = e;
                Ok(s)
            }
            None => Err(parse_err(
                self.path,
                format!(
                    "truncated: {what} ends beyond the file ({} bytes)",
                    self.b.len() + 8
                ),
            )),
        }
    }
    fn count(n: usize, size: usize, path: &Path) -> Result<usize, FlankError> {
        n.checked_mul(size)
            .ok_or_else(|| parse_err(path, "array sizes overflow"))
    }
    fn u32s(&mut self, n: usize, what: &str) -> Result<Vec<u32>, FlankError> {
        let b = self.take(Self::count(n, 4, self.path)?, what)?;
        Ok(b.chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().expect("4 bytes")))
            .collect())
    }
    fn u64s(&mut self, n: usize, what: &str) -> Result<Vec<u64>, FlankError> {
        let b = self.take(Self::count(n, 8, self.path)?, what)?;
        Ok(b.chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect())
    }
    fn f64s(&mut self, n: usize, what: &str) -> Result<Vec<f64>, FlankError> {
        Ok(self
            .u64s(n, what)?
            .into_iter()
            .map(f64::from_bits)
            .collect())
    }
}

/// Matrix words read per chunk (8 MB): the matrix is streamed from the
/// file into its full (symmetric) layout, so reading a tensor holds the
/// matrix once, not the file's bytes beside it.
const READ_CHUNK_WORDS: usize = 1 << 20;

fn read_native(path: &Path) -> Result<ComplianceTensor, FlankError> {
    use std::io::Read;
    let io = |e| FlankError::io(path, e);
    let mut file = std::fs::File::open(path).map_err(io)?;
    let size = usize::try_from(file.metadata().map_err(io)?.len())
        .map_err(|_| parse_err(path, "larger than this machine's address space"))?;
    // magic, format version, header length
    let mut head = vec![0u8; size.min(16)];
    file.read_exact(&mut head).map_err(io)?;
    if head.len() < 8 || &head[..8] != MAGIC {
        return Err(parse_err(
            path,
            "not a flank compliance file (bad magic; expected \"FLANKCMP\")",
        ));
    }
    if size < 24 {
        return Err(parse_err(path, "truncated: no header"));
    }
    let version = u32::from_le_bytes(head[8..12].try_into().expect("4 bytes"));
    if version != FORMAT_VERSION {
        return Err(parse_err(
            path,
            format!(
                "compliance file format version {version}; this build reads version {FORMAT_VERSION}{}",
                if version > FORMAT_VERSION {
                    " (written by a newer flank)"
                } else {
                    ""
                }
            ),
        ));
    }
    // everything before the 8-byte checksum
    let body_len = size - 8;
    let hl = u32::from_le_bytes(head[12..16].try_into().expect("4 bytes")) as usize;
    if hl > body_len - 16 {
        return Err(parse_err(
            path,
            format!("truncated: header ends beyond the file ({size} bytes)"),
        ));
    }
    let mut header_bytes = vec![0u8; hl];
    file.read_exact(&mut header_bytes).map_err(io)?;
    let header: NativeHeader = serde_json::from_slice(&header_bytes)
        .map_err(|e| parse_err(path, format!("header: {e}")))?;
    if header.matrix != PACKED || header.dim != 3 * header.nodes {
        return Err(parse_err(
            path,
            format!(
                "header: matrix layout '{}' of dimension {} for {} nodes is not supported",
                header.matrix, header.dim, header.nodes
            ),
        ));
    }
    let n = header.nodes;
    let nf = header.faces;
    let m = header.dim;
    // every length against the file size before allocating
    let arrays_len = n
        .checked_mul(8 + 4 + 16 + 24 + 24)
        .and_then(|a| a.checked_add(nf.checked_mul(40)?));
    let packed_len = m.checked_mul(m + 1).map(|x| x / 2);
    let expect = arrays_len
        .and_then(|a| a.checked_add(16 + hl))
        .and_then(|s| s.checked_add(packed_len?.checked_mul(8)?));
    let (Some(arrays_len), Some(packed_len), Some(body_len)) =
        (arrays_len, packed_len, expect.filter(|&e| e == body_len))
    else {
        return Err(parse_err(
            path,
            format!(
                "size {size} bytes does not match the header ({n} nodes, {nf} faces): truncated or corrupt"
            ),
        ));
    };
    let mut arrays = vec![0u8; arrays_len];
    file.read_exact(&mut arrays).map_err(io)?;
    let mut h = WordHash::new();
    h.update(&head);
    h.update(&header_bytes);
    h.update(&arrays);
    // the packed lower triangle, row by row, into both triangles
    let mut matrix = vec![0.0; m * m];
    let mut chunk = vec![0u8; 8 * READ_CHUNK_WORDS.min(packed_len)];
    let (mut i, mut j) = (0usize, 0usize);
    let mut left = packed_len;
    while left > 0 {
        let k = left.min(READ_CHUNK_WORDS);
        let words = &mut chunk[..8 * k];
        file.read_exact(words).map_err(io)?;
        h.update(words);
        for w in words.chunks_exact(8) {
            let x = f64::from_bits(u64::from_le_bytes(w.try_into().expect("8 bytes")));
            matrix[i * m + j] = x;
            matrix[j * m + i] = x;
            if j == i {
                i += 1;
                j = 0;
            } else {
                j += 1;
            }
        }
        left -= k;
    }
    drop(chunk);
    let mut tail = [0u8; 8];
    file.read_exact(&mut tail).map_err(io)?;
    debug_assert_eq!(body_len + 8, size);
    if h.finish() != u64::from_le_bytes(tail) {
        return Err(parse_err(path, "checksum mismatch: the file is corrupt"));
    }
    let mut c = Cursor {
        b: &arrays,
        pos: 0,
        path,
    };
    let labels = c.u64s(n, "node ids")?;
    let set_of = c.u32s(n, "flank sets")?;
    let uv = c.f64s(2 * n, "flank (u, v)")?;
    let pos = c.f64s(3 * n, "positions")?;
    let nor = c.f64s(3 * n, "normals")?;
    let faces_raw = c.u32s(9 * nf, "faces")?;
    let face_set = c.u32s(nf, "face sets")?;
    let mut faces = Vec::with_capacity(nf);
    for (k, row) in faces_raw.chunks_exact(9).enumerate() {
        let cnt = row[0] as usize;
        if cnt != 6 && cnt != 8 {
            return Err(parse_err(path, format!("face {k} has {cnt} nodes")));
        }
        faces.push(FlankFace {
            set: face_set[k],
            nodes: row[1..1 + cnt].to_vec(),
        });
    }
    let flank = FlankNodes {
        sets: header.meta.flank_sets.clone(),
        nodes: Vec::new(),
        labels,
        set_of,
        uv: uv.chunks_exact(2).map(|c| [c[0], c[1]]).collect(),
        positions: pos.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        normals: nor.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        faces,
    };
    Ok(ComplianceTensor {
        meta: header.meta,
        flank,
        matrix,
    })
}

#[cfg(not(feature = "hdf5"))]
fn write_hdf5(path: &Path, _t: &ComplianceTensor) -> Result<(), FlankError> {
    Err(parse_err(
        path,
        "HDF5 output needs flank built with the cargo feature `hdf5`; use .compliance.bin",
    ))
}

#[cfg(not(feature = "hdf5"))]
fn read_hdf5(path: &Path) -> Result<ComplianceTensor, FlankError> {
    Err(parse_err(
        path,
        "reading HDF5 needs flank built with the cargo feature `hdf5`",
    ))
}

/// The checksum of an HDF5 compliance file (attribute `checksum`): the
/// native format's FNV-1a 64 over every dataset's values, little-endian, in
/// the order below, then the `meta_json` text (HDF5 itself checks no data).
#[cfg(feature = "hdf5")]
#[allow(clippy::too_many_arguments)]
fn hdf5_checksum(
    matrix: &[f64],
    labels: &[u64],
    uv: &[f64],
    positions: &[f64],
    normals: &[f64],
    set_of: &[u32],
    faces: &[i64],
    face_set: &[u32],
    meta_json: &str,
) -> u64 {
    let mut h = WordHash::new();
    let mut f64s = |v: &[f64]| {
        for x in v {
            h.update(&x.to_le_bytes());
        }
    };
    for v in [matrix, uv, positions, normals] {
        f64s(v);
    }
    for x in labels {
        h.update(&x.to_le_bytes());
    }
    for x in set_of.iter().chain(face_set) {
        h.update(&x.to_le_bytes());
    }
    for x in faces {
        h.update(&x.to_le_bytes());
    }
    h.update(meta_json.as_bytes());
    h.finish()
}

#[cfg(feature = "hdf5")]
fn write_hdf5(path: &Path, t: &ComplianceTensor) -> Result<(), FlankError> {
    use h5::types::VarLenUnicode;
    use hdf5_metno as h5;
    let e = |err: h5::Error| parse_err(path, format!("HDF5: {err}"));
    let vs = |s: &str| -> Result<VarLenUnicode, FlankError> {
        s.parse::<VarLenUnicode>()
            .map_err(|err| parse_err(path, format!("HDF5 string: {err}")))
    };
    let file = h5::File::create(path).map_err(e)?;
    let g = file.create_group("compliance").map_err(e)?;
    let n = t.node_count();
    let m = t.dim();
    let f = &t.flank;
    g.new_dataset::<f64>()
        .shape([m, m])
        .create("matrix")
        .map_err(e)?
        .write_raw(&t.matrix[..])
        .map_err(e)?;
    g.new_dataset::<u64>()
        .shape([n])
        .create("node_ids")
        .map_err(e)?
        .write_raw(&f.labels[..])
        .map_err(e)?;
    let flat2: Vec<f64> = f.uv.iter().flatten().copied().collect();
    g.new_dataset::<f64>()
        .shape([n, 2])
        .create("flank_uv")
        .map_err(e)?
        .write_raw(&flat2[..])
        .map_err(e)?;
    let positions: Vec<f64> = f.positions.iter().flatten().copied().collect();
    let normals: Vec<f64> = f.normals.iter().flatten().copied().collect();
    for (name, flat) in [("positions", &positions), ("normals", &normals)] {
        g.new_dataset::<f64>()
            .shape([n, 3])
            .create(name)
            .map_err(e)?
            .write_raw(&flat[..])
            .map_err(e)?;
    }
    g.new_dataset::<u32>()
        .shape([n])
        .create("flank_set")
        .map_err(e)?
        .write_raw(&f.set_of[..])
        .map_err(e)?;
    let faces: Vec<i64> = f
        .faces
        .iter()
        .flat_map(|face| {
            let mut row = [-1i64; 8];
            for (k, &a) in face.nodes.iter().enumerate() {
                row[k] = a as i64;
            }
            row
        })
        .collect();
    let fs = g
        .new_dataset::<i64>()
        .shape([f.faces.len(), 8])
        .create("faces")
        .map_err(e)?;
    if !faces.is_empty() {
        fs.write_raw(&faces[..]).map_err(e)?;
    }
    let face_set: Vec<u32> = f.faces.iter().map(|x| x.set).collect();
    let fss = g
        .new_dataset::<u32>()
        .shape([f.faces.len()])
        .create("face_set")
        .map_err(e)?;
    if !face_set.is_empty() {
        fss.write_raw(&face_set[..]).map_err(e)?;
    }
    let meta = &t.meta;
    let meta_json = serde_json::to_string(meta).map_err(|err| parse_err(path, err.to_string()))?;
    let checksum = hdf5_checksum(
        &t.matrix, &f.labels, &flat2, &positions, &normals, &f.set_of, &faces, &face_set,
        &meta_json,
    );
    g.new_attr::<u64>()
        .shape(())
        .create("checksum")
        .map_err(e)?
        .write_scalar(&checksum)
        .map_err(e)?;
    let strings = [
        ("body", meta.body.clone()),
        ("mesh_hash", meta.mesh_hash.clone()),
        ("cache_key", meta.cache_key.clone()),
        ("units", meta.units.clone()),
        ("method", meta.method.clone()),
        ("dof_order", "node-major x,y,z".to_string()),
        (
            "material",
            meta.materials
                .iter()
                .map(|(name, e, nu)| format!("{name}: E = {e} MPa, nu = {nu}"))
                .collect::<Vec<_>>()
                .join("; "),
        ),
        ("meta_json", meta_json.clone()),
    ];
    for (name, value) in strings {
        g.new_attr::<VarLenUnicode>()
            .shape(())
            .create(name)
            .map_err(e)?
            .write_scalar(&vs(&value)?)
            .map_err(e)?;
    }
    g.new_attr::<u32>()
        .shape(())
        .create("format_version")
        .map_err(e)?
        .write_scalar(&FORMAT_VERSION)
        .map_err(e)?;
    for (name, list) in [
        ("clamped_sets", &meta.clamped_sets),
        ("flank_sets", &meta.flank_sets),
    ] {
        let v: Vec<VarLenUnicode> = list.iter().map(|s| vs(s)).collect::<Result<_, _>>()?;
        let a = g
            .new_attr::<VarLenUnicode>()
            .shape([v.len()])
            .create(name)
            .map_err(e)?;
        if !v.is_empty() {
            a.write_raw(&v[..]).map_err(e)?;
        }
    }
    let young: Vec<f64> = meta.materials.iter().map(|m| m.1).collect();
    let nu: Vec<f64> = meta.materials.iter().map(|m| m.2).collect();
    for (name, v) in [("young_modulus_mpa", young), ("poisson_ratio", nu)] {
        let a = g
            .new_attr::<f64>()
            .shape([v.len()])
            .create(name)
            .map_err(e)?;
        if !v.is_empty() {
            a.write_raw(&v[..]).map_err(e)?;
        }
    }
    file.flush().map_err(e)?;
    Ok(())
}

#[cfg(feature = "hdf5")]
fn read_hdf5(path: &Path) -> Result<ComplianceTensor, FlankError> {
    use h5::types::VarLenUnicode;
    use hdf5_metno as h5;
    let e = |err: h5::Error| parse_err(path, format!("HDF5: {err}"));
    if !path.exists() {
        return Err(FlankError::io(
            path,
            std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
        ));
    }
    let file = h5::File::open(path).map_err(e)?;
    let g = file
        .group("compliance")
        .map_err(|_| parse_err(path, "no group /compliance: not a flank compliance file"))?;
    let version: u32 = g
        .attr("format_version")
        .and_then(|a| a.read_scalar())
        .map_err(|_| parse_err(path, "no attribute format_version"))?;
    if version != FORMAT_VERSION {
        return Err(parse_err(
            path,
            format!(
                "compliance file format version {version}; this build reads version {FORMAT_VERSION}"
            ),
        ));
    }
    let meta_json: VarLenUnicode = g
        .attr("meta_json")
        .and_then(|a| a.read_scalar())
        .map_err(|_| parse_err(path, "no attribute meta_json"))?;
    let meta: ComplianceMeta = serde_json::from_str(meta_json.as_str())
        .map_err(|err| parse_err(path, format!("meta_json: {err}")))?;
    let ds = |name: &str| {
        g.dataset(name)
            .map_err(|_| parse_err(path, format!("no dataset /compliance/{name}")))
    };
    let labels: Vec<u64> = ds("node_ids")?.read_raw().map_err(e)?;
    let n = labels.len();
    let shape_ok = |name: &str, shape: &[usize]| -> Result<(), FlankError> {
        let s = ds(name)?.shape();
        if s != shape {
            return Err(parse_err(
                path,
                format!("dataset /compliance/{name} has shape {s:?}, expected {shape:?}"),
            ));
        }
        Ok(())
    };
    shape_ok("matrix", &[3 * n, 3 * n])?;
    shape_ok("flank_uv", &[n, 2])?;
    shape_ok("positions", &[n, 3])?;
    shape_ok("normals", &[n, 3])?;
    shape_ok("flank_set", &[n])?;
    let matrix: Vec<f64> = ds("matrix")?.read_raw().map_err(e)?;
    let uv: Vec<f64> = ds("flank_uv")?.read_raw().map_err(e)?;
    let pos: Vec<f64> = ds("positions")?.read_raw().map_err(e)?;
    let nor: Vec<f64> = ds("normals")?.read_raw().map_err(e)?;
    let set_of: Vec<u32> = ds("flank_set")?.read_raw().map_err(e)?;
    let faces_ds = ds("faces")?;
    let fshape = faces_ds.shape();
    if fshape.len() != 2 || fshape[1] != 8 {
        return Err(parse_err(path, format!("faces has shape {fshape:?}")));
    }
    let nf = fshape[0];
    let faces_raw: Vec<i64> = if nf > 0 {
        faces_ds.read_raw().map_err(e)?
    } else {
        Vec::new()
    };
    let face_set: Vec<u32> = if nf > 0 {
        ds("face_set")?.read_raw().map_err(e)?
    } else {
        Vec::new()
    };
    if face_set.len() != nf {
        return Err(parse_err(path, "face_set and faces differ in length"));
    }
    let stored: u64 = g
        .attr("checksum")
        .and_then(|a| a.read_scalar())
        .map_err(|_| {
            parse_err(
                path,
                "no attribute checksum: written by an older flank or not by flank; recompute it",
            )
        })?;
    let sum = hdf5_checksum(
        &matrix,
        &labels,
        &uv,
        &pos,
        &nor,
        &set_of,
        &faces_raw,
        &face_set,
        meta_json.as_str(),
    );
    if sum != stored {
        return Err(parse_err(path, "checksum mismatch: the file is corrupt"));
    }
    let mut faces = Vec::with_capacity(nf);
    for (k, row) in faces_raw.chunks_exact(8).enumerate() {
        let nodes: Vec<u32> = row
            .iter()
            .take_while(|&&v| v >= 0)
            .map(|&v| u32::try_from(v).unwrap_or(u32::MAX))
            .collect();
        faces.push(FlankFace {
            set: face_set[k],
            nodes,
        });
    }
    Ok(ComplianceTensor {
        flank: FlankNodes {
            sets: meta.flank_sets.clone(),
            nodes: Vec::new(),
            labels,
            set_of,
            uv: uv.chunks_exact(2).map(|c| [c[0], c[1]]).collect(),
            positions: pos.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            normals: nor.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            faces,
        },
        meta,
        matrix,
    })
}

/// Reads only the cache key of a compliance file (cheap for native files:
/// the header; HDF5: one attribute).
pub fn read_key(path: &Path) -> Result<String, FlankError> {
    match FileFormat::of_path(path) {
        Some(FileFormat::Native) => {
            use std::io::Read;
            let mut f = std::fs::File::open(path).map_err(|e| FlankError::io(path, e))?;
            let mut head = [0u8; 16];
            f.read_exact(&mut head)
                .map_err(|_| parse_err(path, "truncated: no header"))?;
            if &head[..8] != MAGIC {
                return Err(parse_err(path, "not a flank compliance file (bad magic)"));
            }
            let hl = u32::from_le_bytes(head[12..16].try_into().expect("4")) as usize;
            let mut h = vec![0u8; hl];
            f.read_exact(&mut h)
                .map_err(|_| parse_err(path, "truncated header"))?;
            let header: NativeHeader =
                serde_json::from_slice(&h).map_err(|e| parse_err(path, format!("header: {e}")))?;
            Ok(header.meta.cache_key)
        }
        #[cfg(feature = "hdf5")]
        Some(FileFormat::Hdf5) => {
            use hdf5_metno as h5;
            let file = h5::File::open(path).map_err(|e| parse_err(path, format!("HDF5: {e}")))?;
            let key: h5::types::VarLenUnicode = file
                .group("compliance")
                .and_then(|g| g.attr("cache_key"))
                .and_then(|a| a.read_scalar())
                .map_err(|_| parse_err(path, "no attribute /compliance/cache_key"))?;
            Ok(key.as_str().to_string())
        }
        _ => Ok(read(path)?.meta.cache_key),
    }
}

/// The tensor of `path` if the file exists, names `key` and reads back
/// whole (checksum, lengths, finite values); `None` otherwise. A file that
/// exists but fails is reported on stderr as a warning (it will be
/// recomputed and replaced), never trusted.
pub fn read_trusted(path: &Path, key: &str) -> Option<ComplianceTensor> {
    if !path.exists() {
        return None;
    }
    let r = read_key(path).and_then(|k| {
        if k == key {
            read(path).map(Some)
        } else {
            Ok(None)
        }
    });
    match r {
        Ok(t) => t,
        Err(e) => {
            eprintln!("warning: compliance cache file not used, recomputing it: {e}");
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compliance::flank::tests::box_flank;
    use crate::compliance::{compliance_tensor, ComplianceOptions};
    use crate::mesh::structured::BoxElement;

    fn tensor() -> ComplianceTensor {
        let (model, flank) = box_flank(BoxElement::Hex20);
        compliance_tensor("box", &model, &flank, &ComplianceOptions::default())
            .unwrap()
            .0
    }

    fn tmp(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("flank_cache_test_{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d.join(name)
    }

    fn same(a: &ComplianceTensor, b: &ComplianceTensor) {
        assert_eq!(a.meta, b.meta);
        assert_eq!(a.matrix, b.matrix);
        let mut fa = a.flank.clone();
        fa.nodes.clear();
        assert_eq!(fa, b.flank);
    }

    #[test]
    fn native_round_trip_and_errors() {
        let t = tensor();
        let p = tmp("box.compliance.bin");
        write(&p, &t).unwrap();
        same(&t, &read(&p).unwrap());
        assert_eq!(read_key(&p).unwrap(), t.meta.cache_key);
        let good = std::fs::read(&p).unwrap();
        let check = |bytes: &[u8], what: &str| {
            let q = tmp("bad.compliance.bin");
            std::fs::write(&q, bytes).unwrap();
            let e = read(&q).unwrap_err().to_string();
            assert!(e.contains(what), "expected '{what}' in: {e}");
        };
        // bad magic
        let mut b = good.clone();
        b[0] = b'X';
        check(&b, "bad magic");
        // newer version
        let mut b = good.clone();
        b[8..12].copy_from_slice(&2u32.to_le_bytes());
        check(&b, "format version 2");
        // truncated
        check(&good[..good.len() - 100], "truncated or corrupt");
        // flipped bit in the matrix
        let mut b = good.clone();
        let k = b.len() - 40;
        b[k] ^= 1;
        check(&b, "checksum");
        // unknown extension
        assert!(write(&tmp("x.txt"), &t).is_err());
        assert!(read(&tmp("missing.compliance.bin")).is_err());
    }

    #[cfg(feature = "hdf5")]
    #[test]
    fn hdf5_round_trip() {
        let t = tensor();
        let p = tmp("box.compliance.h5");
        write(&p, &t).unwrap();
        same(&t, &read(&p).unwrap());
        assert_eq!(read_key(&p).unwrap(), t.meta.cache_key);
        std::fs::write(tmp("junk.compliance.h5"), b"not hdf5").unwrap();
        assert!(read(&tmp("junk.compliance.h5")).is_err());
        // one changed value of the matrix: the checksum attribute catches it
        let mut bytes = std::fs::read(&p).unwrap();
        let x = t.matrix[t.matrix.len() / 2].to_le_bytes();
        let at = bytes
            .windows(8)
            .position(|w| w == x)
            .expect("the matrix is stored raw");
        bytes[at] ^= 0x01;
        let bad = tmp("flipped.compliance.h5");
        std::fs::write(&bad, &bytes).unwrap();
        let e = read(&bad).unwrap_err().to_string();
        assert!(e.contains("checksum mismatch"), "{e}");
        // truncated: an HDF5 error, not trusted either
        std::fs::write(&bad, &bytes[..bytes.len() / 2]).unwrap();
        assert!(read(&bad).is_err());
    }
}
