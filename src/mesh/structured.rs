//! Structured meshes for verification (boxes, cylinders, plates).
