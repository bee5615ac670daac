//! Edge-contact candidate lines of the hypoid LTCA (seed `000_…`, issue 19
//! point 2): where the point TCA with edges on found a tooth pair in edge
//! contact (the pinion's tip edge on the gear flank, or the gear's tip edge
//! on the pinion flank), the LTCA takes K candidate points **along that
//! edge**, so a pair keeps carrying load after its flank contact has run
//! off the active flank.
//!
//! * **Extent.** The contact patch at the edge is the one of seed 000's
//!   numerical search (steps 1–6, [`crate::tca::ellipse::searched_ellipse`]
//!   at the TCA's approach δ; the flanks end at their edges, so the patch
//!   is cut by the edge and its long axis runs along it). Its semi-major
//!   axis a is run out, as the flank axes of
//!   [`crate::tca::major_axis::major_axis_line`], to the separation
//!   `span_approach_mm`: half-length L = a √(δ_span/δ) measured as arc
//!   length along the edge (arc length per edge parameter at the contact,
//!   a first-order map over the few mm of L). Where the search finds no
//!   closed patch the whole edge is the candidate line (counted by the
//!   caller through `EdgeLine::whole_edge`).
//! * **Points.** K points at the centres of K equal segments of [−L, L]
//!   on the edge curve (u = u_tip(v) for a tip edge) of the edge member's
//!   tooth, placed by the pair's frames at the roll (gear unturned, as the
//!   flank axes); each is put on the mating flank by closest point
//!   (signed distance along its outward normal: the **initial separation
//!   w from the exact surfaces**, > 0 a gap). Points past the edge's ends
//!   or whose mating point leaves the mating active flank are left out.
//!   The contact normal is the mating flank's (the edge has none), turned
//!   to point from pinion to gear; moment arm r = (ω̂₁ × (x₁ − o₁))·n.
//! * **Compliance at an edge.** The edge point lies on the boundary of the
//!   edge member's tensor flank grid (the tip row of flank nodes). The
//!   line is given the tip-corner kind ([`LineKind::PinionTipCorner`],
//!   [`LineKind::GearTipCorner`]), which [`crate::ltca::model`] treats as
//!   a sharp edge, as the spur/helical tip corners: the edge member is
//!   loaded on the edge line itself (u = u_tip, the tip row of nodes, as
//!   FE contact's slave edge nodes carry it; until 2026-11-27 a cell of
//!   half-width κ h centred on the edge, whose outer half fell off the
//!   flank, which put the load ≈ κ h/3 below the edge); no half-space
//!   near field and no Hertz pressure (an edge has no radius; its
//!   pressure is singular in the elastic model and is left out of p_max).
//!   The mating member's cell is an ordinary flank cell.
//! * **Toe and heel edges** run across the face, but the LTCA's cells are
//!   laid out with the line along the face parameter v; toe/heel edge
//!   contacts are therefore not candidates ([`EdgeLine::Unsupported`]),
//!   reported by the caller. (Seed 000's tilted pair has a gear heel edge
//!   contact 53–64 µm off its TE envelope, beyond the candidate span.)

use crate::error::FlankError;
use crate::geometry::contact_curvature::FlankAtContact;
use crate::geometry::gear_pair::{Flank, GearPair, LineKind};
use crate::geometry::surface::ToothSurface;
use crate::geometry::tangency::{ContactSystem, Edge};
use crate::geometry::vec3::{add, cross, dot, norm, sub, unit, V3};
use crate::tca::ellipse::searched_ellipse;
use crate::tca::point_contact::PairContact;
use crate::tca::{ContactLine, ContactPoint};

/// Planes of the numerical ellipse search at an edge contact (over 180°;
/// the TCA's default, seed 000's section scan).
pub const EDGE_SEARCH_DIRECTIONS: usize = 18;

/// The candidate line of an edge contact, or why there is none.
#[derive(Clone, Debug)]
pub enum EdgeLine {
    /// The line; `whole_edge` when the search found no closed patch and
    /// the whole edge was taken.
    Line { line: ContactLine, whole_edge: bool },
    /// No point of the edge span lies on the mating active flank.
    Empty,
    /// A toe or heel edge (module docs).
    Unsupported(Edge),
}

/// The candidate line of pair contact `c` in edge contact at pinion roll
/// `roll` (rad), K = `k` points (module docs). `approach_mm` is the TCA's
/// δ, `span_approach_mm` the separation out to which the line runs.
/// Errors for a flank contact or bad sizes; `Ok(None)` for a pair outside
/// the sector.
pub fn edge_line(
    pair: &dyn GearPair,
    c: &PairContact,
    roll: f64,
    k: usize,
    approach_mm: f64,
    span_approach_mm: f64,
) -> Result<Option<EdgeLine>, FlankError> {
    let (edge_body, edge) = match c.system {
        ContactSystem::PinionEdge(e) => (0usize, e),
        ContactSystem::GearEdge(e) => (1usize, e),
        ContactSystem::Flank => {
            return Err(FlankError::Model(
                "edge line: the contact is a flank contact (use the major axis)".into(),
            ))
        }
    };
    if k == 0 || !(approach_mm > 0.0 && span_approach_mm > 0.0) {
        return Err(FlankError::Model(format!(
            "edge line: K = {k}, approach {approach_mm} mm, span approach {span_approach_mm} mm (K ≥ 1 and positive approaches are needed)"
        )));
    }
    let Some(teeth) = c.teeth else {
        return Ok(None);
    };
    if edge != Edge::Tip {
        return Ok(Some(EdgeLine::Unsupported(edge)));
    }
    let mate_body = 1 - edge_body;
    let flank = |b: usize, tooth: usize| -> Result<&dyn ToothSurface, FlankError> {
        pair.body(b).flank(Flank::Right, tooth).ok_or_else(|| {
            FlankError::Model(format!(
                "edge line: the {} sector has no tooth {tooth}",
                pair.body(b).name()
            ))
        })
    };
    let middle = pair.middle();
    let mids = [flank(0, middle)?, flank(1, pair.mate(middle))?];
    let es = flank(edge_body, teeth[edge_body])?;
    let ms = flank(mate_body, teeth[mate_body])?;
    // the patch at δ by seed 000's search, at the traced contact (middle
    // teeth in the contact's own placement)
    let uv = [c.pinion_uv, c.gear_uv];
    let at = |b: usize| FlankAtContact {
        surface: mids[b],
        frame: c.placement[b],
        uv: uv[b],
    };
    let (v0, v1) = es.v_range();
    let ellipse = c.searched_ellipse.unwrap_or_else(|| {
        let span = mids[0].v_range().1 - mids[0].v_range().0;
        searched_ellipse(
            &at(0),
            &at(1),
            c.point,
            c.normal,
            approach_mm,
            EDGE_SEARCH_DIRECTIONS,
            span,
        )
    });
    let frames = pair.frames(roll);
    let ef = &frames[edge_body];
    let mf = &frames[mate_body];
    // arc length per unit edge parameter at the contact (a difference
    // kept on the edge: a contact at an edge's end is one-sided)
    let t_c = uv[edge_body][1];
    let on_edge = |t: f64| ef.place(es.point(es.u_tip(t), t));
    let eta = 1e-4 * (v1 - v0);
    let chord = |t: f64| {
        let (a, b) = ((t - eta).max(v0), (t + eta).min(v1));
        (sub(on_edge(b), on_edge(a)), b - a)
    };
    let speed = {
        let (d, dt) = chord(t_c);
        norm(d) / dt
    };
    if !(speed > 0.0 && speed.is_finite()) {
        return Err(FlankError::Model(format!(
            "edge line: the {} tip edge has no length at v = {t_c}",
            pair.body(edge_body).name()
        )));
    }
    let (half, whole_edge) = match ellipse.semi_major_mm {
        Some(a) if a > 0.0 => (a * (span_approach_mm / approach_mm).sqrt(), false),
        _ => (
            0.5 * (v1 - v0) * speed + (t_c - 0.5 * (v0 + v1)).abs() * speed,
            true,
        ),
    };
    let width = 2.0 * half / k as f64;
    let axis = frames[0].rotate(pair.rotation_axes()[0]);
    let origin = frames[0].translation;
    let mut points = Vec::with_capacity(k);
    let mut warm = uv[mate_body];
    let mut warm_centre = warm;
    // march outward from the contact both ways (warm starts from neighbours)
    let centre = k / 2;
    let order: Vec<usize> = (centre..k).chain((0..centre).rev()).collect();
    let mut found: Vec<Option<ContactPoint>> = vec![None; k];
    for &i in &order {
        if i + 1 == centre {
            warm = warm_centre;
        }
        let s = -half + (2 * i + 1) as f64 * half / k as f64;
        let t = t_c + s / speed;
        if !(t > v0 && t < v1) {
            continue;
        }
        let e_uv = [es.u_tip(t), t];
        let x_e = ef.place(es.point(e_uv[0], e_uv[1]));
        let own = mf.rotate_back(sub(x_e, mf.translation));
        let (mu, mv, w) = ms.closest_point_from(own, warm[0], warm[1]);
        if !(mu.is_finite() && mv.is_finite() && w.is_finite() && inside(ms, [mu, mv])) {
            continue;
        }
        warm = [mu, mv];
        if i == centre {
            warm_centre = warm;
        }
        let x_m = mf.place(ms.point(mu, mv));
        let n_mate = mf.rotate(ms.normal(mu, mv));
        // pinion → gear: the pinion's outward normal, or minus the gear's
        let n: V3 = if edge_body == 0 {
            [-n_mate[0], -n_mate[1], -n_mate[2]]
        } else {
            n_mate
        };
        let (xp, pinion_uv, gear_uv) = if edge_body == 0 {
            (x_e, e_uv, [mu, mv])
        } else {
            (x_m, [mu, mv], e_uv)
        };
        let tangent = {
            let ts = add(c.sliding_direction, -dot(c.sliding_direction, n), n);
            if norm(ts) > 1e-12 {
                unit(ts)
            } else {
                let d = chord(t).0;
                unit(add(d, -dot(d, n), n))
            }
        };
        found[i] = Some(ContactPoint {
            pinion_uv,
            gear_uv,
            position: [
                0.5 * (x_e[0] + x_m[0]),
                0.5 * (x_e[1] + x_m[1]),
                0.5 * (x_e[2] + x_m[2]),
            ],
            normal: n,
            separation_mm: w,
            moment_arm_mm: dot(cross(axis, sub(xp, origin)), n),
            width_mm: width,
            across_mm: 0.0,
            tangent,
            sliding_velocity: c.sliding_velocity,
            rolling_velocity: c.rolling_velocity,
            sum_velocity: 2.0 * c.rolling_velocity,
            // a sharp edge: no radius across the line
            curvature_radius: if edge_body == 0 {
                [0.0, f64::INFINITY]
            } else {
                [f64::INFINITY, 0.0]
            },
            equivalent_radius_mm: 0.0,
        });
    }
    points.extend(found.into_iter().flatten());
    if points.is_empty() {
        return Ok(Some(EdgeLine::Empty));
    }
    // pinion face parameter per mm along the line (the cells' v extent)
    let pv = points
        .iter()
        .fold([f64::INFINITY, f64::NEG_INFINITY], |e, q| {
            [e[0].min(q.pinion_uv[1]), e[1].max(q.pinion_uv[1])]
        });
    let length = width * points.len() as f64;
    let param_per_mm = if pv[1] > pv[0] && points.len() > 1 {
        (pv[1] - pv[0]) / (length - width)
    } else {
        // one point: the edge member's own v per mm along its edge (for a
        // gear edge an approximation of the pinion's: both are cone
        // distances)
        1.0 / speed
    };
    Ok(Some(EdgeLine::Line {
        line: ContactLine {
            pinion_tooth: teeth[0],
            gear_tooth: teeth[1],
            kind: if edge_body == 0 {
                LineKind::PinionTipCorner
            } else {
                LineKind::GearTipCorner
            },
            length_mm: length,
            param_per_mm,
            points,
        },
        whole_edge,
    }))
}

/// (u, v) strictly inside the active flank (form line to tip, toe to
/// heel), 1e-9 from its edges: a closest point clamped to an edge is out.
fn inside(s: &dyn ToothSurface, [u, v]: [f64; 2]) -> bool {
    let (v0, v1) = s.v_range();
    let e = 1e-9;
    v > v0 + e && v < v1 - e && u < s.u_tip(v) - e && u > s.u_form(v) + e
}
