//! Creases of separate walls: a particle resting on one wall that also touches others (a bead
//! in the corner of a column and a conical baffle, between two planes in a V). The geometry
//! here; the sliding along a crease is the flight kernel's ([`crate::flight`]).

use super::{PUSH_OUT_TOLERANCE, Surface, Wall, push_out};
use glam::DVec3;

/// Gap (fraction of the radius) within which a particle resting on one wall counts as resting
/// against another too: the in-step contact location puts a particle on a wall to 1e-13 of its
/// radius, so a particle that slid into a second wall touches both far within this.
pub const CREASE_TOUCHING: f64 = 1e-9;

/// Below this `|n₁ × n₂|` two touching walls are taken as one plane (a crease flatter than
/// 0.06°, or two walls facing each other): the particle slides on its own wall and is only
/// kept out of the other, as a crease line of such walls is not well defined.
pub const FLAT_CREASE: f64 = 1e-3;

/// The other walls a particle resting on wall `own` touches (at most [`Crease::MAX`]; a third
/// or more is counted in [`Crease::more`]): each wall's index and its normal at the particle.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Crease {
    len: usize,
    walls: [u32; Crease::MAX],
    normals: [DVec3; Crease::MAX],
    /// Further walls touched beyond [`Crease::MAX`] (a particle wedged among four walls).
    pub more: bool,
}

impl Crease {
    /// Walls kept besides the particle's own: two make a corner of three walls.
    pub const MAX: usize = 2;

    /// No other wall touched.
    pub fn is_empty(&self) -> bool {
        self.len == 0 && !self.more
    }

    /// The other walls touched, with their normals (towards the particle).
    pub fn iter(&self) -> impl Iterator<Item = (u32, DVec3)> + '_ {
        self.walls[..self.len].iter().copied().zip(self.normals[..self.len].iter().copied())
    }

    /// Whether wall `w` is one of them.
    pub fn contains(&self, w: u32) -> bool {
        self.walls[..self.len].contains(&w)
    }
}

/// The walls other than `own` that a sphere of radius `r` at `x` touches (gap at most
/// [`CREASE_TOUCHING`] `r`, or overlapping). Each closed-form broad-phase test comes first, so
/// a particle far from every other wall costs one cheap test per wall.
pub fn crease(walls: &[Wall], own: u32, x: DVec3, r: f64) -> Crease {
    let mut c = Crease::default();
    let reach = r * (1.0 + CREASE_TOUCHING);
    for (w, wall) in walls.iter().enumerate() {
        // `may_touch` is false only when the grown sphere is clear: then the gap is positive
        // beyond the tolerance.
        if w as u32 == own || !wall.shape.may_touch(x, x, reach) {
            continue;
        }
        let g = wall.shape.gap(x, r);
        if g.gap <= CREASE_TOUCHING * r {
            if c.len < Crease::MAX {
                (c.walls[c.len], c.normals[c.len]) = (w as u32, g.normal);
                c.len += 1;
            } else {
                c.more = true;
            }
        }
    }
    c
}

/// Puts a sphere of radius `r` at `x` on both `a` and `b` (gaps zero): Newton steps along the
/// two normals, exact in one for planes; a few for curved walls, whose gaps are smooth near a
/// crease. Returns the position and the unit direction of the crease line there.
pub fn onto_crease(a: &impl Surface, b: &impl Surface, mut x: DVec3, r: f64) -> (DVec3, DVec3) {
    for _ in 0..8 {
        let (ga, gb) = (a.gap(x, r), b.gap(x, r));
        let c = ga.normal.dot(gb.normal);
        let det = 1.0 - c * c;
        if det <= FLAT_CREASE * FLAT_CREASE || (ga.gap.abs() <= 1e-14 * r && gb.gap.abs() <= 1e-14 * r) {
            break;
        }
        let alpha = (ga.gap - c * gb.gap) / det;
        let beta = (gb.gap - c * ga.gap) / det;
        x -= alpha * ga.normal + beta * gb.normal;
    }
    let line = a.gap(x, r).normal.cross(b.gap(x, r).normal).normalize_or_zero();
    (x, line)
}

/// Moves a sphere of radius `r` at `x` out of its own wall `own` and the walls of `crease` at
/// once, and removes its velocity `v` into them. Pushed out of each wall in turn, a sphere in a
/// crease may be pushed back into the other (a faceted mesh's normal jumps too), and in a
/// narrow crease that alternation converges slowly: each round shrinks the overlap by the
/// square of the cosine between the normals, 0.88 per round in a 20° crease, which left a bead
/// 2.4e-7 r inside a mesh after 64 rounds. So once a round leaves it overlapping one wall while
/// touching another, it is put on the crease line of the two at once.
pub fn out_of_crease(
    walls: &[Wall],
    own: u32,
    crease: &Crease,
    mut x: DVec3,
    mut v: DVec3,
    r: f64,
) -> (DVec3, DVec3) {
    let shape = |w: u32| &walls[w as usize].shape;
    let mut all = [own; Crease::MAX + 1];
    all[1..=crease.len].copy_from_slice(&crease.walls[..crease.len]);
    let ids = all[..=crease.len].iter().copied();
    for _ in 0..64 {
        let mut moved = false;
        for w in ids.clone() {
            let m;
            (x, v, m) = push_out(shape(w), x, v, r);
            moved |= m;
        }
        if !moved {
            break;
        }
        let over = ids.clone().find(|&w| shape(w).gap(x, r).gap < -PUSH_OUT_TOLERANCE * r);
        let Some(a) = over else { break };
        let na = shape(a).gap(x, r).normal;
        let pair = ids.clone().filter(|&w| w != a).find(|&w| {
            let g = shape(w).gap(x, r);
            g.gap <= CREASE_TOUCHING * r && na.cross(g.normal).length() >= FLAT_CREASE
        });
        if let Some(b) = pair {
            let (on, _) = onto_crease(shape(a), shape(b), x, r);
            x = on;
            v = out_of_both(v, shape(a).gap(x, r).normal, shape(b).gap(x, r).normal);
        }
    }
    (x, v)
}

/// The velocity nearest `v` that goes into neither of two walls of normals `na` and `nb`: `v`
/// itself, `v` less its part into one of them, or its part along their crease line.
fn out_of_both(v: DVec3, na: DVec3, nb: DVec3) -> DVec3 {
    let round_off = 1e-12 * v.length();
    let clear = |u: DVec3| u.dot(na) >= -round_off && u.dot(nb) >= -round_off;
    if clear(v) {
        return v;
    }
    let t = na.cross(nb).normalize_or_zero();
    [v - v.dot(na).min(0.0) * na, v - v.dot(nb).min(0.0) * nb, v.dot(t) * t]
        .into_iter()
        .filter(|&u| clear(u))
        .min_by(|p, q| (*p - v).length_squared().total_cmp(&(*q - v).length_squared()))
        .unwrap_or(DVec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walls::{Plane, Shape, WallMaterial};

    fn plane(point: DVec3, normal: DVec3) -> Wall {
        Wall {
            name: "p".into(),
            material: WallMaterial::default(),
            shape: Shape::Plane(Plane { point, normal: normal.normalize() }),
        }
    }

    #[test]
    fn a_sphere_in_a_vee_touches_the_other_plane_and_is_put_on_both() {
        let walls =
            [plane(DVec3::ZERO, DVec3::new(1.0, 0.0, 1.0)), plane(DVec3::ZERO, DVec3::new(-1.0, 0.0, 1.0))];
        let r = 1e-3;
        let x = DVec3::new(0.0, 0.3, r * 2f64.sqrt());
        let c = crease(&walls, 0, x, r);
        assert_eq!(c.iter().map(|(w, _)| w).collect::<Vec<_>>(), vec![1]);
        // Lifted off b by 1.4e-6 m (1.4e-3 r): no longer touching it.
        assert!(crease(&walls, 0, x + DVec3::new(-1e-6, 0.0, 1e-6), r).is_empty());
        let (on, line) = onto_crease(&walls[0].shape, &walls[1].shape, x + DVec3::new(3e-5, 0.0, -2e-5), r);
        assert!(walls.iter().all(|w| w.shape.gap(on, r).gap.abs() < 1e-15), "{on:?}");
        assert!((line.cross(DVec3::Y)).length() < 1e-12, "{line:?}");
    }

    #[test]
    fn a_sphere_inside_both_walls_of_a_narrow_crease_comes_out_of_both_at_once() {
        // 20° between the walls: pushed out of each in turn, 64 rounds left 3.5e-4 of the overlap.
        let half = 10f64.to_radians();
        let (na, nb) = (DVec3::new(half.cos(), 0.0, half.sin()), DVec3::new(-half.cos(), 0.0, half.sin()));
        let walls = [plane(DVec3::ZERO, na), plane(DVec3::ZERO, nb)];
        let r = 1e-3;
        let on_both = DVec3::new(0.0, 0.0, r / half.sin());
        let c = crease(&walls, 0, on_both, r);
        let (x, v) = out_of_crease(
            &walls,
            0,
            &c,
            on_both - DVec3::new(1e-4, 0.0, 1e-4),
            DVec3::new(0.3, 0.2, -1.0),
            r,
        );
        assert!(walls.iter().all(|w| w.shape.gap(x, r).gap >= -1e-12 * r), "{x:?}");
        // Into both walls: only its part along the crease line is left.
        assert!((v - DVec3::new(0.0, 0.2, 0.0)).length() < 1e-12, "{v:?}");
    }
}
