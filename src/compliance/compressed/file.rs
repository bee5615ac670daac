//! The native file of a [`BlrTensor`] (`<body>.compression.bin`): its
//! bytes ([`BlrTensor::to_bytes`]) and their reading
//! ([`BlrTensor::read`]), which refuses a corrupt, stale or other-ε file
//! with the reason.

use crate::compliance::compressed::{page_len, Block, BlrOptions, BlrStats, BlrTensor};
use crate::compliance::page_order::{paged_order, paged_positions, PAGE};
use crate::compliance::{ComplianceTensor, Fnv128, WordHash};
use crate::error::FlankError;

/// Magic bytes and version of the native file of a [`BlrTensor`].
/// Version 2 ends with an FNV-1a 64 checksum over 64-bit words
/// ([`crate::compliance::WordHash`], 8 bytes); version 1, still read, with
/// an FNV-1a 128 over bytes (16 bytes), which took 3.2 of the 7.9 s of
/// reading seed 002's 0.1 mm tensors (2.3 GB).
const MAGIC: &[u8; 8] = b"FLANKBLR";
const VERSION: u32 = 2;

/// The header of a [`BlrTensor`] file (JSON after the magic and version).
#[derive(serde::Serialize, serde::Deserialize)]
struct FileHeader {
    cache_key: String,
    dim: usize,
    nodes: usize,
    page: usize,
    pages: usize,
    stats: BlrStats,
}

impl BlrTensor {
    /// The file bytes: magic, version, JSON header, the paged order (u32),
    /// per block a kind byte (0 dense, 1 low rank), the rank (u32) and the
    /// values (f64, little endian), then the checksum of all that
    /// (`crate::compliance::WordHash`, u64).
    pub fn to_bytes(&self) -> Vec<u8> {
        let header = serde_json::to_vec(&FileHeader {
            cache_key: self.cache_key.clone(),
            dim: self.dim,
            nodes: self.order.len(),
            page: PAGE,
            pages: self.pages,
            stats: self.stats.clone(),
        })
        .expect("BLR header to JSON");
        let mut out = Vec::with_capacity(self.stats.compressed_bytes + header.len() + 64);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        out.extend_from_slice(&(header.len() as u64).to_le_bytes());
        out.extend_from_slice(&header);
        for &a in &self.order {
            out.extend_from_slice(&a.to_le_bytes());
        }
        for b in &self.blocks {
            let (kind, rank, parts): (u8, usize, [&[f64]; 2]) = match b {
                Block::Dense(d) => (0, 0, [d, &[]]),
                Block::LowRank { rank, u, v } => (1, *rank, [u, v]),
            };
            out.push(kind);
            out.extend_from_slice(&(rank as u32).to_le_bytes());
            for x in parts.iter().flat_map(|p| p.iter()) {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        let mut h = crate::compliance::WordHash::new();
        h.update(&out);
        out.extend_from_slice(&h.finish().to_le_bytes());
        out
    }

    /// Writes [`Self::to_bytes`] to `path` (atomically).
    pub fn write(&self, path: &std::path::Path) -> Result<(), FlankError> {
        crate::atomic_file::write(path, self.to_bytes())
    }

    /// Reads the compression of `t` at accuracy `epsilon` from `path`: an
    /// error naming the reason when the file is corrupt, of another
    /// version, of another tensor (cache key, dimension, node order) or of
    /// another accuracy, never another tensor's values. The file is read
    /// in order straight into the blocks (`FileReader`): no whole-file
    /// buffer, and a stale file is refused after its header.
    pub fn read(
        path: &std::path::Path,
        t: &ComplianceTensor,
        epsilon: f64,
    ) -> Result<Self, FlankError> {
        let file = std::fs::File::open(path).map_err(|e| FlankError::io(path, e))?;
        let len = file.metadata().map_err(|e| FlankError::io(path, e))?.len();
        let src = std::io::BufReader::with_capacity(1 << 16, file);
        Self::from_reader(src, len, t, epsilon)
            .map_err(|e| FlankError::Model(format!("{}: {e}", path.display())))
    }

    /// [`Self::read`] from the file's bytes.
    #[cfg(test)]
    pub(crate) fn from_bytes(
        bytes: &[u8],
        t: &ComplianceTensor,
        epsilon: f64,
    ) -> Result<Self, String> {
        Self::from_reader(bytes, bytes.len() as u64, t, epsilon)
    }

    /// [`Self::read`] from `len` bytes of `src`.
    fn from_reader(
        src: impl std::io::Read,
        len: u64,
        t: &ComplianceTensor,
        epsilon: f64,
    ) -> Result<Self, String> {
        let mut f = FileReader::open(src, len)?;
        let hlen = u64::from_le_bytes(f.array()?) as usize;
        let header: FileHeader =
            serde_json::from_slice(&f.bytes(hlen)?).map_err(|e| format!("header: {e}"))?;
        if header.cache_key != t.meta.cache_key || header.dim != t.dim() {
            return Err(format!(
                "compression of tensor {} (dimension {}), not of {} (dimension {})",
                header.cache_key,
                header.dim,
                t.meta.cache_key,
                t.dim()
            ));
        }
        if header.stats.epsilon != epsilon {
            return Err(format!(
                "compressed to ε = {:e}, asked for {epsilon:e}",
                header.stats.epsilon
            ));
        }
        let n = t.node_count();
        let pages = n.div_ceil(PAGE);
        if header.page != PAGE || header.pages != pages || header.nodes != n {
            return Err(format!(
                "page layout {} × {} nodes, expected {pages} × {PAGE}",
                header.pages, header.page
            ));
        }
        let order: Vec<u32> = f
            .bytes(4 * n)?
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().expect("4 bytes")))
            .collect();
        if order != paged_order(t) {
            return Err("another flank node order than the tensor's pages".into());
        }
        let mut blocks = Vec::with_capacity(pages * (pages + 1) / 2);
        for r in 0..pages {
            for q in 0..=r {
                let (rows, cols) = (3 * page_len(n, r), 3 * page_len(n, q));
                let [kind] = f.array()?;
                let rank = u32::from_le_bytes(f.array()?) as usize;
                blocks.push(match kind {
                    0 => Block::Dense(f.f64s(rows * cols)?),
                    1 if rank <= rows.min(cols) => Block::LowRank {
                        rank,
                        u: f.f64s(rows * rank)?,
                        v: f.f64s(cols * rank)?,
                    },
                    _ => {
                        return Err(format!(
                            "corrupt file: bad block ({r}, {q}): kind {kind}, rank {rank}"
                        ))
                    }
                });
            }
        }
        f.finish()?;
        let position = paged_positions(&order);
        Ok(BlrTensor {
            dim: t.dim(),
            cache_key: header.cache_key,
            order,
            position,
            pages,
            blocks,
            stats: header.stats,
        })
    }

    /// The compression of `t` at `options`, read from `path` when it holds
    /// it, else built and written there; a file that does not hold it
    /// (corrupt, stale, another ε) is reported on stderr and replaced.
    /// Returns whether it was read.
    pub fn cached(
        path: &std::path::Path,
        t: &ComplianceTensor,
        options: &BlrOptions,
    ) -> Result<(Self, bool), FlankError> {
        options.validate()?;
        if path.exists() {
            match Self::read(path, t, options.epsilon) {
                Ok(c) => return Ok((c, true)),
                Err(e) => eprintln!("warning: {e}; compressing again"),
            }
        }
        let c = Self::from_dense(t, options)?;
        c.write(path)?;
        Ok((c, false))
    }
}

/// The checksum of a file version.
enum Checksum {
    /// Version 1: FNV-1a 128 over bytes.
    Bytes(Fnv128),
    /// Version 2: FNV-1a 64 over 64-bit words.
    Words(WordHash),
}

/// A [`BlrTensor`] file read front to back: the fields are taken in
/// order, the checksum is updated as their bytes pass and compared with
/// the file's at the end ([`FileReader::finish`]). No take may reach
/// into the checksum (a truncated or corrupt length is an error, never a
/// huge allocation), and the values are read straight into their blocks
/// (one copy from the page cache; seed 002's 0.1 mm files, 2.3 GB, were
/// read into one buffer and then copied into the blocks before).
struct FileReader<R> {
    src: R,
    /// Bytes left before the checksum.
    left: u64,
    sum: Checksum,
    version: u32,
}

impl<R: std::io::Read> FileReader<R> {
    /// Reads the magic and the version of a file of `len` bytes.
    fn open(mut src: R, len: u64) -> Result<Self, String> {
        let mut head = [0u8; 12];
        if len < 8 + 4 + 8 + 16 || src.read_exact(&mut head).is_err() || &head[..8] != MAGIC {
            return Err("not a compressed compliance file".into());
        }
        let version = u32::from_le_bytes(head[8..12].try_into().expect("4 bytes"));
        let (mut sum, trailer) = match version {
            1 => (Checksum::Bytes(Fnv128::new()), 16),
            VERSION => (Checksum::Words(WordHash::new()), 8),
            _ => {
                return Err(format!(
                    "format version {version}; this build reads versions 1 and {VERSION}"
                ))
            }
        };
        sum.update(&head);
        Ok(FileReader {
            src,
            left: len - 12 - trailer,
            sum,
            version,
        })
    }

    /// Fills `out` with the next bytes.
    fn fill(&mut self, out: &mut [u8]) -> Result<(), String> {
        if out.len() as u64 > self.left {
            return Err("truncated file".into());
        }
        self.src
            .read_exact(out)
            .map_err(|e| format!("reading: {e}"))?;
        self.left -= out.len() as u64;
        self.sum.update(out);
        Ok(())
    }

    fn array<const K: usize>(&mut self) -> Result<[u8; K], String> {
        let mut a = [0u8; K];
        self.fill(&mut a)?;
        Ok(a)
    }

    fn bytes(&mut self, k: usize) -> Result<Vec<u8>, String> {
        if k as u64 > self.left {
            return Err("truncated file".into());
        }
        let mut v = vec![0u8; k];
        self.fill(&mut v)?;
        Ok(v)
    }

    /// The next `k` values (f64, little endian).
    fn f64s(&mut self, k: usize) -> Result<Vec<f64>, String> {
        if 8 * k as u64 > self.left {
            return Err("truncated file".into());
        }
        let mut v = vec![0.0f64; k];
        self.fill(bytemuck::cast_slice_mut(&mut v))?;
        if cfg!(target_endian = "big") {
            for x in &mut v {
                *x = f64::from_bits(u64::from_le(x.to_bits()));
            }
        }
        Ok(v)
    }

    /// Checks that the blocks end where the checksum begins and that the
    /// checksum matches.
    fn finish(mut self) -> Result<(), String> {
        if self.left != 0 {
            return Err("trailing bytes after the blocks".into());
        }
        let ok = match self.sum {
            Checksum::Bytes(h) => {
                let mut s = [0u8; 16];
                self.src.read_exact(&mut s).is_ok() && h.0.to_le_bytes() == s
            }
            Checksum::Words(h) => {
                let mut s = [0u8; 8];
                self.src.read_exact(&mut s).is_ok() && h.finish().to_le_bytes() == s
            }
        };
        if !ok {
            return Err(format!(
                "checksum mismatch (corrupt or truncated file, format version {})",
                self.version
            ));
        }
        Ok(())
    }
}

impl Checksum {
    fn update(&mut self, b: &[u8]) {
        match self {
            Checksum::Bytes(h) => h.bytes(b),
            Checksum::Words(h) => h.update(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compliance::compressed::tests::kernel_tensor;

    #[test]
    fn file_round_trip_and_stale_files() {
        let t = kernel_tensor(2, 12, 12);
        let opts = BlrOptions::default();
        let c = BlrTensor::from_dense(&t, &opts).unwrap();
        let dir = std::env::temp_dir().join(format!("flank_blr_test_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.blr.bin");
        let (c1, read) = BlrTensor::cached(&path, &t, &opts).unwrap();
        assert!(!read);
        assert_eq!(c1.blocks, c.blocks);
        let (c2, read) = BlrTensor::cached(&path, &t, &opts).unwrap();
        assert!(read);
        assert_eq!(c2.blocks, c.blocks);
        assert_eq!(c2.position, c.position);
        assert_eq!(c2.stats, c1.stats);
        // another ε, another tensor, a flipped byte, a truncated file
        let e = BlrTensor::read(&path, &t, 1e-8).unwrap_err().to_string();
        assert!(e.contains("ε"), "{e}");
        let mut other = t.clone();
        other.meta.cache_key = "other".into();
        let e = BlrTensor::read(&path, &other, 1e-6)
            .unwrap_err()
            .to_string();
        assert!(e.contains("not of other"), "{e}");
        let mut bytes = std::fs::read(&path).unwrap();
        let k = bytes.len() / 2;
        bytes[k] ^= 1;
        assert!(BlrTensor::from_bytes(&bytes, &t, 1e-6)
            .unwrap_err()
            .contains("checksum"));
        bytes[k] ^= 1;
        assert!(BlrTensor::from_bytes(&bytes[..k], &t, 1e-6).is_err());
        assert!(BlrTensor::from_bytes(b"FLANKBLR", &t, 1e-6).is_err());
        // a corrupt length is refused before anything of that length is
        // allocated or read
        let mut huge = bytes.clone();
        huge[12..20].copy_from_slice(&u64::MAX.to_le_bytes());
        let e = BlrTensor::from_bytes(&huge, &t, 1e-6).unwrap_err();
        assert!(e.contains("truncated"), "{e}");
        // a version 1 file (FNV-1a 128 over bytes) is still read, to the
        // same blocks; a version this build does not know is refused
        let mut v1 = bytes[..bytes.len() - 8].to_vec();
        v1[8..12].copy_from_slice(&1u32.to_le_bytes());
        let mut h = crate::compliance::Fnv128::new();
        h.bytes(&v1);
        v1.extend_from_slice(&h.0.to_le_bytes());
        let old = BlrTensor::from_bytes(&v1, &t, 1e-6).unwrap();
        assert_eq!(old.blocks, c.blocks);
        v1[k] ^= 1;
        assert!(BlrTensor::from_bytes(&v1, &t, 1e-6)
            .unwrap_err()
            .contains("checksum"));
        let mut v3 = bytes.clone();
        v3[8..12].copy_from_slice(&3u32.to_le_bytes());
        let e = BlrTensor::from_bytes(&v3, &t, 1e-6).unwrap_err();
        assert!(e.contains("version 3"), "{e}");
        // a stale file is replaced, not used
        std::fs::write(&path, &bytes[..k]).unwrap();
        let (c3, read) = BlrTensor::cached(&path, &t, &opts).unwrap();
        assert!(!read);
        assert_eq!(c3.blocks, c.blocks);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
