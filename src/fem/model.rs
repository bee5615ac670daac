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

/// A body force per unit mass b(x) (mm/s²), CalculiX's `*DLOAD` types
/// GRAV and CENTRIF (ccx 2.20 manual, *DLOAD); the force per unit volume is
/// ρ b with the element material's density.
#[derive(Clone, Debug, PartialEq)]
pub enum BodyForce {
    /// GRAV: b = g n, the acceleration vector `g n` (n a unit vector).
    Gravity { acceleration: [f64; 3] },
    /// CENTRIF: b = ω² r⊥, r⊥ the distance vector of the *undeformed*
    /// position from the axis through `point` along the unit vector `axis`.
    /// Linear statics: no centrifugal stiffening (spin softening) enters the
    /// stiffness, as in ccx without NLGEOM.
    Centrifugal {
        omega_squared: f64,
        point: [f64; 3],
        axis: [f64; 3],
    },
}

impl BodyForce {
    /// b(x), force per unit mass at the point x.
    pub fn at(&self, x: [f64; 3]) -> [f64; 3] {
        match self {
            BodyForce::Gravity { acceleration } => *acceleration,
            BodyForce::Centrifugal {
                omega_squared,
                point,
                axis,
            } => {
                let d = [x[0] - point[0], x[1] - point[1], x[2] - point[2]];
                let s = d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
                [
                    omega_squared * (d[0] - s * axis[0]),
                    omega_squared * (d[1] - s * axis[1]),
                    omega_squared * (d[2] - s * axis[2]),
                ]
            }
        }
    }
}

/// A body force on one element (its material needs a density).
#[derive(Clone, Debug, PartialEq)]
pub struct BodyLoad {
    pub element: usize,
    pub force: BodyForce,
}

/// Nodal temperatures of a thermal load (CalculiX's `*INITIAL CONDITIONS,
/// TYPE=TEMPERATURE` for `initial` = T0 and the step's `*TEMPERATURE` for
/// `current` = T), one value per mesh node. Elements whose material has an
/// expansion coefficient α get the initial strain α (T − T0) I
/// ([`crate::fem::thermal`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Temperatures {
    pub initial: Vec<f64>,
    pub current: Vec<f64>,
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

/// One term c·u of a linear multi-point constraint: DOF `component` (0, 1, 2
/// for x, y, z) of mesh node `node` times `coefficient`.
#[derive(Clone, Debug, PartialEq)]
pub struct EquationTerm {
    pub node: usize,
    pub component: usize,
    pub coefficient: f64,
}

/// A linear multi-point constraint Σ cᵢ uᵢ = 0 (CalculiX `*EQUATION`, ccx
/// 2.20 manual: homogeneous, the first term's DOF is the dependent one and
/// is eliminated from the system). A term repeating a DOF adds its
/// coefficient, as in ccx. Resolved into the DOF map by
/// [`crate::fem::constraints::resolve_equations`].
#[derive(Clone, Debug, PartialEq)]
pub struct Equation {
    pub terms: Vec<EquationTerm>,
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
    /// Gravity and centrifugal body loads, per element.
    pub body_loads: Vec<BodyLoad>,
    /// Initial and current nodal temperatures (thermal strains), if any.
    pub temperatures: Option<Temperatures>,
    pub couplings: Vec<RigidCoupling>,
    /// Linear multi-point constraints (`*EQUATION`), in deck order.
    pub equations: Vec<Equation>,
    /// Contact surfaces, interactions and pairs (empty: no contact).
    pub contact: crate::fem::contact_definition::ContactDefinition,
}

impl Model {
    pub fn dof_count(&self) -> usize {
        3 * self.mesh.node_count()
    }
}
