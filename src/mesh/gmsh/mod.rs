//! gmsh through its C API (Cargo feature `gmsh`; needs `libgmsh-dev`, gmsh
//! 4.8): a safe wrapper over the few functions flank uses, and the gmsh gear
//! sector mesher [`sector::gmsh_sector`].
//!
//! Why gmsh next to the native mesher: unstructured, size-field driven meshes
//! (any flank size, local refinement, wedges from triangles) as a second,
//! independent mesh of the same geometry for mesh-sensitivity studies, and
//! the `.msh` files other tools exchange (read natively by
//! [`crate::mesh::msh`], without this feature).
//!
//! gmsh keeps one global model state per process, so every use goes through
//! a [`Session`]: it takes a process-wide lock, initializes gmsh, and
//! finalizes it when dropped. Every call checks gmsh's `ierr` and turns a
//! failure into [`FlankError::Model`] naming the C function and gmsh's last
//! error message; arrays gmsh allocates are released with `gmshFree`.
//! gmsh's own terminal output is off; `General.AbortOnError = 3` asks gmsh
//! to raise the errors it would otherwise only log. (A crash inside gmsh
//! cannot be caught: the quad mesher `Mesh.Algorithm = 8` segfaults in
//! Debian's gmsh 4.8.4 and is not used.)
//!
//! The mesher's construction, size field and node-order permutation are
//! documented in [`sector`]; the permutation tables live in
//! [`crate::mesh::msh`], shared with the `.msh` reader.

mod ffi;
pub mod sector;

pub use sector::{gmsh_sector, gmsh_sector_with_msh};

use std::ffi::{CStr, CString};
use std::os::raw::{c_char, c_int, c_void};
use std::path::Path;
use std::sync::{Mutex, MutexGuard};

use crate::error::FlankError;

type Result<T> = std::result::Result<T, FlankError>;

static LOCK: Mutex<()> = Mutex::new(());

/// An array allocated by gmsh, freed with `gmshFree` on drop.
struct GmshArray<T> {
    ptr: *mut T,
    len: usize,
}

impl<T: Copy> GmshArray<T> {
    fn new() -> Self {
        GmshArray {
            ptr: std::ptr::null_mut(),
            len: 0,
        }
    }

    fn as_slice(&self) -> &[T] {
        if self.ptr.is_null() || self.len == 0 {
            &[]
        } else {
            // SAFETY: gmsh returned `len` initialized elements at `ptr`.
            unsafe { std::slice::from_raw_parts(self.ptr, self.len) }
        }
    }

    fn to_vec(&self) -> Vec<T> {
        self.as_slice().to_vec()
    }
}

impl<T> Drop for GmshArray<T> {
    fn drop(&mut self) {
        if !self.ptr.is_null() {
            // SAFETY: allocated by gmsh, released once.
            unsafe { ffi::gmshFree(self.ptr as *mut c_void) };
        }
    }
}

/// gmsh's last error message (empty if none).
fn last_error() -> String {
    let mut p: *mut c_char = std::ptr::null_mut();
    let mut ierr: c_int = 0;
    // SAFETY: out-pointer to a gmsh-allocated C string, freed below.
    unsafe { ffi::gmshLoggerGetLastError(&mut p, &mut ierr) };
    if p.is_null() {
        return String::new();
    }
    // SAFETY: gmsh returns a NUL-terminated string.
    let s = unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned();
    // SAFETY: allocated by gmsh.
    unsafe { ffi::gmshFree(p as *mut c_void) };
    s
}

fn check(function: &str, ierr: c_int) -> Result<()> {
    if ierr == 0 {
        return Ok(());
    }
    let msg = last_error();
    Err(FlankError::Model(if msg.is_empty() {
        format!("gmsh: {function} failed (ierr {ierr})")
    } else {
        format!("gmsh: {function} failed: {msg}")
    }))
}

fn cstring(function: &str, s: &str) -> Result<CString> {
    CString::new(s).map_err(|_| {
        FlankError::Model(format!(
            "gmsh: {function}: argument {s:?} contains a NUL byte"
        ))
    })
}

fn pairs(dim_tags: &[c_int]) -> Vec<(i32, i32)> {
    dim_tags.chunks_exact(2).map(|p| (p[0], p[1])).collect()
}

fn flatten(dim_tags: &[(i32, i32)]) -> Vec<c_int> {
    dim_tags.iter().flat_map(|&(d, t)| [d, t]).collect()
}

/// Calls a gmsh function with a trailing `ierr` and checks it.
macro_rules! call {
    ($f:ident ( $($arg:expr),* )) => {{
        let mut ierr: c_int = 0;
        // SAFETY: arguments are valid for the call (pointers to live locals
        // or gmsh out-parameters); the session lock is held.
        let r = unsafe { ffi::$f($($arg,)* &mut ierr) };
        check(stringify!($f), ierr).map(|_| r)
    }};
}

/// Properties of a gmsh element type ([`Session::element_properties`]).
#[derive(Clone, Debug)]
pub struct ElementProperties {
    pub name: String,
    pub dim: i32,
    pub order: i32,
    pub nodes: usize,
    /// Reference coordinates of the nodes, `dim` per node, in gmsh's order.
    pub local_coords: Vec<f64>,
    pub primary_nodes: usize,
}

/// The gmsh session: gmsh initialized and the process-wide lock held.
/// Dropping it finalizes gmsh.
pub struct Session {
    _guard: MutexGuard<'static, ()>,
}

impl Session {
    /// Takes the lock (waiting for another session to end) and initializes gmsh.
    pub fn start() -> Result<Session> {
        // A poisoned lock only means a panic elsewhere; gmsh state is reset here.
        let guard = LOCK.lock().unwrap_or_else(|p| p.into_inner());
        call!(gmshInitialize(0, std::ptr::null_mut(), 0))?;
        let s = Session { _guard: guard };
        s.option("General.Terminal", 0.0)?;
        s.option("General.Verbosity", 1.0)?;
        s.option("General.AbortOnError", 3.0)?;
        Ok(s)
    }

    /// Sets a numeric option, e.g. `Mesh.ElementOrder`.
    pub fn option(&self, name: &str, value: f64) -> Result<()> {
        let c = cstring("gmshOptionSetNumber", name)?;
        call!(gmshOptionSetNumber(c.as_ptr(), value))
            .map_err(|e| FlankError::Model(format!("{e} (option {name} = {value})")))
    }

    pub fn model_add(&self, name: &str) -> Result<()> {
        let c = cstring("gmshModelAdd", name)?;
        call!(gmshModelAdd(c.as_ptr()))
    }

    /// Writes the current model/mesh; the format follows the extension and
    /// the `Mesh.MshFileVersion` / `Mesh.Binary` options.
    pub fn write(&self, path: &Path) -> Result<()> {
        let s = path.to_str().ok_or_else(|| {
            FlankError::Model(format!(
                "gmsh: gmshWrite: path {} is not valid UTF-8",
                path.display()
            ))
        })?;
        let c = cstring("gmshWrite", s)?;
        call!(gmshWrite(c.as_ptr()))
    }

    // --- geo kernel -------------------------------------------------------

    pub fn geo_point(&self, p: [f64; 3], mesh_size: f64) -> Result<i32> {
        call!(gmshModelGeoAddPoint(p[0], p[1], p[2], mesh_size, -1))
    }

    pub fn geo_line(&self, start: i32, end: i32) -> Result<i32> {
        call!(gmshModelGeoAddLine(start, end, -1))
    }

    /// Circle arc (< π) from `start` to `end` about `centre`.
    pub fn geo_circle_arc(&self, start: i32, centre: i32, end: i32) -> Result<i32> {
        call!(gmshModelGeoAddCircleArc(
            start, centre, end, -1, 0.0, 0.0, 0.0
        ))
    }

    /// Spline (Catmull–Rom) through the points.
    pub fn geo_spline(&self, points: &[i32]) -> Result<i32> {
        call!(gmshModelGeoAddSpline(points.as_ptr(), points.len(), -1))
    }

    /// Curve loop of signed curve tags (negative = reversed), as given.
    pub fn geo_curve_loop(&self, curves: &[i32]) -> Result<i32> {
        call!(gmshModelGeoAddCurveLoop(
            curves.as_ptr(),
            curves.len(),
            -1,
            0
        ))
    }

    pub fn geo_plane_surface(&self, loops: &[i32]) -> Result<i32> {
        call!(gmshModelGeoAddPlaneSurface(loops.as_ptr(), loops.len(), -1))
    }

    /// Extrudes by translation with a layered (structured) mesh; returns the
    /// extruded entities (per input: top, volume, lateral entities).
    pub fn geo_extrude(
        &self,
        dim_tags: &[(i32, i32)],
        d: [f64; 3],
        layers: &[i32],
        recombine: bool,
    ) -> Result<Vec<(i32, i32)>> {
        let dt = flatten(dim_tags);
        let mut out = GmshArray::<c_int>::new();
        call!(gmshModelGeoExtrude(
            dt.as_ptr(),
            dt.len(),
            d[0],
            d[1],
            d[2],
            &mut out.ptr,
            &mut out.len,
            layers.as_ptr(),
            layers.len(),
            std::ptr::null(),
            0,
            recombine as c_int
        ))?;
        Ok(pairs(out.as_slice()))
    }

    /// Extrudes by a combined translation `d` and rotation by `angle` (< π)
    /// about the axis through `point` along `axis`, with a layered mesh.
    #[allow(clippy::too_many_arguments)]
    pub fn geo_twist(
        &self,
        dim_tags: &[(i32, i32)],
        point: [f64; 3],
        d: [f64; 3],
        axis: [f64; 3],
        angle: f64,
        layers: &[i32],
        recombine: bool,
    ) -> Result<Vec<(i32, i32)>> {
        let dt = flatten(dim_tags);
        let mut out = GmshArray::<c_int>::new();
        call!(gmshModelGeoTwist(
            dt.as_ptr(),
            dt.len(),
            point[0],
            point[1],
            point[2],
            d[0],
            d[1],
            d[2],
            axis[0],
            axis[1],
            axis[2],
            angle,
            &mut out.ptr,
            &mut out.len,
            layers.as_ptr(),
            layers.len(),
            std::ptr::null(),
            0,
            recombine as c_int
        ))?;
        Ok(pairs(out.as_slice()))
    }

    pub fn geo_synchronize(&self) -> Result<()> {
        call!(gmshModelGeoSynchronize())
    }

    // --- model ------------------------------------------------------------

    /// Entities of dimension `dim` (all if negative).
    pub fn entities(&self, dim: i32) -> Result<Vec<(i32, i32)>> {
        let mut out = GmshArray::<c_int>::new();
        call!(gmshModelGetEntities(&mut out.ptr, &mut out.len, dim))?;
        Ok(pairs(out.as_slice()))
    }

    /// Boundary entities of `dim_tags` (not combined, not oriented, one level).
    pub fn boundary(&self, dim_tags: &[(i32, i32)]) -> Result<Vec<(i32, i32)>> {
        let dt = flatten(dim_tags);
        let mut out = GmshArray::<c_int>::new();
        call!(gmshModelGetBoundary(
            dt.as_ptr(),
            dt.len(),
            &mut out.ptr,
            &mut out.len,
            0,
            0,
            0
        ))?;
        Ok(pairs(out.as_slice()))
    }

    /// Adds a named physical group of entities of dimension `dim`; returns its tag.
    pub fn physical_group(&self, dim: i32, tags: &[i32], name: &str) -> Result<i32> {
        let t = call!(gmshModelAddPhysicalGroup(
            dim,
            tags.as_ptr(),
            tags.len(),
            -1
        ))?;
        let c = cstring("gmshModelSetPhysicalName", name)?;
        call!(gmshModelSetPhysicalName(dim, t, c.as_ptr()))?;
        Ok(t)
    }

    // --- mesh size fields -----------------------------------------------------

    pub fn field_add(&self, kind: &str) -> Result<i32> {
        let c = cstring("gmshModelMeshFieldAdd", kind)?;
        call!(gmshModelMeshFieldAdd(c.as_ptr(), -1))
    }

    pub fn field_number(&self, field: i32, option: &str, value: f64) -> Result<()> {
        let c = cstring("gmshModelMeshFieldSetNumber", option)?;
        call!(gmshModelMeshFieldSetNumber(field, c.as_ptr(), value))
            .map_err(|e| FlankError::Model(format!("{e} (field {field}: {option} = {value})")))
    }

    pub fn field_numbers(&self, field: i32, option: &str, values: &[f64]) -> Result<()> {
        let c = cstring("gmshModelMeshFieldSetNumbers", option)?;
        call!(gmshModelMeshFieldSetNumbers(
            field,
            c.as_ptr(),
            values.as_ptr(),
            values.len()
        ))
        .map_err(|e| FlankError::Model(format!("{e} (field {field}: {option})")))
    }

    pub fn field_background(&self, field: i32) -> Result<()> {
        call!(gmshModelMeshFieldSetAsBackgroundMesh(field))
    }

    // --- mesh ---------------------------------------------------------------

    pub fn generate(&self, dim: i32) -> Result<()> {
        call!(gmshModelMeshGenerate(dim))
    }

    pub fn set_order(&self, order: i32) -> Result<()> {
        call!(gmshModelMeshSetOrder(order))
    }

    /// All mesh nodes: tags and coordinates (x, y, z per node).
    pub fn nodes(&self) -> Result<(Vec<usize>, Vec<f64>)> {
        let mut tags = GmshArray::<usize>::new();
        let mut coords = GmshArray::<f64>::new();
        let mut param = GmshArray::<f64>::new();
        call!(gmshModelMeshGetNodes(
            &mut tags.ptr,
            &mut tags.len,
            &mut coords.ptr,
            &mut coords.len,
            &mut param.ptr,
            &mut param.len,
            -1,
            -1,
            0,
            0
        ))?;
        if coords.len != 3 * tags.len {
            return Err(FlankError::Model(format!(
                "gmsh: gmshModelMeshGetNodes returned {} coordinates for {} nodes",
                coords.len, tags.len
            )));
        }
        Ok((tags.to_vec(), coords.to_vec()))
    }

    /// Moves node `tag` to `x`.
    pub fn set_node(&self, tag: usize, x: [f64; 3]) -> Result<()> {
        call!(gmshModelMeshSetNode(
            tag,
            x.as_ptr(),
            3,
            std::ptr::null(),
            0
        ))
    }

    /// Tags of the nodes of the elements of physical group (dim, tag).
    pub fn physical_group_nodes(&self, dim: i32, tag: i32) -> Result<Vec<usize>> {
        let mut tags = GmshArray::<usize>::new();
        let mut coords = GmshArray::<f64>::new();
        call!(gmshModelMeshGetNodesForPhysicalGroup(
            dim,
            tag,
            &mut tags.ptr,
            &mut tags.len,
            &mut coords.ptr,
            &mut coords.len
        ))?;
        Ok(tags.to_vec())
    }

    /// Element types present in entities of dimension `dim`.
    pub fn element_types(&self, dim: i32) -> Result<Vec<i32>> {
        let mut t = GmshArray::<c_int>::new();
        call!(gmshModelMeshGetElementTypes(
            &mut t.ptr, &mut t.len, dim, -1
        ))?;
        Ok(t.to_vec())
    }

    /// All elements of gmsh type `kind`: tags and node tags (gmsh node order).
    pub fn elements_of_type(&self, kind: i32) -> Result<(Vec<usize>, Vec<usize>)> {
        let mut tags = GmshArray::<usize>::new();
        let mut nodes = GmshArray::<usize>::new();
        call!(gmshModelMeshGetElementsByType(
            kind,
            &mut tags.ptr,
            &mut tags.len,
            &mut nodes.ptr,
            &mut nodes.len,
            -1,
            0,
            1
        ))?;
        Ok((tags.to_vec(), nodes.to_vec()))
    }

    /// Name, dimension, order, node count and reference node coordinates of
    /// gmsh element type `kind`.
    pub fn element_properties(&self, kind: i32) -> Result<ElementProperties> {
        let mut name: *mut c_char = std::ptr::null_mut();
        let (mut dim, mut order, mut nodes, mut primary) = (0, 0, 0, 0);
        let mut local = GmshArray::<f64>::new();
        call!(gmshModelMeshGetElementProperties(
            kind,
            &mut name,
            &mut dim,
            &mut order,
            &mut nodes,
            &mut local.ptr,
            &mut local.len,
            &mut primary
        ))?;
        let name = if name.is_null() {
            String::new()
        } else {
            // SAFETY: NUL-terminated string allocated by gmsh, freed once.
            let s = unsafe { CStr::from_ptr(name) }
                .to_string_lossy()
                .into_owned();
            unsafe { ffi::gmshFree(name as *mut c_void) };
            s
        };
        Ok(ElementProperties {
            name,
            dim,
            order,
            nodes: nodes.max(0) as usize,
            local_coords: local.to_vec(),
            primary_nodes: primary.max(0) as usize,
        })
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        let mut ierr: c_int = 0;
        // SAFETY: gmsh was initialized by `start`; the lock is still held.
        unsafe { ffi::gmshFinalize(&mut ierr) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn session_restarts_and_reports_errors() {
        // gmsh can be initialized again after finalize; errors carry the
        // function name and gmsh's message
        for _ in 0..2 {
            let s = Session::start().unwrap();
            s.model_add("t").unwrap();
            let e = s.option("Mesh.NoSuchOption", 1.0).unwrap_err().to_string();
            assert!(
                e.contains("gmshOptionSetNumber") && e.contains("NoSuchOption"),
                "{e}"
            );
            let e = s.geo_line(1000, 1001).unwrap_err().to_string();
            assert!(
                e.contains("gmshModelGeoAddLine") && e.contains("1000"),
                "{e}"
            );
            let p = s.geo_point([0.0; 3], 0.0).unwrap();
            let q = s.geo_point([1.0, 0.0, 0.0], 0.0).unwrap();
            assert!(s.geo_line(p, q).unwrap() > 0);
            s.geo_synchronize().unwrap();
            assert_eq!(s.entities(1).unwrap().len(), 1);
        }
    }
}
