//! # Nodal compliance tensors of a gear body
//!
//! The input of every compliance-matrix LTCA (seeds `001_…` and `003_…`:
//! "a compliance tensor for discrete nodes on the tooth surface via a single
//! static FEM run", interpolated at the contact points afterwards).
//!
//! ## What
//!
//! For one linear-elastic body (a gear sector with its bore clamped, see
//! [`crate::mesh::gear_body`]) and N selected flank nodes, the **nodal
//! compliance tensor** C^{ij} (3 × 3, mm/N) is the displacement at node i
//! from a unit force at node j:
//!
//! ```text
//! C^{ij}_{ab} = u_a(x_i) for f = e_b δ(x − x_j),   a, b ∈ {x, y, z}
//! ```
//!
//! i.e. the restriction of K⁻¹ (K the stiffness with its Dirichlet conditions
//! eliminated) to the 3N flank DOFs: C = Eᵀ K⁻¹ E with E the 0/1 columns of
//! those DOFs. C is stored as one 3N × 3N matrix in node-major DOF order
//! (x, y, z of node 0, then node 1, …), full and symmetric: Maxwell–Betti
//! reciprocity gives C^{ij} = (C^{ji})ᵀ (seed 001: "by the reciprocal theorem
//! of displacement, C^{ij} = (C^{ji})ᵀ"). Seed 001 states the component
//! indices the other way round (c^{ij}_{mn}: displacement along n at i from a
//! force along m at j); its directional compliances and their stated
//! meanings (c^{kl}_{nn} is "the normal displacement at point k due to a unit
//! normal force at point l") are those of the convention used here, which is
//! the matrix convention of K⁻¹ (row = response DOF, column = load DOF).
//!
//! ## How (one factorization)
//!
//! Two methods, both from one sparse Cholesky factorization K = LLᵀ
//! ([`tensor`]):
//!
//! * **Schur complement** (default, [`Method::Schur`]): the flank DOFs are
//!   numbered last (METIS nested dissection of the rest,
//!   [`crate::fem::ordering::order_groups_last`]). Then
//!   L = [L₁₁ 0; L₂₁ L₂₂] and L₂₂L₂₂ᵀ = S = K₂₂ − K₂₁K₁₁⁻¹K₁₂, the Schur
//!   complement (condensed stiffness) on the flank DOFs. Since the flank
//!   block of K⁻¹ is S⁻¹ (block inverse), C = S⁻¹ = L₂₂⁻ᵀL₂₂⁻¹: a dense
//!   triangular inverse and a triangular product, m³/3 flops each
//!   (m = 3N), on top of a factorization whose root front is the m × m flank
//!   block. Golub & Van Loan, *Matrix Computations*, 4th ed., the chapters on
//!   block LU/Cholesky and the Schur complement; George & Liu, *Computer
//!   Solution of Large Sparse Positive Definite Systems*, on orderings with
//!   a prescribed last set.
//! * **Blocked right-hand sides** ([`Method::Blocked`]): the standard
//!   (unconstrained) METIS ordering, and K X = E solved for the unit columns
//!   E in blocks of b columns (b from a memory budget), blocks solved
//!   concurrently (one thread each); from each block only the lower
//!   triangle rows (flank DOFs at or after the column) are kept, the upper
//!   triangle is its mirror. Cost ≈ 4 nnz(L) flops per right-hand side.
//!
//! Measured on the seed 002 pinion (`benches/README.md`): the Schur
//! complement is the faster by a wide margin, so it is the default.
//!
//! Symmetry is exploited in both: only one triangle is computed, the other
//! is its mirror, so ‖C − Cᵀ‖ = 0 exactly; the native cache stores the
//! packed lower triangle.
//!
//! ## Which flank nodes
//!
//! [`FlankSelection::Loaded`] (default): the right flank `FLANK_R<k>` of
//! every tooth k of the sector, the flank side on which
//! [`crate::mesh::gear_body`] places the nominal load of both bodies; `Left`,
//! `Right` and `Both` select by side. Flank sets hold the involute and root
//! fillet nodes (not the root arc), so the tensors cover fillet loading too.
//!
//! [`FlankRegion`] then picks the part of each flank: `full` (the whole
//! set) or `active`, the active flank plus a margin
//! ([`body::active_flank_cut`]: from the start of active profile, the
//! radius the mating tip reaches, down the profile by
//! [`body::active_margin_mm`] = 2 flank elements + 1 mm, then every flank
//! face that reaches that cut, [`FlankNodes::restrict_u`]). The Schur path
//! costs m³, so the fillet's DOFs, which the mating tip cannot load, are
//! dear. Nothing is approximated: C on fewer flank DOFs is the sub-block of
//! C on all of them. `active` is the default where the pair is known
//! (`flank ltca`, `flank compare`, spur/helical pairs; `--flank-region`,
//! `[analyses.ltca] flank_region`); `flank compliance` keeps `full` unless
//! asked (`[analyses.compliance] flank_region`). A restricted tensor records
//! where it stops ([`ComplianceMeta::region_u_min`]); a contact point or
//! cell that reaches below is an error naming the region
//! ([`FlankInterpolator::check_region`]), never a load silently dropped,
//! and its cache key differs from the full tensor's ([`region_cache_key`]).
//! Bevel/hypoid bodies take the full flank: their u runs across the pitch
//! generatrix and the start of active profile is a curve in (u, v), not
//! yet derived.
//!
//! ## Storage, cache, interpolation
//!
//! [`cache`]: `<body>.compliance.h5` with the cargo feature `hdf5`, a
//! versioned native binary file `<body>.compliance.bin` without it; both
//! carry the flank (u, v), positions, outward normals, flank faces, the mesh
//! hash, clamped sets, material and units, and a cache key (mesh hash +
//! Dirichlet conditions + material + flank nodes) so that the same body is
//! never computed twice. [`interpolation`]: tensors at any flank point (u, v)
//! and over contact cells with the flank faces' own shape functions, and the
//! directional compliances c_nn, c_tt, c_nt, c_tn of seed 001.
//!
//! [`compressed`]: the tensor in block low-rank form over the pages' page
//! pairs (ACA + recompression, each off-diagonal block within a stated
//! relative accuracy ε of its Frobenius norm); the frictionless LTCA can
//! read its page pairs from it (`[analyses.ltca] compression = 1e-6`).
//! [`compressed_build`]: that form built panel by panel from the body's
//! sparse factor, without the dense tensor (the LTCA's path then).
//!
//! [`Method::Schur`]: crate::settings::Method::Schur
//! [`Method::Blocked`]: crate::settings::Method::Blocked
//! [`FlankSelection::Loaded`]: crate::settings::FlankSelection::Loaded
//! [`FlankRegion`]: crate::settings::FlankRegion

pub mod body;
pub mod cache;
pub mod compressed;
pub mod compressed_build;
pub mod contact_probe;
pub mod flank;
pub mod interpolation;
pub mod page_order;
pub mod pages;
pub mod plot;
pub mod run;
pub mod summary;
pub mod tensor;
pub mod tensor_cache;

pub use cache::FileFormat;
pub use flank::{FlankFace, FlankNodes};
pub use interpolation::{directional, CellShape, Directional, FlankInterpolator, SurfaceLoad};
pub use tensor::{compute_compliance, ComplianceOptions, ComplianceStats};
pub use tensor_cache::ComplianceCache;

use crate::error::FlankError;
use crate::fem::mesh::Mesh;
use crate::fem::model::Model;

/// The compliance of one body on its flank nodes, with what it was computed
/// from. `matrix` is 3N × 3N, full, symmetric, node-major (x, y, z), mm/N.
#[derive(Clone, Debug)]
pub struct ComplianceTensor {
    pub meta: ComplianceMeta,
    pub flank: FlankNodes,
    /// Row-major (= column-major, symmetric) 3N × 3N values.
    pub matrix: Vec<f64>,
}

/// Identification and provenance of a compliance tensor (stored as HDF5
/// attributes or in the native header).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ComplianceMeta {
    /// Body name (`pinion`, `gear`, …).
    pub body: String,
    /// [`mesh_hash`] of the body's mesh.
    pub mesh_hash: String,
    /// [`cache_key`]: mesh hash + Dirichlet conditions + material + flank nodes.
    pub cache_key: String,
    /// Names of the clamped node sets (all DOFs zero), e.g. `["BORE"]`.
    pub clamped_sets: Vec<String>,
    /// Material names, E (MPa) and ν, one entry per material of the model.
    pub materials: Vec<(String, f64, f64)>,
    /// The flank node sets, in the order of [`FlankNodes::sets`].
    pub flank_sets: Vec<String>,
    /// Units of every stored quantity.
    pub units: String,
    /// How the matrix was computed (`schur` or `blocked`).
    pub method: String,
    /// Where the flank nodes stop down the profile when the tensor covers
    /// only part of each flank ([`FlankRegion::Active`]): per flank set (in
    /// the order of `flank_sets`), the lowest flank parameter u of its
    /// nodes. A contact cell reaching below it is an error
    /// ([`FlankInterpolator::cell`]), never a silent zero. Absent for the
    /// full flank (and in files written before it existed).
    ///
    /// [`FlankRegion::Active`]: crate::settings::FlankRegion::Active
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region_u_min: Option<Vec<f64>>,
}

/// Units string stored with every tensor.
pub const UNITS: &str = "matrix mm/N (DOF order node-major x,y,z); positions mm; normals unit, outward; \
flank u: involute roll angle (rad) for u >= u_form, u_form - t on the root fillet (t in [0,1]); v: axial z (mm)";

impl ComplianceTensor {
    /// Number of flank nodes N.
    pub fn node_count(&self) -> usize {
        self.flank.labels.len()
    }

    /// Matrix dimension 3N.
    pub fn dim(&self) -> usize {
        3 * self.node_count()
    }

    /// Whether the dense matrix is held (3N × 3N entries). A tensor built
    /// compressed ([`compressed_build`]) carries its flank and key only,
    /// `matrix` empty: its entries are read from the block low-rank form.
    pub fn has_matrix(&self) -> bool {
        self.matrix.len() == self.dim() * self.dim()
    }

    /// C^{ij}: displacement at flank node i from a unit force at flank node j.
    #[inline]
    pub fn block(&self, i: usize, j: usize) -> [[f64; 3]; 3] {
        let m = self.dim();
        let mut c = [[0.0; 3]; 3];
        for a in 0..3 {
            let row = (3 * i + a) * m + 3 * j;
            c[a].copy_from_slice(&self.matrix[row..row + 3]);
        }
        c
    }

    /// ‖C − Cᵀ‖_F / ‖C‖_F.
    pub fn asymmetry(&self) -> f64 {
        let m = self.dim();
        let (mut d, mut t) = (0.0, 0.0);
        for i in 0..m {
            for j in 0..m {
                let a = self.matrix[i * m + j];
                let b = self.matrix[j * m + i];
                d += (a - b) * (a - b);
                t += a * a;
            }
        }
        if t > 0.0 {
            (d / t).sqrt()
        } else {
            0.0
        }
    }

    /// Position of a flank node by deck label.
    pub fn node_of_label(&self, label: u64) -> Option<usize> {
        self.flank.labels.iter().position(|&l| l == label)
    }
}

/// FNV-1a 64 over little-endian 64-bit words of a byte stream (a tail
/// shorter than a word is zero-padded): the tensor files' checksum, one
/// multiply per 8 bytes where [`Fnv128`] takes one 128-bit multiply per
/// byte.
pub(crate) struct WordHash {
    h: u64,
    pending: [u8; 8],
    len: usize,
}

impl WordHash {
    pub(crate) fn new() -> Self {
        WordHash {
            h: 0xcbf2_9ce4_8422_2325,
            pending: [0; 8],
            len: 0,
        }
    }
    fn word(&mut self, w: u64) {
        self.h ^= w;
        self.h = self.h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    pub(crate) fn update(&mut self, mut b: &[u8]) {
        if self.len > 0 {
            let k = (8 - self.len).min(b.len());
            self.pending[self.len..self.len + k].copy_from_slice(&b[..k]);
            self.len += k;
            b = &b[k..];
            if self.len == 8 {
                self.word(u64::from_le_bytes(self.pending));
                self.len = 0;
            }
            if b.is_empty() {
                // still short of a word: keep what is pending
                return;
            }
        }
        let mut chunks = b.chunks_exact(8);
        for c in &mut chunks {
            self.word(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        let rest = chunks.remainder();
        self.pending[..rest.len()].copy_from_slice(rest);
        self.len = rest.len();
    }
    pub(crate) fn finish(mut self) -> u64 {
        if self.len > 0 {
            self.pending[self.len..].fill(0);
            self.word(u64::from_le_bytes(self.pending));
        }
        self.h
    }
}

/// 128-bit FNV-1a over typed fields (stable across platforms and runs).
#[derive(Clone, Copy)]
pub(crate) struct Fnv128(pub(crate) u128);

impl Fnv128 {
    const OFFSET: u128 = 0x6c62272e07bb014262b821756295c58d;
    const PRIME: u128 = 0x0000000001000000000000000000013B;

    pub(crate) fn new() -> Self {
        Fnv128(Self::OFFSET)
    }
    pub(crate) fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= x as u128;
            self.0 = self.0.wrapping_mul(Self::PRIME);
        }
    }
    pub(crate) fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }
    pub(crate) fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    pub(crate) fn str(&mut self, s: &str) {
        self.u64(s.len() as u64);
        self.bytes(s.as_bytes());
    }
    pub(crate) fn hex(self) -> String {
        format!("{:032x}", self.0)
    }
}

/// Hash of a mesh's geometry and topology: node labels and coordinates
/// (exact bits), element kinds, labels and connectivity. Node and element
/// sets are not part of it (boundary conditions enter [`cache_key`]).
pub fn mesh_hash(mesh: &Mesh) -> String {
    let mut h = Fnv128::new();
    h.str("flank-mesh-v1");
    h.u64(mesh.node_count() as u64);
    for (label, x) in mesh.node_labels.iter().zip(&mesh.coords) {
        h.u64(*label);
        for v in x {
            h.f64(*v);
        }
    }
    h.u64(mesh.elements.len() as u64);
    for el in &mesh.elements {
        h.str(el.kind.name());
        h.u64(el.label);
        for &n in &el.nodes {
            h.u64(mesh.node_labels[n]);
        }
    }
    h.hex()
}

/// Cache key of a compliance computation: the mesh hash, every Dirichlet
/// condition (node label, component, value), rigid couplings, the materials
/// and their assignment, and the flank nodes in order. Two computations with
/// the same key give the same matrix (up to round-off of the method).
pub fn cache_key(model: &Model, mesh_hash: &str, flank: &FlankNodes) -> String {
    let mesh = &model.mesh;
    let mut h = Fnv128::new();
    h.str("flank-compliance-key-v1");
    h.str(mesh_hash);
    let mut bcs: Vec<(u64, usize, u64)> = model
        .dirichlet
        .iter()
        .map(|d| (mesh.node_labels[d.node], d.component, d.value.to_bits()))
        .collect();
    bcs.sort_unstable();
    bcs.dedup();
    h.u64(bcs.len() as u64);
    for (l, c, v) in bcs {
        h.u64(l);
        h.u64(c as u64);
        h.u64(v);
    }
    h.u64(model.couplings.len() as u64);
    for cp in &model.couplings {
        h.str(&cp.name);
        for v in cp.reference_point {
            h.f64(v);
        }
        for f in cp.free {
            h.u64(f as u64);
        }
        for &n in &cp.nodes {
            h.u64(mesh.node_labels[n]);
        }
    }
    h.u64(model.materials.len() as u64);
    for m in &model.materials {
        h.f64(m.young);
        h.f64(m.poisson);
    }
    for &m in &model.element_material {
        h.u64(m as u64);
    }
    h.u64(flank.labels.len() as u64);
    for s in &flank.sets {
        h.str(s);
    }
    for (&l, &s) in flank.labels.iter().zip(&flank.set_of) {
        h.u64(l);
        h.u64(s as u64);
    }
    h.hex()
}

/// The cache key of a tensor restricted to part of its flanks: `key` (the
/// [`cache_key`] of the restricted nodes, which already differ from the
/// full flank's) mixed with where each flank set stops
/// ([`ComplianceMeta::region_u_min`]), so that a restricted tensor never
/// answers for a full one, nor for another region, even where the nodes
/// coincide. `None` (full flank) leaves the key as it was.
pub fn region_cache_key(key: &str, region_u_min: Option<&[f64]>) -> String {
    let Some(u) = region_u_min else {
        return key.to_string();
    };
    let mut h = Fnv128::new();
    h.str("flank-compliance-region-v1");
    h.str(key);
    h.u64(u.len() as u64);
    for &x in u {
        h.f64(x);
    }
    h.hex()
}

/// Names of the node sets all of whose nodes have all three DOFs fixed at
/// zero by the model's Dirichlet conditions (e.g. `BORE`), sorted.
pub fn clamped_sets(model: &Model) -> Vec<String> {
    let nn = model.mesh.node_count();
    let mut fixed = vec![0u8; nn];
    for d in &model.dirichlet {
        if d.node < nn && d.value == 0.0 && d.component < 3 {
            fixed[d.node] |= 1 << d.component;
        }
    }
    model
        .mesh
        .node_sets
        .iter()
        .filter(|(name, nodes)| {
            !nodes.is_empty()
                && name.as_str() != "NALL"
                && nodes.iter().all(|&n| n < nn && fixed[n] == 7)
        })
        .map(|(name, _)| name.clone())
        .collect()
}

/// Adds Dirichlet conditions u = 0 on every node of the named sets.
pub fn clamp_sets(model: &mut Model, sets: &[&str]) -> Result<(), FlankError> {
    for &name in sets {
        let nodes = model
            .mesh
            .node_sets
            .get(&name.to_ascii_uppercase())
            .cloned()
            .ok_or_else(|| FlankError::Model(format!("no node set {name} to clamp")))?;
        for n in nodes {
            for component in 0..3 {
                model.dirichlet.push(crate::fem::model::Dirichlet {
                    node: n,
                    component,
                    value: 0.0,
                });
            }
        }
    }
    Ok(())
}

/// A compliance tensor for `model` on `flank`, computed (never twice for the
/// same key within `cache`, when one is given).
pub fn compliance_tensor(
    name: &str,
    model: &Model,
    flank: &FlankNodes,
    options: &ComplianceOptions,
) -> Result<(ComplianceTensor, ComplianceStats), FlankError> {
    let (matrix, stats) = compute_compliance(model, flank, options)?;
    Ok((
        ComplianceTensor {
            meta: tensor_meta(name, model, flank, options.method.name()),
            flank: flank.clone(),
            matrix,
        },
        stats,
    ))
}

/// The metadata of the tensor of `model` on `flank` (key from the mesh
/// hash, constraints, material and flank nodes; full flank), computed by
/// `method`.
pub fn tensor_meta(name: &str, model: &Model, flank: &FlankNodes, method: &str) -> ComplianceMeta {
    let hash = mesh_hash(&model.mesh);
    let key = cache_key(model, &hash, flank);
    ComplianceMeta {
        body: name.to_string(),
        mesh_hash: hash,
        cache_key: key,
        clamped_sets: clamped_sets(model),
        materials: model
            .materials
            .iter()
            .map(|m| (m.name.clone(), m.young, m.poisson))
            .collect(),
        flank_sets: flank.sets.clone(),
        units: UNITS.to_string(),
        method: method.to_string(),
        region_u_min: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compliance::flank::tests::box_flank;
    use crate::mesh::structured::BoxElement;
    use crate::settings::{FlankRegion, FlankSelection, Method};

    /// The checksum of a byte stream does not depend on how it is cut
    /// into updates (the compressed tensor file is hashed field by field
    /// as it is read; pieces shorter than a word were once dropped).
    #[test]
    fn word_hash_of_a_stream_is_that_of_its_bytes() {
        let bytes: Vec<u8> = (0..203u32).map(|i| (i * 37 % 251) as u8).collect();
        let mut whole = WordHash::new();
        whole.update(&bytes);
        let whole = whole.finish();
        for cuts in [[1, 2, 3], [5, 1, 1], [7, 9, 2], [8, 1, 16], [3, 3, 3]] {
            let mut h = WordHash::new();
            let (mut at, mut i) = (0, 0);
            while at < bytes.len() {
                let k = cuts[i % 3].min(bytes.len() - at);
                h.update(&bytes[at..at + k]);
                at += k;
                i += 1;
            }
            assert_eq!(h.finish(), whole, "pieces {cuts:?}");
        }
        // one byte changed anywhere changes it
        let mut other = bytes.clone();
        other[101] ^= 4;
        let mut h = WordHash::new();
        h.update(&other);
        assert_ne!(h.finish(), whole);
    }

    #[test]
    fn selection_hash_key_and_clamped_sets() {
        let (model, flank) = box_flank(BoxElement::Hex20);
        let h = mesh_hash(&model.mesh);
        assert_eq!(h, mesh_hash(&model.mesh.clone()));
        let key = cache_key(&model, &h, &flank);
        assert_eq!(clamped_sets(&model), ["X0"]);
        // geometry, boundary conditions and material all change the key
        let mut m2 = model.clone();
        m2.mesh.coords[5][0] += 1e-12;
        assert_ne!(mesh_hash(&m2.mesh), h);
        let mut m3 = model.clone();
        clamp_sets(&mut m3, &["X1"]).unwrap();
        assert_ne!(cache_key(&m3, &h, &flank), key);
        assert_eq!(clamped_sets(&m3), ["X0", "X1"]);
        let mut m4 = model.clone();
        m4.materials[0].young *= 1.01;
        assert_ne!(cache_key(&m4, &h, &flank), key);
        assert!(clamp_sets(&mut m4, &["NOPE"]).is_err());
    }

    #[test]
    fn scene_compliance_options() {
        let path = std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/papers/seed002-spur/scene.toml"
        ));
        let text = std::fs::read_to_string(path).unwrap();
        let with = |opts: &str| {
            crate::scene::parse_scene(
                &text.replace(
                    "mesh = {}\n",
                    &format!("mesh = {{}}\ncompliance = {opts}\n"),
                ),
                path,
            )
        };
        let s = with(
            r#"{ clamp_cuts = true, flanks = "both", method = "blocked", memory_budget_mb = 512, flank_region = "active" }"#,
        )
        .unwrap();
        let c = s.analyses.compliance.unwrap();
        assert!(c.clamp_cuts);
        assert_eq!(c.flank_region, FlankRegion::Active);
        assert_eq!(c.flanks, FlankSelection::Both);
        assert_eq!(c.method, Method::Blocked);
        assert_eq!(c.memory_budget_mb, Some(512.0));
        let d = with("{}").unwrap().analyses.compliance.unwrap();
        assert_eq!(
            (d.flanks, d.method, d.clamp_cuts, d.flank_region),
            (
                FlankSelection::Loaded,
                Method::Schur,
                false,
                FlankRegion::Full
            )
        );
        // the LTCA's key: active or full, spur/helical only
        let ltca = |v: &str| {
            crate::scene::parse_scene(
                &text.replace(
                    "mesh = {}\n",
                    &format!("mesh = {{}}\nltca = {{ flank_region = {v} }}\n"),
                ),
                path,
            )
        };
        let l = ltca(r#""full""#).unwrap().analyses.ltca.unwrap();
        assert_eq!(l.flank_region, Some(FlankRegion::Full));
        assert!(ltca(r#""fillet""#).is_err());
        // the region keys a tensor apart; none leaves the key as it was
        assert_eq!(region_cache_key("abc", None), "abc");
        assert_ne!(region_cache_key("abc", Some(&[0.1])), "abc");
        assert_ne!(
            region_cache_key("abc", Some(&[0.1])),
            region_cache_key("abc", Some(&[0.2]))
        );
        for (bad, what) in [
            ("{ order = 2 }", "analyses.compliance"),
            (r#"{ method = "lu" }"#, "analyses.compliance"),
            (r#"{ flank_region = "tip" }"#, "analyses.compliance"),
            ("{ memory_budget_mb = 0 }", "memory_budget_mb"),
        ] {
            let e = with(bad).unwrap_err().to_string();
            assert!(e.contains(what), "{bad}: {e}");
        }
    }
}
