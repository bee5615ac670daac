//! A static linear-elastic problem: mesh, materials, constraints and loads.
//!
//! This is what a deck (`.inp`) or a scene describes and what
//! [`crate::fem::static_analysis`] solves. DOFs are numbered node-major:
//! dof = 3·node + component (0 = x, 1 = y, 2 = z).

use crate::fem::material::Material;
use crate::fem::mesh::Mesh;

/// Prescribed displacement of one DOF.
#[derive(Clone, Debug, PartialEq)]
pub struct Dirichlet {
    pub node: usize,
    /// 0, 1, 2 for x, y, z.
    pub component: usize,
    pub value: f64,
}

/// Concentrated force on one DOF (N).
#[derive(Clone, Debug, PartialEq)]
pub struct NodalForce {
    pub node: usize,
    pub component: usize,
    pub value: f64,
}

/// Uniform pressure on an element face (MPa); positive pushes into the element,
/// as CalculiX's `*DLOAD … Pn`.
#[derive(Clone, Debug, PartialEq)]
pub struct Pressure {
    pub element: usize,
    /// Face number 1..=6 (hex) or 1..=5 (wedge), CalculiX numbering.
    pub face: usize,
    pub value: f64,
}

/// Rigid hub coupling (like Abaqus `*COUPLING` + `*KINEMATIC`): every node of
/// `nodes` follows the rigid-body motion u = t + θ × (x − x_ref) of a reference
/// point. Each of the six reference DOFs (tx, ty, tz, rx, ry, rz) is either
/// free or fixed at zero; a load on a free DOF is a force or moment.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidCoupling {
    pub name: String,
    pub reference_point: [f64; 3],
    pub nodes: Vec<usize>,
    /// Which of (tx, ty, tz, rx, ry, rz) are free.
    pub free: [bool; 6],
    /// Force (N) / moment (N·mm) on each reference DOF (ignored if fixed).
    pub load: [f64; 6],
}

impl RigidCoupling {
    /// Hub that may only rotate about `axis` through `point`, loaded by `torque` (N·mm).
    /// The axis must be a coordinate axis (0 = x, 1 = y, 2 = z).
    pub fn rotation_about(
        name: &str,
        point: [f64; 3],
        axis: usize,
        nodes: Vec<usize>,
        torque: f64,
    ) -> Self {
        let mut free = [false; 6];
        free[3 + axis] = true;
        let mut load = [0.0; 6];
        load[3 + axis] = torque;
        RigidCoupling {
            name: name.to_string(),
            reference_point: point,
            nodes,
            free,
            load,
        }
    }
}

/// A complete linear static problem.
#[derive(Clone, Debug, Default)]
pub struct Model {
    pub mesh: Mesh,
    pub materials: Vec<Material>,
    /// Material index of every element.
    pub element_material: Vec<usize>,
    pub dirichlet: Vec<Dirichlet>,
    pub forces: Vec<NodalForce>,
    pub pressures: Vec<Pressure>,
    pub couplings: Vec<RigidCoupling>,
    /// Contact surfaces, interactions and pairs (empty: no contact).
    pub contact: crate::fem::contact_definition::ContactDefinition,
}

impl Model {
    pub fn dof_count(&self) -> usize {
        3 * self.mesh.node_count()
    }
}
