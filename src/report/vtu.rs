//! VTK XML UnstructuredGrid (`.vtu`, ASCII) writer with quadratic cells, for
//! ParaView.
//!
//! # Node order
//!
//! * C3D20 / C3D20R → `VTK_QUADRATIC_HEXAHEDRON` (25). VTK lists corners
//!   0–7 like CalculiX (0–3 the bottom face, counter-clockwise seen from the
//!   top face 4–7), then midsides on edges (0,1) (1,2) (2,3) (3,0), (4,5)
//!   (5,6) (6,7) (7,4), (0,4) (1,5) (2,6) (3,7). CalculiX nodes 9–20 lie on
//!   edges 1-2, 2-3, 3-4, 4-1, 5-6, 6-7, 7-8, 8-5, 1-5, 2-6, 3-7, 4-8: the
//!   same edges in the same order, so the permutation is the identity.
//! * C3D15 → `VTK_QUADRATIC_WEDGE` (26). VTK lists corners 0–2 (bottom),
//!   3–5 (top), then midsides on (0,1) (1,2) (2,0), (3,4) (4,5) (5,3), (0,3)
//!   (1,4) (2,5); CalculiX nodes 7–15 lie on 1-2, 2-3, 3-1, 4-5, 5-6, 6-4,
//!   1-4, 2-5, 3-6: again the identity. Orientation: VTK's wedge parametric
//!   coordinates put points 0, 1, 2 at (0,0,0), (1,0,0), (0,1,0) and the top
//!   at t = 1, so the interpolation is positive exactly when (p1−p0)×(p2−p0)
//!   points toward the top face — the CalculiX convention. Older VTK
//!   documentation and face/volume code used the opposite winding (base
//!   normal pointing away from the top), and VTK has since aligned them with
//!   the parametric coordinates. Checked with VTK 9.7.2 (Python wheel): a
//!   CalculiX-ordered wedge written here gets volume +0.5 from
//!   `vtkCellSizeFilter` and outward face normals. Older ParaView releases
//!   may report negative cell volumes for wedges; the geometry is right.
//!
//! Node labels are always written as point data `node_label` and element
//! labels as cell data `element_label` (Int64).

use std::fmt::Write as _;
use std::path::Path;

use crate::fem::mesh::{ElementKind, Mesh};
use crate::{FlankError, Result};

/// A field given at the nodes: `values[components * node + c]`.
#[derive(Clone, Copy, Debug)]
pub struct PointField<'a> {
    pub name: &'a str,
    pub components: usize,
    pub values: &'a [f64],
}

/// A field given per element: `values[components * element + c]`.
#[derive(Clone, Copy, Debug)]
pub struct CellField<'a> {
    pub name: &'a str,
    pub components: usize,
    pub values: &'a [f64],
}

/// VTK cell type of an element kind.
pub fn vtk_cell_type(kind: ElementKind) -> u8 {
    match kind {
        ElementKind::C3D20 | ElementKind::C3D20R => 25,
        ElementKind::C3D15 => 26,
    }
}

/// Position in the CalculiX connectivity of each VTK node (see module docs:
/// the identity for both kinds).
pub fn vtk_node_order(kind: ElementKind) -> &'static [usize] {
    const HEX: [usize; 20] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19,
    ];
    const WEDGE: [usize; 15] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14];
    match kind {
        ElementKind::C3D20 | ElementKind::C3D20R => &HEX,
        ElementKind::C3D15 => &WEDGE,
    }
}

/// Writes `mesh` with the given fields to `path` as an ASCII `.vtu` file.
///
/// Errors (`FlankError::Model`) name the offending field if a field has the
/// wrong length, zero components, an empty or duplicate name, or a
/// non-finite value; `FlankError::Io` if the file cannot be written.
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    point_fields: &[PointField],
    cell_fields: &[CellField],
) -> Result<()> {
    let text = vtu_string(mesh, point_fields, cell_fields)?;
    crate::atomic_file::write(path, text)
}

/// The `.vtu` document [`write_vtu`] would write, with the same checks.
pub fn vtu_string(
    mesh: &Mesh,
    point_fields: &[PointField],
    cell_fields: &[CellField],
) -> Result<String> {
    let n = mesh.node_count();
    let m = mesh.elements.len();
    for (e, el) in mesh.elements.iter().enumerate() {
        if el.nodes.len() != el.kind.node_count() || el.nodes.iter().any(|&i| i >= n) {
            return Err(FlankError::Model(format!(
                "vtu: element {} (index {e}) has invalid connectivity",
                el.label
            )));
        }
    }
    let point_labels: Vec<&str> = point_fields.iter().map(|f| f.name).collect();
    let cell_labels: Vec<&str> = cell_fields.iter().map(|f| f.name).collect();
    for f in point_fields {
        check_field(
            "point",
            f.name,
            f.components,
            f.values,
            n,
            &point_labels,
            "node_label",
            |i| mesh.node_labels[i],
        )?;
    }
    for f in cell_fields {
        check_field(
            "cell",
            f.name,
            f.components,
            f.values,
            m,
            &cell_labels,
            "element_label",
            |i| mesh.elements[i].label,
        )?;
    }

    let mut s = String::with_capacity(96 * n + 160 * m + 1024);
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str(
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n",
    );
    s.push_str("  <UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{m}\">"
    );

    s.push_str("      <PointData>\n");
    int_array(&mut s, "node_label", mesh.node_labels.iter().copied());
    for f in point_fields {
        float_array(&mut s, f.name, f.components, f.values);
    }
    s.push_str("      </PointData>\n");

    s.push_str("      <CellData>\n");
    int_array(
        &mut s,
        "element_label",
        mesh.elements.iter().map(|e| e.label),
    );
    for f in cell_fields {
        float_array(&mut s, f.name, f.components, f.values);
    }
    s.push_str("      </CellData>\n");

    s.push_str("      <Points>\n");
    let coords: Vec<f64> = mesh.coords.iter().flatten().copied().collect();
    float_array(&mut s, "Points", 3, &coords);
    s.push_str("      </Points>\n");

    s.push_str("      <Cells>\n");
    s.push_str("        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for el in &mesh.elements {
        s.push_str("         ");
        for &p in vtk_node_order(el.kind) {
            let _ = write!(s, " {}", el.nodes[p]);
        }
        s.push('\n');
    }
    s.push_str("        </DataArray>\n");
    let mut offset = 0u64;
    int_array(
        &mut s,
        "offsets",
        mesh.elements.iter().map(|e| {
            offset += e.nodes.len() as u64;
            offset
        }),
    );
    s.push_str("        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for line in mesh.elements.chunks(20) {
        s.push_str("         ");
        for el in line {
            let _ = write!(s, " {}", vtk_cell_type(el.kind));
        }
        s.push('\n');
    }
    s.push_str("        </DataArray>\n");
    s.push_str("      </Cells>\n");
    s.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    Ok(s)
}

/// Validates one field; `label(i)` gives the deck label of entity `i` for messages.
#[allow(clippy::too_many_arguments)]
fn check_field(
    what: &str,
    name: &str,
    components: usize,
    values: &[f64],
    count: usize,
    all_names: &[&str],
    reserved: &str,
    label: impl Fn(usize) -> u64,
) -> Result<()> {
    let err = |msg: String| {
        Err(FlankError::Model(format!(
            "vtu: {what} field '{name}': {msg}"
        )))
    };
    if name.trim().is_empty() {
        return Err(FlankError::Model(format!(
            "vtu: {what} field with an empty name"
        )));
    }
    if name == reserved || all_names.iter().filter(|&&x| x == name).count() > 1 {
        return err("duplicate name".into());
    }
    if components == 0 {
        return err("zero components".into());
    }
    if values.len() != components * count {
        return err(format!(
            "{} values, expected {components} × {count} = {}",
            values.len(),
            components * count
        ));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        let entity = if what == "point" { "node" } else { "element" };
        return err(format!(
            "non-finite value {} at {entity} {} component {}",
            values[i],
            label(i / components),
            i % components
        ));
    }
    Ok(())
}

/// Escapes a string for an XML attribute value.
fn xml_escape(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for c in name.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(c),
        }
    }
    out
}

/// Appends a finite `f64` in shortest round-trip form; scientific notation
/// outside [1e-5, 1e15) so huge or tiny values stay short.
fn push_f64(s: &mut String, v: f64) {
    let a = v.abs();
    if a == 0.0 {
        s.push('0');
    } else if (1e-5..1e15).contains(&a) {
        let _ = write!(s, "{v}");
    } else {
        let _ = write!(s, "{v:e}");
    }
}

/// Float64 DataArray, one tuple per line.
fn float_array(s: &mut String, name: &str, components: usize, values: &[f64]) {
    let _ = writeln!(
        s,
        "        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{components}\" \
         format=\"ascii\">",
        xml_escape(name)
    );
    for tuple in values.chunks(components) {
        s.push_str("         ");
        for &v in tuple {
            s.push(' ');
            push_f64(s, v);
        }
        s.push('\n');
    }
    s.push_str("        </DataArray>\n");
}

/// Int64 DataArray, ten values per line.
fn int_array(s: &mut String, name: &str, values: impl Iterator<Item = u64>) {
    let _ = writeln!(
        s,
        "        <DataArray type=\"Int64\" Name=\"{}\" format=\"ascii\">",
        xml_escape(name)
    );
    let mut col = 0;
    for v in values {
        if col == 0 {
            s.push_str("         ");
        }
        let _ = write!(s, " {v}");
        col += 1;
        if col == 10 {
            s.push('\n');
            col = 0;
        }
    }
    if col != 0 {
        s.push('\n');
    }
    s.push_str("        </DataArray>\n");
}

/// The VTU file of a roll angle: `roll_+012.50deg.vtu`.
pub fn vtu_name(roll_deg: f64) -> String {
    format!("roll_{roll_deg:+08.3}deg.vtu")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::{box_mesh, BoxElement};

    /// Text of the DataArray named `name` (minimal parser for these files).
    fn array<'a>(doc: &'a str, name: &str) -> Vec<&'a str> {
        let tag = format!("Name=\"{name}\"");
        let start = doc.find(&tag).unwrap_or_else(|| panic!("no array {name}"));
        let body = &doc[start..];
        let body = &body[body.find('>').unwrap() + 1..];
        let body = &body[..body.find("</DataArray>").unwrap()];
        body.split_whitespace().collect()
    }

    fn attr(doc: &str, name: &str) -> usize {
        let tag = format!("{name}=\"");
        let start = doc.find(&tag).unwrap() + tag.len();
        doc[start..start + doc[start..].find('"').unwrap()]
            .parse()
            .unwrap()
    }

    fn check_roundtrip(mesh: &Mesh, vtk_type: &str, nodes_per_cell: usize) {
        let n = mesh.node_count();
        let u: Vec<f64> = (0..3 * n).map(|i| i as f64 * 1e-7 - 1.5e20).collect();
        let s: Vec<f64> = (0..mesh.elements.len()).map(|e| e as f64 + 0.25).collect();
        let doc = vtu_string(
            mesh,
            &[PointField {
                name: "U",
                components: 3,
                values: &u,
            }],
            &[CellField {
                name: "S<mises>",
                components: 1,
                values: &s,
            }],
        )
        .unwrap();
        assert!(doc.starts_with("<?xml"));
        assert_eq!(attr(&doc, "NumberOfPoints"), n);
        assert_eq!(attr(&doc, "NumberOfCells"), mesh.elements.len());
        let types = array(&doc, "types");
        assert_eq!(types.len(), mesh.elements.len());
        assert!(types.iter().all(|&t| t == vtk_type));
        let conn: Vec<usize> = array(&doc, "connectivity")
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        let expected: Vec<usize> = mesh.elements.iter().flat_map(|e| e.nodes.clone()).collect();
        assert_eq!(conn, expected);
        let offsets: Vec<usize> = array(&doc, "offsets")
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(
            offsets,
            (1..=mesh.elements.len())
                .map(|e| e * nodes_per_cell)
                .collect::<Vec<_>>()
        );
        let labels: Vec<u64> = array(&doc, "node_label")
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(labels, mesh.node_labels);
        assert_eq!(array(&doc, "element_label").len(), mesh.elements.len());
        let pts: Vec<f64> = array(&doc, "Points")
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(
            pts,
            mesh.coords.iter().flatten().copied().collect::<Vec<_>>()
        );
        let back: Vec<f64> = array(&doc, "U")
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(back, u, "floats must round-trip exactly");
        assert!(doc.contains("Name=\"S&lt;mises&gt;\""));
    }

    #[test]
    fn hex20_box_roundtrip() {
        let mesh = box_mesh([2.0, 1.0, 1.0], [2, 1, 1], BoxElement::Hex20);
        check_roundtrip(&mesh, "25", 20);
    }

    #[test]
    fn wedge_box_roundtrip() {
        let mesh = box_mesh([2.0, 1.0, 1.0], [2, 1, 1], BoxElement::Wedge15);
        check_roundtrip(&mesh, "26", 15);
        // VTK order = CalculiX order: bottom triangle winds toward the top face.
        for el in &mesh.elements {
            let p: Vec<[f64; 3]> = vtk_node_order(el.kind)
                .iter()
                .map(|&i| mesh.coords[el.nodes[i]])
                .collect();
            let (a, b) = (
                [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]],
                [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]],
            );
            let n = [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ];
            let up = [p[3][0] - p[0][0], p[3][1] - p[0][1], p[3][2] - p[0][2]];
            assert!(n[0] * up[0] + n[1] * up[1] + n[2] * up[2] > 0.0);
        }
    }

    #[test]
    fn bad_fields_are_errors() {
        let mesh = box_mesh([1.0; 3], [1, 1, 1], BoxElement::Hex20);
        let n = mesh.node_count();
        let mut u = vec![0.0; 3 * n];
        u[3 * 5 + 2] = f64::NAN;
        let err = vtu_string(
            &mesh,
            &[PointField {
                name: "disp",
                components: 3,
                values: &u,
            }],
            &[],
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("disp") && err.contains("NaN") && err.contains("node 6"),
            "{err}"
        );
        let short = vec![0.0; n];
        let err = vtu_string(
            &mesh,
            &[PointField {
                name: "T",
                components: 3,
                values: &short,
            }],
            &[],
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("'T'") && err.contains("expected"), "{err}");
        let inf = [f64::INFINITY];
        let err = vtu_string(
            &mesh,
            &[],
            &[CellField {
                name: "vm",
                components: 1,
                values: &inf,
            }],
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("vm") && err.contains("element 1"), "{err}");
        let ok = vec![1.0; n];
        let dup = [
            PointField {
                name: "a",
                components: 1,
                values: &ok,
            },
            PointField {
                name: "a",
                components: 1,
                values: &ok,
            },
        ];
        assert!(vtu_string(&mesh, &dup, &[]).is_err());
        let reserved = [PointField {
            name: "node_label",
            components: 1,
            values: &ok,
        }];
        assert!(vtu_string(&mesh, &reserved, &[]).is_err());
        let zero = [PointField {
            name: "z",
            components: 0,
            values: &[],
        }];
        assert!(vtu_string(&mesh, &zero, &[]).is_err());
        let path = std::env::temp_dir().join("flank-vtu-test-nonfinite.vtu");
        let _ = std::fs::remove_file(&path);
        assert!(write_vtu(
            &path,
            &mesh,
            &[],
            &[CellField {
                name: "vm",
                components: 1,
                values: &inf
            }]
        )
        .is_err());
        assert!(!path.exists(), "no file is written for invalid fields");
    }

    #[test]
    fn write_vtu_writes_file() {
        let mesh = box_mesh([1.0; 3], [1, 1, 2], BoxElement::Hex20R);
        let path = std::env::temp_dir().join(format!("flank-vtu-test-{}.vtu", std::process::id()));
        write_vtu(&path, &mesh, &[], &[]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(text, vtu_string(&mesh, &[], &[]).unwrap());
        assert_eq!(array(&text, "types"), ["25", "25"]);
        let bad = Path::new("/nonexistent-dir-flank/x.vtu");
        assert!(matches!(
            write_vtu(bad, &mesh, &[], &[]),
            Err(FlankError::Io { .. })
        ));
    }

    #[test]
    fn number_format() {
        let mut s = String::new();
        for v in [0.0, -0.0, 1.0, -2.5, 1e-7, 123456.789, 1e300, -4.2e-12] {
            push_f64(&mut s, v);
            s.push(' ');
        }
        assert_eq!(s, "0 0 1 -2.5 1e-7 123456.789 1e300 -4.2e-12 ");
    }
}
