//! Native reader of gmsh `.msh` files, format 4.1 ASCII (no gmsh library
//! needed): the mesh other tools exchange, imported as a flank [`Mesh`].
//!
//! Read sections: `$MeshFormat` (must be `4.1 0 8`: other versions and
//! binary files are refused with what to do instead), `$PhysicalNames`,
//! `$Entities`, `$Nodes`, `$Elements`; other sections (`$NodeData`,
//! `$Periodic`, comments, …) are skipped, as gmsh does with sections it
//! does not know. Partitioned meshes are refused.
//!
//! * Volume elements: type 17 (20-node hexahedron) → C3D20 and type 18
//!   (15-node prism) → C3D15, permuted into CalculiX node order. Every
//!   other volume type is an error saying which types are supported and to
//!   export with `Mesh.SecondOrderIncomplete = 1` (order 2).
//! * Lower-dimensional elements (points, lines, triangles, quadrangles of
//!   any order) only build node sets: every physical group of dimension 0–2
//!   becomes a node set of all nodes of its elements, named by its
//!   `$PhysicalNames` name (upper-cased; `PG<dim>_<tag>` if it has none).
//!   Every physical group of dimension 3 becomes an element set.
//! * Labels are gmsh's node and element tags.
//!
//! Node order (gmsh → CalculiX), `ccx[i] = gmsh[perm[i]]`, from gmsh's
//! documented reference elements (edges of the hexahedron: gmsh numbers its
//! midside nodes 8..19 on edges 0-1, 0-3, 0-4, 1-2, 1-5, 2-3, 2-6, 3-7, 4-5,
//! 4-7, 5-6, 6-7; CalculiX on 0-1, 1-2, 2-3, 3-0, 4-5, 5-6, 6-7, 7-4, 0-4,
//! 1-5, 2-6, 3-7; prism: gmsh 6..14 on 0-1, 0-2, 0-3, 1-2, 1-4, 2-5, 3-4, 3-5,
//! 4-5; CalculiX 0-1, 1-2, 2-0, 3-4, 4-5, 5-3, 0-3, 1-4, 2-5; corners agree):
//!
//! | CalculiX position | 0–7 | 8 | 9 | 10 | 11 | 12 | 13 | 14 | 15 | 16 | 17 | 18 | 19 |
//! |---|---|---|---|---|---|---|---|---|---|---|---|---|---|
//! | C3D20 ← gmsh 17 | 0–7 | 8 | 11 | 13 | 9 | 16 | 18 | 19 | 17 | 10 | 12 | 14 | 15 |
//!
//! | CalculiX position | 0–5 | 6 | 7 | 8 | 9 | 10 | 11 | 12 | 13 | 14 |
//! |---|---|---|---|---|---|---|---|---|---|---|
//! | C3D15 ← gmsh 18 | 0–5 | 6 | 9 | 7 | 12 | 14 | 13 | 8 | 10 | 11 |
//!
//! (the tables of DESIGN.md; with the `gmsh` feature a test checks them
//! against gmsh's own reference node coordinates).
//!
//! Malformed input is an error with `file:line`; no input makes the reader
//! panic.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use crate::error::FlankError;
use crate::fem::mesh::{ElementKind, Mesh};

type Result<T> = std::result::Result<T, FlankError>;

/// gmsh type 17 (20-node hexahedron) → C3D20: `ccx[i] = gmsh[GMSH_HEX20_TO_CCX[i]]`.
pub const GMSH_HEX20_TO_CCX: [usize; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15,
];

/// gmsh type 18 (15-node prism) → C3D15: `ccx[i] = gmsh[GMSH_PRISM15_TO_CCX[i]]`.
pub const GMSH_PRISM15_TO_CCX: [usize; 15] = [0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11];

/// (name, node count, dimension) of the gmsh element types up to order 3/4.
fn gmsh_type(t: i64) -> Option<(&'static str, usize, usize)> {
    Some(match t {
        1 => ("2-node line", 2, 1),
        2 => ("3-node triangle", 3, 2),
        3 => ("4-node quadrangle", 4, 2),
        4 => ("4-node tetrahedron", 4, 3),
        5 => ("8-node hexahedron", 8, 3),
        6 => ("6-node prism", 6, 3),
        7 => ("5-node pyramid", 5, 3),
        8 => ("3-node line", 3, 1),
        9 => ("6-node triangle", 6, 2),
        10 => ("9-node quadrangle", 9, 2),
        11 => ("10-node tetrahedron", 10, 3),
        12 => ("27-node hexahedron", 27, 3),
        13 => ("18-node prism", 18, 3),
        14 => ("14-node pyramid", 14, 3),
        15 => ("1-node point", 1, 0),
        16 => ("8-node quadrangle", 8, 2),
        17 => ("20-node hexahedron", 20, 3),
        18 => ("15-node prism", 15, 3),
        19 => ("13-node pyramid", 13, 3),
        20 => ("9-node triangle", 9, 2),
        21 => ("10-node triangle", 10, 2),
        22 => ("12-node triangle", 12, 2),
        23 => ("15-node triangle", 15, 2),
        24 => ("15-node incomplete triangle", 15, 2),
        25 => ("21-node triangle", 21, 2),
        26 => ("4-node line", 4, 1),
        27 => ("5-node line", 5, 1),
        28 => ("6-node line", 6, 1),
        29 => ("20-node tetrahedron", 20, 3),
        30 => ("35-node tetrahedron", 35, 3),
        31 => ("56-node tetrahedron", 56, 3),
        36 => ("16-node quadrangle", 16, 2),
        37 => ("25-node quadrangle", 25, 2),
        92 => ("64-node hexahedron", 64, 3),
        93 => ("125-node hexahedron", 125, 3),
        _ => return None,
    })
}

const SUPPORTED: &str = "flank reads type 17 (20-node hexahedron → C3D20) and type 18 (15-node prism → C3D15); \
     export order 2 with Mesh.SecondOrderIncomplete = 1 (gmsh -3 -order 2 -setnumber Mesh.SecondOrderIncomplete 1)";

/// Reads a gmsh `.msh` 4.1 ASCII file (see the module docs).
pub fn read_msh(path: &Path) -> Result<Mesh> {
    let bytes = std::fs::read(path).map_err(|e| FlankError::io(path, e))?;
    // Binary files have an ASCII header: parse lossily, the header check
    // refuses them before their data is read.
    let text = String::from_utf8_lossy(&bytes);
    parse_msh(&text, path)
}

/// One `$Name … $EndName` block: its body lines with 1-based numbers.
struct Section<'a> {
    name: &'a str,
    line: usize,
    end_line: usize,
    body: Vec<(usize, &'a str)>,
}

/// Whitespace-separated tokens of a section body, with their line numbers.
struct Tokens<'a> {
    file: &'a Path,
    section: &'a str,
    end_line: usize,
    toks: Vec<(usize, &'a str)>,
    pos: usize,
}

impl<'a> Tokens<'a> {
    fn new(file: &'a Path, s: &Section<'a>) -> Self {
        let toks = s
            .body
            .iter()
            .flat_map(|&(n, l)| l.split_whitespace().map(move |t| (n, t)))
            .collect();
        Tokens {
            file,
            section: s.name,
            end_line: s.end_line,
            toks,
            pos: 0,
        }
    }

    fn line(&self) -> usize {
        self.toks
            .get(self.pos)
            .map(|t| t.0)
            .unwrap_or(self.end_line)
    }

    fn err(&self, line: usize, msg: String) -> FlankError {
        FlankError::Parse {
            file: self.file.to_path_buf(),
            line,
            message: format!("${}: {msg}", self.section),
        }
    }

    fn next(&mut self, what: &str) -> Result<(usize, &'a str)> {
        match self.toks.get(self.pos) {
            Some(&t) => {
                self.pos += 1;
                Ok(t)
            }
            None => Err(self.err(
                self.end_line,
                format!("section ends early: expected {what}"),
            )),
        }
    }

    fn int(&mut self, what: &str) -> Result<(usize, i64)> {
        let (l, t) = self.next(what)?;
        t.parse::<i64>()
            .map(|v| (l, v))
            .map_err(|_| self.err(l, format!("expected {what} (an integer), found {t:?}")))
    }

    fn count(&mut self, what: &str) -> Result<usize> {
        let (l, v) = self.int(what)?;
        usize::try_from(v).map_err(|_| self.err(l, format!("{what} must be ≥ 0, found {v}")))
    }

    fn tag(&mut self, what: &str) -> Result<(usize, u64)> {
        let (l, v) = self.int(what)?;
        if v <= 0 {
            return Err(self.err(l, format!("{what} must be a positive tag, found {v}")));
        }
        Ok((l, v as u64))
    }

    fn real(&mut self, what: &str) -> Result<f64> {
        let (l, t) = self.next(what)?;
        match t.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.err(l, format!("expected {what} (a finite number), found {t:?}"))),
        }
    }

    fn finish(&self) -> Result<()> {
        match self.toks.get(self.pos) {
            Some(&(l, t)) => Err(self.err(
                l,
                format!("unexpected data {t:?} after the declared entries"),
            )),
            None => Ok(()),
        }
    }
}

fn parse_err(file: &Path, line: usize, message: String) -> FlankError {
    FlankError::Parse {
        file: file.to_path_buf(),
        line,
        message,
    }
}

/// Parses `.msh` 4.1 ASCII text; `file` names it in error messages.
pub fn parse_msh(text: &str, file: &Path) -> Result<Mesh> {
    let lines: Vec<(usize, &str)> = text.lines().enumerate().map(|(i, l)| (i + 1, l)).collect();
    let mut i = 0;
    let mut format_seen = false;
    let mut names: HashMap<(usize, i64), String> = HashMap::new();
    // (dim, entity tag) → physical tags
    let mut entity_phys: HashMap<(usize, i64), Vec<i64>> = HashMap::new();
    let mut mesh = Mesh::new();
    let mut nodes_seen = false;
    let mut elements_seen = false;
    // (dim, physical tag) → node indices / element indices
    let mut group_nodes: BTreeMap<(usize, i64), Vec<usize>> = BTreeMap::new();
    let mut group_elems: BTreeMap<(usize, i64), Vec<usize>> = BTreeMap::new();
    while i < lines.len() {
        let (ln, raw) = lines[i];
        let l = raw.trim();
        i += 1;
        if l.is_empty() {
            continue;
        }
        let Some(name) = l.strip_prefix('$') else {
            return Err(parse_err(
                file,
                ln,
                format!(
                    "expected a section header like $Nodes, found {:?}",
                    short(l)
                ),
            ));
        };
        let end = format!("$End{name}");
        let start = i;
        while i < lines.len() && lines[i].1.trim() != end {
            i += 1;
        }
        if !format_seen && name != "MeshFormat" {
            return Err(parse_err(
                file,
                ln,
                format!(
                    "not a gmsh .msh file: it must start with $MeshFormat, found ${}",
                    short(name)
                ),
            ));
        }
        let body_end = i.min(lines.len());
        let section = Section {
            name,
            line: ln,
            end_line: lines.get(i).map(|x| x.0).unwrap_or(ln),
            body: lines[start..body_end].to_vec(),
        };
        // the format line is checked before the section's end is required,
        // so that binary files get the right message
        if name == "MeshFormat" {
            check_format(file, &section)?;
            format_seen = true;
        }
        if i >= lines.len() {
            return Err(parse_err(
                file,
                ln,
                format!("section ${name} is not closed ({end} missing)"),
            ));
        }
        i += 1; // the $End line
        match name {
            "MeshFormat" => {}
            "PhysicalNames" => names = parse_physical_names(file, &section)?,
            "Entities" => entity_phys = parse_entities(file, &section)?,
            "PartitionedEntities" => {
                return Err(parse_err(
                    file,
                    ln,
                    "partitioned meshes are not supported: save the unpartitioned mesh".into(),
                ))
            }
            "Nodes" => {
                if nodes_seen {
                    return Err(parse_err(file, ln, "a second $Nodes section".into()));
                }
                parse_nodes(file, &section, &mut mesh)?;
                nodes_seen = true;
            }
            "Elements" => {
                if !nodes_seen {
                    return Err(parse_err(
                        file,
                        ln,
                        "$Elements before $Nodes: the nodes must come first".into(),
                    ));
                }
                if elements_seen {
                    return Err(parse_err(file, ln, "a second $Elements section".into()));
                }
                parse_elements(
                    file,
                    &section,
                    &entity_phys,
                    &mut mesh,
                    &mut group_nodes,
                    &mut group_elems,
                )?;
                elements_seen = true;
            }
            _ => {} // unknown or unused sections are skipped, as gmsh does
        }
    }
    let last = lines.last().map(|l| l.0).unwrap_or(1);
    if !format_seen {
        return Err(parse_err(
            file,
            1,
            "not a gmsh .msh file: no $MeshFormat section".into(),
        ));
    }
    if !nodes_seen {
        return Err(parse_err(file, last, "no $Nodes section".into()));
    }
    if !elements_seen {
        return Err(parse_err(file, last, "no $Elements section".into()));
    }
    if mesh.elements.is_empty() {
        return Err(parse_err(
            file,
            last,
            format!("no volume elements in the file: {SUPPORTED}"),
        ));
    }
    let group_name = |dim: usize, tag: i64| {
        names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| format!("PG{dim}_{tag}"))
    };
    for ((dim, tag), v) in group_nodes {
        mesh.extend_node_set(&group_name(dim, tag), v);
    }
    for ((dim, tag), v) in group_elems {
        mesh.extend_element_set(&group_name(dim, tag), v);
    }
    Ok(mesh)
}

fn short(s: &str) -> String {
    s.chars().take(40).collect()
}

fn check_format(file: &Path, s: &Section) -> Result<()> {
    let Some(&(ln, l)) = s.body.iter().find(|(_, l)| !l.trim().is_empty()) else {
        return Err(parse_err(file, s.line, "$MeshFormat is empty".into()));
    };
    let f: Vec<&str> = l.split_whitespace().collect();
    if f.len() < 3 {
        return Err(parse_err(
            file,
            ln,
            format!(
                "$MeshFormat: expected \"version file-type data-size\", found {:?}",
                short(l)
            ),
        ));
    }
    if f[1] != "0" {
        if f[1] == "1" {
            return Err(parse_err(
                file,
                ln,
                "binary .msh files are not supported: save as ASCII (gmsh: Mesh.Binary = 0, or -bin off)".into(),
            ));
        }
        return Err(parse_err(
            file,
            ln,
            format!(
                "$MeshFormat: file-type must be 0 (ASCII), found {:?}",
                short(f[1])
            ),
        ));
    }
    if f[0] != "4.1" {
        return Err(parse_err(
            file,
            ln,
            format!(
                "MSH version {} is not supported: save as MSH 4.1 ASCII (gmsh: Mesh.MshFileVersion = 4.1, or -format msh41)",
                short(f[0])
            ),
        ));
    }
    Ok(())
}

fn parse_physical_names(file: &Path, s: &Section) -> Result<HashMap<(usize, i64), String>> {
    let mut body = s.body.iter().filter(|(_, l)| !l.trim().is_empty());
    let Some(&(ln, first)) = body.next() else {
        return Err(parse_err(
            file,
            s.end_line,
            "$PhysicalNames: no count".into(),
        ));
    };
    let n: usize = first.trim().parse().map_err(|_| {
        parse_err(
            file,
            ln,
            format!(
                "$PhysicalNames: expected the number of names, found {:?}",
                short(first)
            ),
        )
    })?;
    let mut out = HashMap::new();
    let mut read = 0;
    for &(ln, l) in body {
        let l = l.trim();
        let mut it = l.splitn(3, char::is_whitespace);
        let (d, t, rest) = (it.next(), it.next(), it.next().map(str::trim));
        let bad = || {
            parse_err(
                file,
                ln,
                format!(
                    "$PhysicalNames: expected 'dim tag \"name\"', found {:?}",
                    short(l)
                ),
            )
        };
        let (Some(d), Some(t), Some(rest)) = (d, t, rest) else {
            return Err(bad());
        };
        let dim: usize = d.parse().map_err(|_| bad())?;
        let tag: i64 = t.parse().map_err(|_| bad())?;
        if dim > 3 || rest.len() < 2 || !rest.starts_with('"') || !rest.ends_with('"') {
            return Err(bad());
        }
        out.insert((dim, tag), rest[1..rest.len() - 1].to_string());
        read += 1;
    }
    if read != n {
        return Err(parse_err(
            file,
            s.end_line,
            format!("$PhysicalNames: {n} names declared, {read} found"),
        ));
    }
    Ok(out)
}

fn parse_entities(file: &Path, s: &Section) -> Result<HashMap<(usize, i64), Vec<i64>>> {
    let mut t = Tokens::new(file, s);
    let mut counts = [0usize; 4];
    for (d, c) in counts.iter_mut().enumerate() {
        *c = t.count(&format!("the number of dimension-{d} entities"))?;
    }
    let mut out = HashMap::new();
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let (l, tag) = t.int("an entity tag")?;
            let coords = if dim == 0 { 3 } else { 6 };
            for _ in 0..coords {
                t.real("a coordinate of the entity's bounding box")?;
            }
            let np = t.count("the number of physical tags")?;
            let mut phys = Vec::new();
            for _ in 0..np {
                phys.push(t.int("a physical tag")?.1);
            }
            if dim > 0 {
                let nb = t.count("the number of bounding entities")?;
                for _ in 0..nb {
                    t.int("a bounding entity tag")?;
                }
            }
            if out.insert((dim, tag), phys).is_some() {
                return Err(t.err(l, format!("dimension-{dim} entity {tag} is defined twice")));
            }
        }
    }
    t.finish()?;
    Ok(out)
}

fn parse_nodes(file: &Path, s: &Section, mesh: &mut Mesh) -> Result<()> {
    let mut t = Tokens::new(file, s);
    let blocks = t.count("the number of entity blocks")?;
    let total = t.count("the number of nodes")?;
    t.int("the minimum node tag")?;
    t.int("the maximum node tag")?;
    let mut read = 0usize;
    let mut tags = Vec::new();
    for _ in 0..blocks {
        let (l, dim) = t.int("the entity dimension")?;
        if !(0..=3).contains(&dim) {
            return Err(t.err(l, format!("entity dimension {dim} is not in 0..3")));
        }
        t.int("the entity tag")?;
        let (lp, parametric) = t.int("the parametric flag")?;
        if parametric != 0 && parametric != 1 {
            return Err(t.err(
                lp,
                format!("parametric flag must be 0 or 1, found {parametric}"),
            ));
        }
        let n = t.count("the number of nodes in the block")?;
        tags.clear();
        for _ in 0..n {
            tags.push(t.tag("a node tag")?);
        }
        let extra = if parametric == 1 { dim as usize } else { 0 };
        for &(lt, tag) in &tags {
            let line = t.line();
            let x = [
                t.real("a node coordinate")?,
                t.real("a node coordinate")?,
                t.real("a node coordinate")?,
            ];
            for _ in 0..extra {
                t.real("a parametric coordinate")?;
            }
            mesh.add_node(tag, x)
                .map_err(|_| t.err(line.max(lt), format!("node {tag} is defined twice")))?;
        }
        read += n;
    }
    if read != total {
        return Err(t.err(
            t.line(),
            format!("{total} nodes declared, {read} found in the blocks"),
        ));
    }
    t.finish()
}

fn parse_elements(
    file: &Path,
    s: &Section,
    entity_phys: &HashMap<(usize, i64), Vec<i64>>,
    mesh: &mut Mesh,
    group_nodes: &mut BTreeMap<(usize, i64), Vec<usize>>,
    group_elems: &mut BTreeMap<(usize, i64), Vec<usize>>,
) -> Result<()> {
    let mut t = Tokens::new(file, s);
    let blocks = t.count("the number of entity blocks")?;
    let total = t.count("the number of elements")?;
    t.int("the minimum element tag")?;
    t.int("the maximum element tag")?;
    let mut read = 0usize;
    let mut gnodes: Vec<usize> = Vec::new();
    let none = Vec::new();
    for _ in 0..blocks {
        let (ld, dim) = t.int("the entity dimension")?;
        if !(0..=3).contains(&dim) {
            return Err(t.err(ld, format!("entity dimension {dim} is not in 0..3")));
        }
        let dim = dim as usize;
        let (_, etag) = t.int("the entity tag")?;
        let (lt, ty) = t.int("the element type")?;
        let n = t.count("the number of elements in the block")?;
        let Some((tname, nn, tdim)) = gmsh_type(ty) else {
            return Err(t.err(lt, format!("unknown element type {ty}; {SUPPORTED}")));
        };
        if tdim != dim {
            return Err(t.err(
                lt,
                format!("element type {ty} ({tname}) is {tdim}-dimensional but its block is on a dimension-{dim} entity"),
            ));
        }
        let (kind, perm): (Option<ElementKind>, &[usize]) = match ty {
            17 => (Some(ElementKind::C3D20), &GMSH_HEX20_TO_CCX),
            18 => (Some(ElementKind::C3D15), &GMSH_PRISM15_TO_CCX),
            _ if tdim == 3 => {
                let why = match ty {
                    12..=14 => "a complete second-order element (with face/volume nodes)",
                    4..=7 => "a first-order element",
                    _ if ty == 11 || (29..=31).contains(&ty) => "a tetrahedron (not supported)",
                    19 => "a pyramid (not supported)",
                    _ => "not supported",
                };
                return Err(t.err(
                    lt,
                    format!("element type {ty} ({tname}) is {why}; {SUPPORTED}"),
                ));
            }
            _ => (None, &[]),
        };
        let phys = entity_phys.get(&(dim, etag)).unwrap_or(&none);
        for _ in 0..n {
            let (le, tag) = t.tag("an element tag")?;
            gnodes.clear();
            for _ in 0..nn {
                let (ln, nt) = t.tag("a node tag of the element")?;
                let idx = mesh.node(nt).ok_or_else(|| {
                    t.err(
                        ln,
                        format!("element {tag} refers to node {nt}, which is not in $Nodes"),
                    )
                })?;
                gnodes.push(idx);
            }
            match kind {
                Some(k) => {
                    let nodes: Vec<usize> = perm.iter().map(|&p| gnodes[p]).collect();
                    let e = mesh
                        .add_element(tag, k, nodes)
                        .map_err(|_| t.err(le, format!("element {tag} is defined twice")))?;
                    for &p in phys {
                        group_elems.entry((3, p)).or_default().push(e);
                    }
                }
                None => {
                    for &p in phys {
                        group_nodes
                            .entry((dim, p))
                            .or_default()
                            .extend_from_slice(&gnodes);
                    }
                }
            }
        }
        read += n;
    }
    if read != total {
        return Err(t.err(
            t.line(),
            format!("{total} elements declared, {read} found in the blocks"),
        ));
    }
    t.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::{check_jacobian, det3, edges, jacobian, ReferenceElement};
    use crate::testing::Rng;

    const FIXTURE: &str = include_str!("../../tests/data/blocks.msh");

    fn parse(text: &str) -> Result<Mesh> {
        parse_msh(text, Path::new("t.msh"))
    }

    /// The message and line of a parse error.
    #[track_caller]
    fn parse_error(text: &str) -> (String, usize) {
        match parse(text) {
            Err(FlankError::Parse { line, message, .. }) => (message, line),
            Err(e) => panic!("not a parse error: {e}"),
            Ok(_) => panic!("parsed"),
        }
    }

    fn line_of(text: &str, pat: &str) -> usize {
        text.lines().position(|l| l.starts_with(pat)).unwrap() + 1
    }

    #[test]
    fn fixture_reads_with_calculix_node_order_and_sets() {
        let m = parse(FIXTURE).unwrap();
        assert_eq!(m.node_count(), 55);
        let hex: Vec<usize> = (0..m.elements.len())
            .filter(|&e| m.elements[e].kind == ElementKind::C3D20)
            .collect();
        let wedge: Vec<usize> = (0..m.elements.len())
            .filter(|&e| m.elements[e].kind == ElementKind::C3D15)
            .collect();
        assert_eq!((hex.len(), wedge.len()), (2, 4));
        // valid elements, straight edges: every CalculiX midside node halfway
        // between its corners (checks the permutation), volume 2 × 1 × 1
        let mut volume = 0.0;
        for e in 0..m.elements.len() {
            let kind = m.elements[e].kind;
            let x = m.element_coords(e);
            check_jacobian(kind, &x).unwrap();
            for ed in edges(kind) {
                for c in 0..3 {
                    let mid = 0.5 * (x[ed[0]][c] + x[ed[1]][c]);
                    // gmsh places midside nodes to ~1e-12
                    assert!((x[ed[2]][c] - mid).abs() < 1e-9, "element {e} edge {ed:?}");
                }
            }
            let re = ReferenceElement::get(kind);
            for (p, d) in re.points.iter().zip(&re.derivatives) {
                volume += det3(&jacobian(&x, d)) * p.weight;
            }
        }
        assert!((volume - 2.0).abs() < 1e-12, "{volume}");
        let set = |name: &str| m.node_sets[name].clone();
        let select = |f: &dyn Fn([f64; 3]) -> bool| -> Vec<usize> {
            (0..m.node_count()).filter(|&i| f(m.coords[i])).collect()
        };
        assert_eq!(set("CORNER"), select(&|x| x == [0.0; 3]));
        assert_eq!(set("EDGE"), select(&|x| x[0] == 2.0 && x[2] == 0.0));
        assert_eq!(set("EDGE").len(), 3);
        assert_eq!(set("BOTTOM"), select(&|x| x[2] == 0.0));
        assert_eq!(set("X0"), select(&|x| x[0] == 0.0));
        // an unnamed physical group keeps its tag in the name
        assert_eq!(set("PG2_77"), select(&|x| x[2] == 1.0 && x[0] >= 1.0));
        assert_eq!(m.element_sets["SOLID"].len(), 6);
        assert_eq!(m.element_sets["PRISMS"], wedge);
        // labels are gmsh's tags
        assert!(m.node(55).is_some());
        assert_eq!(m.elements[hex[0]].label, 14);
    }

    #[test]
    fn reads_file_and_reports_missing_file() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/blocks.msh");
        assert_eq!(read_msh(&p).unwrap().elements.len(), 6);
        let e = read_msh(Path::new("/nonexistent/x.msh")).unwrap_err();
        assert!(matches!(e, FlankError::Io { .. }), "{e}");
    }

    /// A minimal file with one element of gmsh type `ty` on a volume.
    fn one_element(ty: usize, nodes: usize) -> String {
        let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n");
        s += &format!("1 {nodes} 1 {nodes}\n3 1 0 {nodes}\n");
        for i in 1..=nodes {
            s += &format!("{i}\n");
        }
        for i in 1..=nodes {
            s += &format!("{} {} {}\n", i as f64, (i * i) as f64, 0.5 * i as f64);
        }
        s += &format!("$EndNodes\n$Elements\n1 1 1 1\n3 1 {ty} 1\n1");
        for i in 1..=nodes {
            s += &format!(" {i}");
        }
        s += "\n$EndElements\n";
        s
    }

    #[test]
    fn unsupported_element_types_say_what_to_do() {
        for (ty, n, what) in [
            (12, 27, "27-node hexahedron"),
            (11, 10, "10-node tetrahedron"),
            (5, 8, "first-order"),
            (13, 18, "complete second-order"),
        ] {
            let text = one_element(ty, n);
            let (msg, line) = parse_error(&text);
            assert_eq!(line, line_of(&text, &format!("3 1 {ty} 1")), "{msg}");
            assert!(
                msg.contains(what)
                    && msg.contains("Mesh.SecondOrderIncomplete = 1")
                    && msg.contains("type 17")
                    && msg.contains("type 18"),
                "{msg}"
            );
        }
        let (msg, _) = parse_error(&one_element(99, 4));
        assert!(msg.contains("unknown element type 99"), "{msg}");
        // and the supported ones parse
        assert_eq!(parse(&one_element(17, 20)).unwrap().elements.len(), 1);
        assert_eq!(parse(&one_element(18, 15)).unwrap().elements.len(), 1);
    }

    #[test]
    fn format_errors() {
        let v22 = FIXTURE.replacen("4.1 0 8", "2.2 0 8", 1);
        let (msg, line) = parse_error(&v22);
        assert!(
            msg.contains("MSH version 2.2") && msg.contains("4.1"),
            "{msg}"
        );
        assert_eq!(line, 2);
        let bin = "$MeshFormat\n4.1 1 8\n\u{1}\u{0}\u{0}\u{0}\n$EndMeshFormat\n$Nodes\n\u{7f}\u{3}";
        let (msg, line) = parse_error(bin);
        assert!(msg.contains("binary") && msg.contains("ASCII"), "{msg}");
        assert_eq!(line, 2);
        let (msg, line) = parse_error("");
        assert!(msg.contains("no $MeshFormat"), "{msg}");
        assert_eq!(line, 1);
        let (msg, _) = parse_error("$Nodes\n0 0 0 0\n$EndNodes\n");
        assert!(msg.contains("must start with $MeshFormat"), "{msg}");
        let (msg, _) = parse_error("solid cube\nfacet normal 0 0 1\n");
        assert!(msg.contains("section header"), "{msg}");
    }

    #[test]
    fn section_errors_name_the_line() {
        // missing sections
        let cut = |a: &str, b: &str| {
            let i = FIXTURE.find(a).unwrap();
            let j = FIXTURE.find(b).unwrap() + b.len();
            format!("{}{}", &FIXTURE[..i], &FIXTURE[j..])
        };
        let (msg, _) = parse_error(&cut("$Nodes", "$EndElements\n"));
        assert!(msg.contains("no $Nodes section"), "{msg}");
        let (msg, _) = parse_error(&cut("$Elements", "$EndElements\n"));
        assert!(msg.contains("no $Elements section"), "{msg}");
        let (msg, _) = parse_error(&cut("$Nodes", "$EndNodes\n"));
        assert!(msg.contains("nodes must come first"), "{msg}");
        let text = FIXTURE.replace("$EndElements", "");
        let (msg, line) = parse_error(&text);
        assert!(msg.contains("$EndElements missing"), "{msg}");
        assert_eq!(line, line_of(FIXTURE, "$Elements"));
        // a bad number: its line
        let l = line_of(FIXTURE, "$Nodes") + 5; // header of the second node block
        let mut lines: Vec<String> = FIXTURE.lines().map(String::from).collect();
        lines[l - 1] = "0 zero 0".into();
        let (msg, line) = parse_error(&lines.join("\n"));
        assert_eq!(line, l, "{msg}");
        assert!(msg.contains("$Nodes") && msg.contains("\"zero\""), "{msg}");
        // an element on a node that does not exist
        let hexes = line_of(FIXTURE, "3 1 17 2");
        let mut lines: Vec<String> = FIXTURE.lines().map(String::from).collect();
        let mut f: Vec<String> = lines[hexes].split_whitespace().map(String::from).collect();
        f[3] = "999".into();
        lines[hexes] = f.join(" ");
        let (msg, line) = parse_error(&lines.join("\n"));
        assert_eq!(line, hexes + 1, "{msg}");
        assert!(msg.contains("node 999"), "{msg}");
        // counts that do not match
        let text = FIXTURE.replacen("41 55 1 55", "41 56 1 55", 1);
        let (msg, _) = parse_error(&text);
        assert!(msg.contains("56 nodes declared, 55 found"), "{msg}");
        let text = FIXTURE.replacen("$PhysicalNames\n6", "$PhysicalNames\n7", 1);
        let (msg, _) = parse_error(&text);
        assert!(msg.contains("7 names declared, 6 found"), "{msg}");
        let text = FIXTURE.replacen("1 5 \"EDGE\"", "1 5 EDGE", 1);
        let (msg, line) = parse_error(&text);
        assert!(msg.contains("dim tag"), "{msg}");
        assert_eq!(line, line_of(FIXTURE, "1 5 \"EDGE\""));
    }

    /// Mutated and truncated files never panic: they parse or give an error.
    #[test]
    fn fuzz_mutated_files_never_panic() {
        let base = FIXTURE.as_bytes();
        // every truncation at a line end
        let mut errors = 0;
        for (i, _) in FIXTURE.match_indices('\n') {
            if parse(&FIXTURE[..i]).is_err() {
                errors += 1;
            }
        }
        assert!(errors > 200);
        let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
        let alphabet = b"0123456789 -.e$\n\"+EndNodesElements17x";
        let (mut ok, mut err) = (0, 0);
        for _ in 0..4000 {
            let mut b = base.to_vec();
            for _ in 0..1 + rng.below(4) {
                match rng.below(6) {
                    0 => {
                        let i = rng.below(b.len());
                        b[i] = alphabet[rng.below(alphabet.len())];
                    }
                    1 => {
                        let i = rng.below(b.len());
                        let j = (i + rng.below(40)).min(b.len());
                        b.drain(i..j);
                    }
                    2 => {
                        let i = rng.below(b.len());
                        b.truncate(i);
                    }
                    3 => {
                        let i = rng.below(b.len());
                        b.insert(i, alphabet[rng.below(alphabet.len())]);
                    }
                    4 => {
                        let i = rng.below(b.len());
                        b[i] = (rng.next() & 0xff) as u8; // any byte, also invalid UTF-8
                    }
                    _ => {
                        // duplicate a chunk
                        let i = rng.below(b.len());
                        let j = (i + rng.below(200)).min(b.len());
                        let chunk = b[i..j].to_vec();
                        let k = rng.below(b.len());
                        b.splice(k..k, chunk);
                    }
                }
                if b.is_empty() {
                    break;
                }
            }
            match parse(&String::from_utf8_lossy(&b)) {
                Ok(m) => {
                    ok += 1;
                    assert!(m
                        .elements
                        .iter()
                        .all(|e| e.nodes.len() == e.kind.node_count()));
                }
                Err(e) => {
                    err += 1;
                    if let FlankError::Parse { line, .. } = e {
                        assert!(line >= 1);
                    }
                }
            }
        }
        println!("fuzz: {ok} parsed, {err} rejected");
        assert!(err > 1000);
    }
}
