//! Meshes: nodes, quadratic solid elements, node and element sets.
//!
//! Node and element *labels* are the numbers of the deck (CalculiX/Abaqus);
//! everything inside flank works with dense *indices* `0..n`. Connectivity is
//! stored in CalculiX/Abaqus node order (see [`ElementKind`]).

pub mod gear_body;
pub mod gear_sector;
#[cfg(feature = "gmsh")]
pub mod gmsh;
pub mod hertz;
pub mod inp;
pub mod msh;
pub mod structured;

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
