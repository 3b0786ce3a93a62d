//! Static walls: closed-form shapes and triangle meshes (parry3d-f64).
//!
//! Each shape answers two questions about a sphere of radius `r`:
//! - [`Surface::gap`]: the signed gap between the sphere's surface and the wall, and the wall's
//!   unit normal towards the sphere's centre;
//! - [`Surface::sweep`]: where along a straight move `c0 → c1` the sphere first touches the
//!   wall while approaching it, and where it would leave it (the chord test used to detect a
//!   contact inside a step; [`crate::contact`] then locates it on the curved path).
//!
//! Planes, boxes and the inside of a cylinder are closed form: a faceted mesh of a cylinder
//! gives normals off by up to π/N. Meshes go through parry's `TriMesh` and `cast_shapes`.

mod annulus;
mod crease;
mod cuboid;
mod cylinder;
mod mesh;
mod plane;
mod solid;

pub use annulus::annulus_mesh;
pub use crease::{CREASE_TOUCHING, Crease, FLAT_CREASE, crease, onto_crease, out_of_crease};
pub use cuboid::Cuboid;
pub use cylinder::Cylinder;
pub use mesh::{MeshError, MeshWall, load_mesh};
pub use plane::Plane;
pub use solid::Solid;

use glam::DVec3;

/// A wall's material: elastic constants for the Hertz contact time of solid particles, and an
/// optional restitution in air that overrides the particle kind's.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WallMaterial {
    /// Young's modulus `Ew` (Pa); needed when the scene has solid particles.
    pub youngs_modulus: Option<f64>,
    /// Poisson ratio `νw`; needed when the scene has solid particles.
    pub poisson_ratio: Option<f64>,
    /// `ε_max` of impacts on this wall, overriding the particle kind's.
    pub restitution_max: Option<f64>,
    /// Surface roughness `h_r` of the wall (m) **[ext]**, added to the particle's with the
    /// `wall_lubrication` effect (docs/physics.md §8); 0 when not given.
    pub roughness: f64,
    /// The wall's friction keys **[ext]** (docs/physics.md §9).
    pub friction: crate::particles::FrictionMaterial,
}

/// A named static wall.
#[derive(Debug, Clone)]
pub struct Wall {
    /// Name used in events and summaries.
    pub name: String,
    /// Material of the wall.
    pub material: WallMaterial,
    /// Geometry.
    pub shape: Shape,
}

/// The gap between a sphere and a wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// Distance between the sphere's surface and the wall (m); negative when they overlap.
    pub gap: f64,
    /// Unit normal of the wall at the nearest point, pointing towards the sphere's centre.
    pub normal: DVec3,
}

/// The part of a straight move `λ ∈ [0, 1]` during which a sphere overlaps a wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// First touch, while approaching.
    pub enter: f64,
    /// Where the straight move would leave the wall again (1 if it does not within the move).
    pub exit: f64,
}

/// Closed-form or mesh geometry queries for a sphere of radius `r` (m).
pub trait Surface {
    /// Signed gap and normal for a sphere centred at `c`.
    fn gap(&self, c: DVec3, r: f64) -> Gap;
    /// First contact of a sphere moving straight from `c0` to `c1`, if it approaches the wall.
    fn sweep(&self, c0: DVec3, c1: DVec3, r: f64) -> Option<Crossing>;
    /// Broad phase: false only when the move `c0 → c1` certainly stays clear of the wall.
    fn may_touch(&self, c0: DVec3, c1: DVec3, r: f64) -> bool;
    /// Every part of the wall within `within` (m) of the sphere's surface, each with its
    /// [`Part`] number and its own gap: a sphere in a box corner touches two or three faces at
    /// once, and a contact solver needs each as a constraint. By default the wall is one part.
    fn touching(&self, c: DVec3, r: f64, within: f64, mut each: impl FnMut(Part, Gap))
    where
        Self: Sized,
    {
        let g = self.gap(c, r);
        if g.gap < within {
            each(0, g);
        }
    }
    /// The gap to one part (as numbered by [`Surface::touching`]). By default the wall is one
    /// part.
    fn part_gap(&self, _part: Part, c: DVec3, r: f64) -> Gap {
        self.gap(c, r)
    }
    /// The gap to the wall without the parts in `skip` (as numbered by [`Surface::touching`]):
    /// where the contact of a path is located, the parts it slides along or leaves at its start
    /// must not hide the part it approaches. `+∞` when nothing is left. By default the wall is
    /// one part, never skipped.
    fn gap_without(&self, c: DVec3, r: f64, _skip: &[Part]) -> Gap {
        self.gap(c, r)
    }
}

/// A part of a wall: a face of a box, a triangle of a mesh; 0 for a wall of one part.
pub type Part = u32;

/// What a picture of a wall needs: where a bounded shape is, and the solid that stands for it.
pub trait Drawable {
    /// The box `(min, max)` (m) that frames the shape in a picture, `None` when it does not
    /// frame the scene (a plane, a cylinder open at an end: they are drawn to the size of what
    /// else is there).
    fn bounds(&self) -> Option<(DVec3, DVec3)>;
    /// The solid that represents the shape in a picture centred at `center` with half-size
    /// `half` (m): an unbounded shape is cut to a patch there.
    fn solid(&self, center: DVec3, half: f64) -> Solid;
}

/// Lists the wall shapes once: the enum [`Shape`] and its dispatch of [`Surface`] and
/// [`Drawable`] to each shape's own file are generated from the list.
macro_rules! shapes {
    ($($(#[$doc:meta])* $variant:ident($ty:ty)),* $(,)?) => {
        /// The geometry of a wall.
        #[derive(Debug, Clone)]
        pub enum Shape {
            $($(#[$doc])* $variant($ty),)*
        }

        impl Surface for Shape {
            #[inline(always)]
            fn gap(&self, c: DVec3, r: f64) -> Gap {
                match self {
                    $(Shape::$variant(s) => s.gap(c, r),)*
                }
            }

            fn sweep(&self, c0: DVec3, c1: DVec3, r: f64) -> Option<Crossing> {
                match self {
                    $(Shape::$variant(s) => s.sweep(c0, c1, r),)*
                }
            }

            // Inlined into the particle pass: passing the two ends through memory to an
            // outlined call stalled on store forwarding and took half of a dilute step.
            #[inline(always)]
            fn may_touch(&self, c0: DVec3, c1: DVec3, r: f64) -> bool {
                match self {
                    $(Shape::$variant(s) => s.may_touch(c0, c1, r),)*
                }
            }

            fn touching(&self, c: DVec3, r: f64, within: f64, each: impl FnMut(Part, Gap)) {
                match self {
                    $(Shape::$variant(s) => s.touching(c, r, within, each),)*
                }
            }

            fn part_gap(&self, part: Part, c: DVec3, r: f64) -> Gap {
                match self {
                    $(Shape::$variant(s) => s.part_gap(part, c, r),)*
                }
            }

            fn gap_without(&self, c: DVec3, r: f64, skip: &[Part]) -> Gap {
                match self {
                    $(Shape::$variant(s) => s.gap_without(c, r, skip),)*
                }
            }
        }

        impl Drawable for Shape {
            fn bounds(&self) -> Option<(DVec3, DVec3)> {
                match self {
                    $(Shape::$variant(s) => s.bounds(),)*
                }
            }

            fn solid(&self, center: DVec3, half: f64) -> Solid {
                match self {
                    $(Shape::$variant(s) => s.solid(center, half),)*
                }
            }
        }
    };
}

shapes! {
    /// Infinite plane; particles on the side the normal points to.
    Plane(Plane),
    /// Axis-aligned box, particles inside or outside.
    Cuboid(Cuboid),
    /// Lateral surface of a cylinder, particles inside.
    Cylinder(Cylinder),
    /// Triangle mesh (either side); also the annulus baffles.
    Mesh(Box<MeshWall>),
}

/// Broad phase for shapes whose gap is smallest at an end of a straight move (half-spaces,
/// the inside of a box or a cylinder): the move may touch only if an end does.
pub(crate) fn ends_touch(s: &impl Surface, c0: DVec3, c1: DVec3, r: f64) -> bool {
    s.gap(c0, r).gap <= 0.0 || s.gap(c1, r).gap <= 0.0
}

/// Broad phase against a bounded shape: the swept sphere's box overlaps the shape's box.
pub(crate) fn boxes_overlap(c0: DVec3, c1: DVec3, r: f64, min: DVec3, max: DVec3) -> bool {
    let lo = c0.min(c1) - DVec3::splat(r);
    let hi = c0.max(c1) + DVec3::splat(r);
    lo.cmple(max).all() && hi.cmpge(min).all()
}

/// Crossing of a gap that varies linearly along the move, from `g0` to `g1` (a plane, a face).
pub(crate) fn linear_crossing(g0: f64, g1: f64) -> Option<Crossing> {
    if g1 >= g0 || g1 > 0.0 {
        // Receding, or still apart at the end of the move.
        return None;
    }
    let enter = if g0 <= 0.0 { 0.0 } else { g0 / (g0 - g1) };
    Some(Crossing { enter, exit: 1.0 })
}

/// First root along the move of a gap that is a convex function of `λ` (distance to a convex
/// body minus `r`): Newton's method from `λ = 0` never overshoots such a root, and a
/// non-negative slope before it means the move never reaches the body.
pub(crate) fn convex_crossing(gap: impl Fn(f64) -> Gap, dir: DVec3, tol: f64) -> Option<f64> {
    let mut lambda = 0.0;
    for _ in 0..100 {
        let g = gap(lambda);
        let slope = g.normal.dot(dir);
        if g.gap <= tol {
            return (slope < 0.0 || lambda > 0.0).then_some(lambda);
        }
        if slope >= 0.0 {
            return None;
        }
        lambda -= g.gap / slope;
        if lambda > 1.0 {
            return None;
        }
    }
    Some(lambda)
}

/// The part of `shape` that a sphere of radius `r` at `c`, moving at `v`, meets: among the
/// parts within `within` (m) of it ([`Surface::touching`]: the faces of a box corner, the
/// facets of a mesh crease), the one it approaches fastest; the nearest part when no other
/// approaches faster (beyond round-off: the same face found two ways differs in the last
/// bits). The nearest part alone is not enough: a sphere that reaches two faces of a box in
/// one step and has just rebounded from one is as near to both, and the face it still
/// approaches is the one that matters.
pub fn contact_part(shape: &impl Surface, c: DVec3, r: f64, v: DVec3, within: f64) -> Gap {
    let mut best = shape.gap(c, r);
    let mut best_approach = -v.dot(best.normal);
    let round_off = 1e-12 * v.length();
    shape.touching(c, r, within, |_, g| {
        let approach = -v.dot(g.normal);
        if approach > best_approach + round_off {
            (best, best_approach) = (g, approach);
        }
    });
    best
}

/// The parts of `shape` that a sphere of radius `r` moving from `c0` (at velocity `v0`) to `c1`
/// in a stretch of its path touches at its start (within `within`, m) and slides along: it
/// does not move into them at the start (beyond round-off, 1e-12 of its speed), nor end
/// inside them. Its gap to them stays zero, so locating its next contact must skip them
/// ([`Surface::gap_without`]), or they hide the part it does approach (a bead falling along a
/// box's side face onto the floor). A part the path ends inside is kept: a bead at rest on a
/// floor under gravity, or back after a weak rebound.
pub fn parts_slid_along(
    shape: &impl Surface,
    (c0, c1): (DVec3, DVec3),
    r: f64,
    v0: DVec3,
    within: f64,
) -> Vec<Part> {
    let round_off = 1e-12 * v0.length();
    let mut skip = Vec::new();
    shape.touching(c0, r, within, |part, g| {
        if v0.dot(g.normal) >= -round_off && shape.part_gap(part, c1, r).gap >= -within {
            skip.push(part);
        }
    });
    skip
}

/// Rounds of [`push_out`]. 3 settle a box corner (one face per round); a sphere touching many
/// features at once — sitting in a mesh ring's hole, on its whole rim — converges geometrically
/// towards the position clear of all of them, and needs more: after the third round it goes
/// on while the overlap exceeds round-off ([`PUSH_OUT_TOLERANCE`] of the radius), up to this.
const PUSH_OUT_ROUNDS: usize = 1024;
/// Overlap (fraction of the radius) left to round-off after three rounds of [`push_out`].
pub(crate) const PUSH_OUT_TOLERANCE: f64 = 1e-12;

/// Moves a sphere of radius `r` at `x` out of `shape` and removes its velocity into it. Repeated
/// because the gap names the nearest face only: in a box corner the sphere may overlap two or
/// three faces at once. Returns the corrected position and velocity and whether it overlapped.
pub fn push_out(shape: &impl Surface, mut x: DVec3, mut v: DVec3, r: f64) -> (DVec3, DVec3, bool) {
    let mut moved = false;
    for round in 0..PUSH_OUT_ROUNDS {
        let g = shape.gap(x, r);
        if g.gap >= 0.0 || (round >= 3 && g.gap >= -PUSH_OUT_TOLERANCE * r) {
            break;
        }
        moved = true;
        x -= g.gap * g.normal;
        v -= v.dot(g.normal).min(0.0) * g.normal;
    }
    (x, v, moved)
}
