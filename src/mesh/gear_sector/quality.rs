//! Element quality figures of a sector mesh: scaled Jacobian over the
//! Gauss points and edge aspect ratio.

use crate::fem::element::{det3, jacobian, ReferenceElement};
use crate::fem::mesh::ElementKind;

/// Element quality figures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quality {
    /// min over elements of (min det J / max det J over the 27 Gauss points).
    pub min_scaled_jacobian: f64,
    /// max over elements of longest / shortest corner-to-corner edge.
    pub max_aspect_ratio: f64,
}

impl Quality {
    /// No element yet: the neutral values of [`Quality::add`].
    pub fn empty() -> Self {
        Quality {
            min_scaled_jacobian: f64::INFINITY,
            max_aspect_ratio: 0.0,
        }
    }

    /// Takes one element (`kind`, node coordinates) into the figures.
    pub fn add(&mut self, kind: ElementKind, x: &[[f64; 3]]) {
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for d in &ReferenceElement::get(kind).derivatives {
            let dj = det3(&jacobian(x, d));
            lo = lo.min(dj);
            hi = hi.max(dj);
        }
        self.min_scaled_jacobian = self.min_scaled_jacobian.min(lo / hi);
        let (mut emin, mut emax) = (f64::INFINITY, 0.0f64);
        for e in crate::fem::element::edges(kind) {
            let (p, q) = (x[e[0]], x[e[1]]);
            let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
            emin = emin.min(d);
            emax = emax.max(d);
        }
        self.max_aspect_ratio = self.max_aspect_ratio.max(emax / emin);
    }
}
