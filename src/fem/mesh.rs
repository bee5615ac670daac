//! Meshes: nodes, quadratic solid elements, node and element sets.
//!
//! Node and element *labels* are the numbers of the deck (CalculiX/Abaqus);
//! everything inside flank works with dense *indices* `0..n`. Connectivity is
//! stored in CalculiX/Abaqus node order (see [`ElementKind`]).

use std::collections::{BTreeMap, HashMap};

/// Supported solid element types, named as in CalculiX/Abaqus.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ElementKind {
    /// 20-node serendipity hexahedron, 3×3×3 Gauss points.
    C3D20,
    /// 20-node hexahedron, reduced 2×2×2 integration.
    C3D20R,
    /// 15-node wedge, 9 points (3-point triangle × 3-point Gauss).
    C3D15,
}

impl ElementKind {
    /// Number of nodes of the element.
    pub fn node_count(self) -> usize {
        match self {
            ElementKind::C3D20 | ElementKind::C3D20R => 20,
            ElementKind::C3D15 => 15,
        }
    }

    /// Number of faces (6 for hexahedra, 5 for wedges).
    pub fn face_count(self) -> usize {
        match self {
            ElementKind::C3D20 | ElementKind::C3D20R => 6,
            ElementKind::C3D15 => 5,
        }
    }

    /// Parses a CalculiX/Abaqus TYPE name (case-insensitive).
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim().to_ascii_uppercase().as_str() {
            "C3D20" => Some(ElementKind::C3D20),
            "C3D20R" => Some(ElementKind::C3D20R),
            "C3D15" => Some(ElementKind::C3D15),
            _ => None,
        }
    }

    /// The CalculiX/Abaqus TYPE name.
    pub fn name(self) -> &'static str {
        match self {
            ElementKind::C3D20 => "C3D20",
            ElementKind::C3D20R => "C3D20R",
            ElementKind::C3D15 => "C3D15",
        }
    }
}

/// Which kind of set [`Mesh::append`] asks a new name for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetKind {
    Node,
    Element,
}

/// A label [`Mesh::append`] could not add because, shifted by its offset,
/// it is already taken; given as in the appended mesh (before the offset).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LabelClash {
    Node(u64),
    Element(u64),
}

impl std::fmt::Display for LabelClash {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LabelClash::Node(label) => write!(f, "duplicate node label {label}"),
            LabelClash::Element(label) => write!(f, "duplicate element label {label}"),
        }
    }
}

impl std::error::Error for LabelClash {}

/// One element: its kind, its deck label and its node indices (CalculiX order).
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    pub kind: ElementKind,
    pub label: u64,
    pub nodes: Vec<usize>,
}

/// An unstructured mesh of quadratic solid elements.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Node coordinates (mm), by node index.
    pub coords: Vec<[f64; 3]>,
    /// Deck label of each node index.
    pub node_labels: Vec<u64>,
    pub elements: Vec<Element>,
    /// Named node sets (upper-case names), as sorted, unique node indices.
    pub node_sets: BTreeMap<String, Vec<usize>>,
    /// Named element sets (upper-case names), as sorted, unique element indices.
    pub element_sets: BTreeMap<String, Vec<usize>>,
    node_index: HashMap<u64, usize>,
    element_index: HashMap<u64, usize>,
}

impl Mesh {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a node; returns its index, or `Err(existing index)` if the label exists.
    pub fn add_node(&mut self, label: u64, x: [f64; 3]) -> Result<usize, usize> {
        if let Some(&i) = self.node_index.get(&label) {
            return Err(i);
        }
        let i = self.coords.len();
        self.coords.push(x);
        self.node_labels.push(label);
        self.node_index.insert(label, i);
        Ok(i)
    }

    /// Adds an element whose nodes are given as indices; returns its index, or
    /// `Err(existing index)` if the label exists.
    pub fn add_element(
        &mut self,
        label: u64,
        kind: ElementKind,
        nodes: Vec<usize>,
    ) -> Result<usize, usize> {
        if let Some(&i) = self.element_index.get(&label) {
            return Err(i);
        }
        debug_assert_eq!(nodes.len(), kind.node_count());
        let i = self.elements.len();
        self.elements.push(Element { kind, label, nodes });
        self.element_index.insert(label, i);
        Ok(i)
    }

    /// Index of the node with deck label `label`.
    pub fn node(&self, label: u64) -> Option<usize> {
        self.node_index.get(&label).copied()
    }

    /// Index of the element with deck label `label`.
    pub fn element(&self, label: u64) -> Option<usize> {
        self.element_index.get(&label).copied()
    }

    pub fn node_count(&self) -> usize {
        self.coords.len()
    }

    /// Adds indices to a node set (created if absent); keeps it sorted and unique.
    pub fn extend_node_set(&mut self, name: &str, nodes: impl IntoIterator<Item = usize>) {
        let set = self.node_sets.entry(name.to_ascii_uppercase()).or_default();
        set.extend(nodes);
        set.sort_unstable();
        set.dedup();
    }

    /// Adds indices to an element set (created if absent); keeps it sorted and unique.
    pub fn extend_element_set(&mut self, name: &str, elements: impl IntoIterator<Item = usize>) {
        let set = self
            .element_sets
            .entry(name.to_ascii_uppercase())
            .or_default();
        set.extend(elements);
        set.sort_unstable();
        set.dedup();
    }

    /// Node coordinates of element `e` in element order.
    pub fn element_coords(&self, e: usize) -> Vec<[f64; 3]> {
        self.elements[e]
            .nodes
            .iter()
            .map(|&n| self.coords[n])
            .collect()
    }

    /// Appends a copy of `other` (e.g. a second body): its node and element
    /// labels shifted by `node_label_offset` and `element_label_offset`, its
    /// connectivity and sets shifted to their new indices. Each node or
    /// element set of `other` is merged into the set named `set_name(kind,
    /// name)` (created if absent, upper-cased like every set name), or left
    /// out where that is `None`.
    ///
    /// Returns `(node_base, element_base)`: node `i` of `other` is node
    /// `node_base + i` here, element `e` is `element_base + e`. A shifted
    /// label that is already taken is an error naming the label as in
    /// `other`; `self` then keeps what was appended before it.
    pub fn append(
        &mut self,
        other: &Mesh,
        node_label_offset: u64,
        element_label_offset: u64,
        mut set_name: impl FnMut(SetKind, &str) -> Option<String>,
    ) -> Result<(usize, usize), LabelClash> {
        let node_base = self.node_count();
        let element_base = self.elements.len();
        for (&label, &x) in other.node_labels.iter().zip(&other.coords) {
            self.add_node(label + node_label_offset, x)
                .map_err(|_| LabelClash::Node(label))?;
        }
        for el in &other.elements {
            let nodes = el.nodes.iter().map(|&n| n + node_base).collect();
            self.add_element(el.label + element_label_offset, el.kind, nodes)
                .map_err(|_| LabelClash::Element(el.label))?;
        }
        for (name, nodes) in &other.node_sets {
            if let Some(name) = set_name(SetKind::Node, name) {
                self.extend_node_set(&name, nodes.iter().map(|&n| n + node_base));
            }
        }
        for (name, elements) in &other.element_sets {
            if let Some(name) = set_name(SetKind::Element, name) {
                self.extend_element_set(&name, elements.iter().map(|&e| e + element_base));
            }
        }
        Ok((node_base, element_base))
    }

    /// Marks which nodes belong to at least one element.
    pub fn used_nodes(&self) -> Vec<bool> {
        let mut used = vec![false; self.coords.len()];
        for el in &self.elements {
            for &n in &el.nodes {
                used[n] = true;
            }
        }
        used
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::{box_mesh, BoxElement};

    #[test]
    fn append_offsets_labels_and_shifts_indices_and_sets() {
        let a = box_mesh([1.0, 1.0, 1.0], [1, 1, 1], BoxElement::Hex20);
        let mut b = box_mesh([2.0, 1.0, 1.0], [2, 1, 1], BoxElement::Wedge15);
        for x in b.coords.iter_mut() {
            x[2] += 1.0;
        }
        let mut m = Mesh::new();
        let first = m.append(&a, 0, 0, |_, name| Some(format!("a_{name}")));
        assert_eq!(first, Ok((0, 0)));
        let (nb, eb) = m
            .append(&b, 100, 1000, |kind, name| {
                (kind == SetKind::Node && name != "NALL").then(|| format!("b_{name}"))
            })
            .unwrap();
        assert_eq!((nb, eb), (a.node_count(), a.elements.len()));
        assert_eq!(m.node_count(), a.node_count() + b.node_count());
        assert_eq!(m.elements.len(), a.elements.len() + b.elements.len());
        // the first mesh as it was
        assert_eq!(&m.node_labels[..nb], &a.node_labels[..]);
        assert_eq!(&m.elements[..eb], &a.elements[..]);
        // labels offset, coordinates copied, connectivity shifted
        for i in 0..b.node_count() {
            assert_eq!(m.node_labels[nb + i], b.node_labels[i] + 100);
            assert_eq!(m.coords[nb + i], b.coords[i]);
            assert_eq!(m.node(b.node_labels[i] + 100), Some(nb + i));
        }
        for (k, el) in b.elements.iter().enumerate() {
            let e = &m.elements[eb + k];
            assert_eq!((e.label, e.kind), (el.label + 1000, el.kind));
            let shifted: Vec<usize> = el.nodes.iter().map(|&n| n + nb).collect();
            assert_eq!(e.nodes, shifted);
            assert_eq!(m.element(el.label + 1000), Some(eb + k));
        }
        // sets renamed (upper case) and shifted, left out where None
        assert_eq!(m.node_sets["A_Z1"], a.node_sets["Z1"]);
        assert_eq!(m.element_sets["A_EALL"], a.element_sets["EALL"]);
        let z1: Vec<usize> = b.node_sets["Z1"].iter().map(|&n| n + nb).collect();
        assert_eq!(m.node_sets["B_Z1"], z1);
        assert!(!m.node_sets.contains_key("B_NALL"));
        assert!(!m.element_sets.keys().any(|k| k.starts_with("B_")));
        // sets of the same name merge
        let mut both = Mesh::new();
        both.append(&a, 0, 0, |_, n| Some(n.to_string())).unwrap();
        both.append(&b, 100, 100, |_, n| Some(n.to_string()))
            .unwrap();
        assert_eq!(
            both.node_sets["NALL"],
            (0..both.node_count()).collect::<Vec<_>>()
        );
        let eall: Vec<usize> = (0..both.elements.len()).collect();
        assert_eq!(both.element_sets["EALL"], eall);
        // a taken label: named as in the appended mesh
        let clash = m.append(&b, 100, 5000, |_, _| None);
        assert_eq!(clash, Err(LabelClash::Node(b.node_labels[0])));
        let mut c = Mesh::new();
        c.append(&a, 0, 0, |_, _| None).unwrap();
        let clash = c.append(&a, 1000, 0, |_, _| None);
        assert_eq!(clash, Err(LabelClash::Element(a.elements[0].label)));
        assert_eq!(
            clash.unwrap_err().to_string(),
            format!("duplicate element label {}", a.elements[0].label)
        );
    }
}
