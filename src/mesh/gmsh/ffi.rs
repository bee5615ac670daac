//! Hand-written bindings to the part of gmsh's C API (`gmshc.h`, gmsh 4.8,
//! Debian package `libgmsh-dev`) that flank uses. Only [`super`] calls them:
//! it holds the process-wide session lock, checks every `ierr` and frees
//! every array gmsh allocates with [`gmshFree`].
//!
//! Conventions of the C API: every function ends with `int *ierr` (0 = ok);
//! output arrays are `T **` + `size_t *` pairs allocated by gmsh; input arrays
//! are `T *` + `size_t` (declared `*const` here: gmsh does not write them);
//! `(dim, tag)` pairs are flattened into one `int` array.

#![allow(non_snake_case)]

use std::os::raw::{c_char, c_double, c_int, c_void};

#[link(name = "gmsh")]
extern "C" {
    pub fn gmshFree(p: *mut c_void);

    pub fn gmshInitialize(
        argc: c_int,
        argv: *mut *mut c_char,
        readConfigFiles: c_int,
        ierr: *mut c_int,
    );
    pub fn gmshFinalize(ierr: *mut c_int);
    pub fn gmshWrite(fileName: *const c_char, ierr: *mut c_int);

    pub fn gmshOptionSetNumber(name: *const c_char, value: c_double, ierr: *mut c_int);

    pub fn gmshModelAdd(name: *const c_char, ierr: *mut c_int);
    pub fn gmshModelGetBoundary(
        dimTags: *const c_int,
        dimTags_n: usize,
        outDimTags: *mut *mut c_int,
        outDimTags_n: *mut usize,
        combined: c_int,
        oriented: c_int,
        recursive: c_int,
        ierr: *mut c_int,
    );
    pub fn gmshModelGetEntities(
        dimTags: *mut *mut c_int,
        dimTags_n: *mut usize,
        dim: c_int,
        ierr: *mut c_int,
    );
    pub fn gmshModelAddPhysicalGroup(
        dim: c_int,
        tags: *const c_int,
        tags_n: usize,
        tag: c_int,
        ierr: *mut c_int,
    ) -> c_int;
    pub fn gmshModelSetPhysicalName(dim: c_int, tag: c_int, name: *const c_char, ierr: *mut c_int);

    pub fn gmshModelGeoAddPoint(
        x: c_double,
        y: c_double,
        z: c_double,
        meshSize: c_double,
        tag: c_int,
        ierr: *mut c_int,
    ) -> c_int;
    pub fn gmshModelGeoAddLine(
        startTag: c_int,
        endTag: c_int,
        tag: c_int,
        ierr: *mut c_int,
    ) -> c_int;
    pub fn gmshModelGeoAddCircleArc(
        startTag: c_int,
        centerTag: c_int,
        endTag: c_int,
        tag: c_int,
        nx: c_double,
        ny: c_double,
        nz: c_double,
        ierr: *mut c_int,
    ) -> c_int;
    pub fn gmshModelGeoAddSpline(
        pointTags: *const c_int,
        pointTags_n: usize,
        tag: c_int,
        ierr: *mut c_int,
    ) -> c_int;
    pub fn gmshModelGeoAddCurveLoop(
        curveTags: *const c_int,
        curveTags_n: usize,
        tag: c_int,
        reorient: c_int,
        ierr: *mut c_int,
    ) -> c_int;
    pub fn gmshModelGeoAddPlaneSurface(
        wireTags: *const c_int,
        wireTags_n: usize,
        tag: c_int,
        ierr: *mut c_int,
    ) -> c_int;
    pub fn gmshModelGeoExtrude(
        dimTags: *const c_int,
        dimTags_n: usize,
        dx: c_double,
        dy: c_double,
        dz: c_double,
        outDimTags: *mut *mut c_int,
        outDimTags_n: *mut usize,
        numElements: *const c_int,
        numElements_n: usize,
        heights: *const c_double,
        heights_n: usize,
        recombine: c_int,
        ierr: *mut c_int,
    );
    pub fn gmshModelGeoTwist(
        dimTags: *const c_int,
        dimTags_n: usize,
        x: c_double,
        y: c_double,
        z: c_double,
        dx: c_double,
        dy: c_double,
        dz: c_double,
        ax: c_double,
        ay: c_double,
        az: c_double,
        angle: c_double,
        outDimTags: *mut *mut c_int,
        outDimTags_n: *mut usize,
        numElements: *const c_int,
        numElements_n: usize,
        heights: *const c_double,
        heights_n: usize,
        recombine: c_int,
        ierr: *mut c_int,
    );
    pub fn gmshModelGeoSynchronize(ierr: *mut c_int);

    pub fn gmshModelMeshFieldAdd(fieldType: *const c_char, tag: c_int, ierr: *mut c_int) -> c_int;
    pub fn gmshModelMeshFieldSetNumber(
        tag: c_int,
        option: *const c_char,
        value: c_double,
        ierr: *mut c_int,
    );
    pub fn gmshModelMeshFieldSetNumbers(
        tag: c_int,
        option: *const c_char,
        value: *const c_double,
        value_n: usize,
        ierr: *mut c_int,
    );
    pub fn gmshModelMeshFieldSetAsBackgroundMesh(tag: c_int, ierr: *mut c_int);

    pub fn gmshModelMeshGenerate(dim: c_int, ierr: *mut c_int);
    pub fn gmshModelMeshSetOrder(order: c_int, ierr: *mut c_int);
    pub fn gmshModelMeshGetNodes(
        nodeTags: *mut *mut usize,
        nodeTags_n: *mut usize,
        coord: *mut *mut c_double,
        coord_n: *mut usize,
        parametricCoord: *mut *mut c_double,
        parametricCoord_n: *mut usize,
        dim: c_int,
        tag: c_int,
        includeBoundary: c_int,
        returnParametricCoord: c_int,
        ierr: *mut c_int,
    );
    pub fn gmshModelMeshSetNode(
        nodeTag: usize,
        coord: *const c_double,
        coord_n: usize,
        parametricCoord: *const c_double,
        parametricCoord_n: usize,
        ierr: *mut c_int,
    );
    pub fn gmshModelMeshGetNodesForPhysicalGroup(
        dim: c_int,
        tag: c_int,
        nodeTags: *mut *mut usize,
        nodeTags_n: *mut usize,
        coord: *mut *mut c_double,
        coord_n: *mut usize,
        ierr: *mut c_int,
    );
    pub fn gmshModelMeshGetElementTypes(
        elementTypes: *mut *mut c_int,
        elementTypes_n: *mut usize,
        dim: c_int,
        tag: c_int,
        ierr: *mut c_int,
    );
    pub fn gmshModelMeshGetElementProperties(
        elementType: c_int,
        elementName: *mut *mut c_char,
        dim: *mut c_int,
        order: *mut c_int,
        numNodes: *mut c_int,
        localNodeCoord: *mut *mut c_double,
        localNodeCoord_n: *mut usize,
        numPrimaryNodes: *mut c_int,
        ierr: *mut c_int,
    );
    pub fn gmshModelMeshGetElementsByType(
        elementType: c_int,
        elementTags: *mut *mut usize,
        elementTags_n: *mut usize,
        nodeTags: *mut *mut usize,
        nodeTags_n: *mut usize,
        tag: c_int,
        task: usize,
        numTasks: usize,
        ierr: *mut c_int,
    );

    pub fn gmshLoggerGetLastError(error: *mut *mut c_char, ierr: *mut c_int);
}
