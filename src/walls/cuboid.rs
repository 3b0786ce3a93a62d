//! Axis-aligned box, with the particles inside (a container) or outside (an obstacle).

use super::{Crossing, Drawable, Gap, Part, Solid, Surface, boxes_overlap, convex_crossing, linear_crossing};
use glam::{DQuat, DVec3};

/// An axis-aligned box from `min` to `max` (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cuboid {
    /// Lower corner (m).
    pub min: DVec3,
    /// Upper corner (m).
    pub max: DVec3,
    /// True: particles are inside (six inward faces); false: the box is a solid obstacle.
    pub inside: bool,
}

const AXES: [DVec3; 3] = [DVec3::X, DVec3::Y, DVec3::Z];

impl Cuboid {
    /// The six inward faces as `(signed distance of c from the face, inward normal)`.
    fn inner_faces(&self, c: DVec3) -> [(f64, DVec3); 6] {
        let lo = c - self.min;
        let hi = self.max - c;
        [
            (lo.x, AXES[0]),
            (hi.x, -AXES[0]),
            (lo.y, AXES[1]),
            (hi.y, -AXES[1]),
            (lo.z, AXES[2]),
            (hi.z, -AXES[2]),
        ]
    }

    fn outer_gap(&self, c: DVec3, r: f64) -> Gap {
        let nearest = c.clamp(self.min, self.max);
        let d = c - nearest;
        let dist = d.length();
        if dist > 0.0 {
            return Gap { gap: dist - r, normal: d / dist };
        }
        // Centre inside the box: leave through the nearest face.
        let (depth, inward) = nearest_face(c - self.min, self.max - c);
        Gap { gap: -depth - r, normal: -inward }
    }
}

/// The inward normals of [`Cuboid::inner_faces`]' faces, in their order (`−X` as negated
/// there: its zeros are `−0`).
const FACE_NORMALS: [DVec3; 6] = [
    DVec3::X,
    DVec3::new(-1.0, -0.0, -0.0),
    DVec3::Y,
    DVec3::new(-0.0, -1.0, -0.0),
    DVec3::Z,
    DVec3::new(-0.0, -0.0, -1.0),
];

/// The face of least distance, the first of them on a tie: what `min_by` with `total_cmp` over
/// the six faces gave, written out on the distances alone (the lubricated flight asks for it
/// every step of every bead near a box's walls, and the iterator's closure was a call of its
/// own). A plain `<`: the two differ only on NaN, which leaves face 0 either way, and on `−0`
/// against `+0`, two faces at once at distance zero, which only a box of no width has.
#[inline(always)]
fn nearest_face(lo: DVec3, hi: DVec3) -> (f64, DVec3) {
    let dist = [lo.x, hi.x, lo.y, hi.y, lo.z, hi.z];
    let mut best = 0;
    for face in 1..6 {
        if dist[face] < dist[best] {
            best = face;
        }
    }
    (dist[best], FACE_NORMALS[best])
}

impl Surface for Cuboid {
    #[inline(always)]
    fn gap(&self, c: DVec3, r: f64) -> Gap {
        if !self.inside {
            return self.outer_gap(c, r);
        }
        let (dist, normal) = nearest_face(c - self.min, self.max - c);
        Gap { gap: dist - r, normal }
    }

    fn sweep(&self, c0: DVec3, c1: DVec3, r: f64) -> Option<Crossing> {
        if self.inside {
            // Six half-spaces: the first face reached.
            let (f0, f1) = (self.inner_faces(c0), self.inner_faces(c1));
            return f0
                .iter()
                .zip(&f1)
                .filter_map(|(a, b)| linear_crossing(a.0 - r, b.0 - r))
                .min_by(|a, b| a.enter.total_cmp(&b.enter));
        }
        let dir = c1 - c0;
        let tol = 1e-12 * r;
        let enter = convex_crossing(|l| self.outer_gap(c0 + l * dir, r), dir, tol)?;
        // The exit is the first root of the reversed move.
        let exit = convex_crossing(|l| self.outer_gap(c1 - l * dir, r), -dir, tol).map_or(1.0, |l| 1.0 - l);
        Some(Crossing { enter, exit: exit.max(enter) })
    }

    #[inline]
    fn may_touch(&self, c0: DVec3, c1: DVec3, r: f64) -> bool {
        if self.inside {
            // The inside of the box shrunk by r is convex: the move stays clear of the faces iff
            // both ends lie in it.
            // As the box spanned by the two ends (this runs for every particle at every step).
            let (lo, hi) = (c0.min(c1) - self.min, self.max - c0.max(c1));
            lo.min(hi).min_element() <= r
        } else {
            boxes_overlap(c0, c1, r, self.min, self.max)
        }
    }

    /// Inside: each face is a part (0–5: −x, +x, −y, +y, −z, +z). An obstacle is one convex
    /// part.
    fn touching(&self, c: DVec3, r: f64, within: f64, mut each: impl FnMut(Part, Gap)) {
        if !self.inside {
            let g = self.outer_gap(c, r);
            if g.gap < within {
                each(0, g);
            }
            return;
        }
        for (face, (dist, normal)) in self.inner_faces(c).into_iter().enumerate() {
            if dist - r < within {
                each(face as Part, Gap { gap: dist - r, normal });
            }
        }
    }

    fn part_gap(&self, part: Part, c: DVec3, r: f64) -> Gap {
        if !self.inside {
            return self.gap(c, r);
        }
        let (dist, normal) = self.inner_faces(c)[part as usize % 6];
        Gap { gap: dist - r, normal }
    }

    fn gap_without(&self, c: DVec3, r: f64, skip: &[Part]) -> Gap {
        if !self.inside || skip.is_empty() {
            return self.gap(c, r);
        }
        let faces =
            self.inner_faces(c).into_iter().enumerate().filter(|(face, _)| !skip.contains(&(*face as Part)));
        faces
            .map(|(_, (dist, normal))| Gap { gap: dist - r, normal })
            .min_by(|a, b| a.gap.total_cmp(&b.gap))
            .unwrap_or(Gap { gap: f64::INFINITY, normal: DVec3::Z })
    }
}

impl Drawable for Cuboid {
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        Some((self.min, self.max))
    }

    fn solid(&self, _center: DVec3, _half: f64) -> Solid {
        Solid::Cuboid {
            center: 0.5 * (self.min + self.max),
            size: self.max - self.min,
            rotation: DQuat::IDENTITY,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_sweeping_past_a_box_edge_touches_at_the_rounded_edge() {
        let b = Cuboid { min: DVec3::ZERO, max: DVec3::ONE, inside: false };
        // Moving along x, centre 0.1 above the top face: it first touches the edge x = 0, z = 1.
        let r = 0.2;
        let c0 = DVec3::new(-1.0, 0.5, 1.0 + 0.1);
        let c1 = DVec3::new(2.0, 0.5, 1.0 + 0.1);
        let hit = b.sweep(c0, c1, r).expect("hits");
        // Touch when the distance to the edge x = 0, z = 1 is r: dx² + 0.1² = 0.04.
        let x = -(0.04f64 - 0.01).sqrt();
        let expected = (x - c0.x) / 3.0;
        assert!((hit.enter - expected).abs() < 1e-9, "{} vs {expected}", hit.enter);
        assert!(hit.exit > 0.5);
    }

    #[test]
    fn particle_inside_box_touches_the_nearest_face_first() {
        let b = Cuboid { min: DVec3::ZERO, max: DVec3::ONE, inside: true };
        let hit = b.sweep(DVec3::splat(0.5), DVec3::new(0.5, 0.5, -0.5), 0.1).unwrap();
        assert!((hit.enter - 0.4).abs() < 1e-12);
    }

    #[test]
    fn nearest_face_is_the_first_least_of_the_six_faces_to_the_bit() {
        let b = Cuboid { min: DVec3::new(-1.0, 0.0, 2.0), max: DVec3::new(1.0, 3.0, 2.5), inside: true };
        let mut points =
            vec![DVec3::new(0.0, 1.5, 2.25), DVec3::new(-1.0, 0.0, 2.0), DVec3::new(0.5, 0.5, 2.25)];
        for i in 0..500 {
            let f = i as f64;
            points.push(DVec3::new(
                (f * 0.37).sin() * 1.2,
                1.5 + (f * 0.71).cos() * 1.7,
                2.25 + (f * 0.13).sin() * 0.3,
            ));
        }
        for c in points {
            let (dist, normal) = b.inner_faces(c).into_iter().min_by(|a, b| a.0.total_cmp(&b.0)).unwrap();
            let g = b.gap(c, 0.1);
            assert_eq!(g.gap.to_bits(), (dist - 0.1).to_bits(), "{c}");
            assert_eq!(g.normal.to_array().map(f64::to_bits), normal.to_array().map(f64::to_bits), "{c}");
        }
    }
}
