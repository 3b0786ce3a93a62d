//! Whether a region has room for a particle clear of the walls: a random fill whose particles
//! cannot be placed, and an injector that can never place one, are told apart from a region
//! that is merely full, and the message blames the diameter or the region.
//!
//! The test is a fixed sample of the region — its centre, the centres of the container walls
//! (a tank, a column) brought into it, 512 seeded random points and a 9 × 9 × 9 grid (a disk: 9
//! rings of 32) — with the walls' own gap, as the injector and the random fill use at run time.
//! It can miss a pocket of room smaller than the sample's spacing; what it misses, the run-time
//! draws (100 per injected particle) almost always miss too.

use super::error::fmt::{num, vec3};
use crate::pipeline::inject::Region;
use crate::walls::{Shape, Surface, Wall};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// What a region holds for a particle of radius `r`.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Room {
    /// The particle fits at `at` (the first point of the sample where it does).
    Fits { at: DVec3 },
    /// Smaller particles fit, not this one: the most room found is at `at`, for a particle of
    /// diameter `largest`, and `walls` are those this one would overlap there.
    TooLarge { at: DVec3, largest: f64, walls: Vec<String> },
    /// Not even a point of the region is clear of the walls: `walls` are those its centre
    /// `at` lies inside or behind.
    Blocked { at: DVec3, walls: Vec<String> },
}

impl Room {
    /// "… the most room found, at [x, y, z], is for d = … m (wall "tank" in the way)", or
    /// "… its centre [x, y, z] is inside or behind wall "floor"".
    pub fn explain(&self) -> String {
        let names = |walls: &[String]| {
            let list: Vec<String> = walls.iter().map(|w| format!("\"{w}\"")).collect();
            let s = if walls.len() == 1 { "" } else { "s" };
            format!("wall{s} {}", list.join(", "))
        };
        match self {
            Room::Fits { at } => format!("one fits at {}", vec3(at.to_array())),
            Room::TooLarge { at, largest, walls } => format!(
                "the most room found, at {}, is for d = {} m ({} in the way)",
                vec3(at.to_array()),
                num(*largest),
                names(walls)
            ),
            Room::Blocked { at, walls } => {
                format!("its centre {} is inside or behind {}", vec3(at.to_array()), names(walls))
            }
        }
    }
}

/// Whether a particle of radius `r` fits somewhere among `points` clear of `walls` (gap ≥ 0,
/// as at run time); if not, why.
pub(super) fn probe(points: &[DVec3], r: f64, walls: &[Wall]) -> Room {
    if let Some(&at) = points.iter().find(|&&x| walls.iter().all(|w| w.shape.gap(x, r).gap >= 0.0)) {
        return Room::Fits { at };
    }
    // The clearance of a point: its distance to the nearest wall, negative inside one.
    let clearance = |x: DVec3| walls.iter().map(|w| w.shape.gap(x, 0.0).gap).fold(f64::INFINITY, f64::min);
    let (best, room) = points
        .iter()
        .map(|&x| (x, clearance(x)))
        .fold((points[0], f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
    let in_the_way = |x: DVec3, r: f64| -> Vec<String> {
        walls.iter().filter(|w| w.shape.gap(x, r).gap < 0.0).map(|w| w.name.clone()).collect()
    };
    if room >= 0.0 {
        Room::TooLarge { at: best, largest: 2.0 * room, walls: in_the_way(best, r) }
    } else {
        Room::Blocked { at: points[0], walls: in_the_way(points[0], 0.0) }
    }
}

/// The sample of an axis-aligned box `[lo, hi]`, its centre first.
pub(super) fn box_points(lo: DVec3, hi: DVec3, walls: &[Wall]) -> Vec<DVec3> {
    let centre = 0.5 * (lo + hi);
    let mut points = vec![centre];
    points.extend(container_centres(walls, centre).map(|c| c.clamp(lo, hi)));
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    points.extend((0..512).map(|_| lo + (hi - lo) * DVec3::new(rng.random(), rng.random(), rng.random())));
    const N: usize = 9;
    for i in 0..N * N * N {
        let f = DVec3::new((i % N) as f64, (i / N % N) as f64, (i / (N * N)) as f64) / (N - 1) as f64;
        points.push(lo + (hi - lo) * f);
    }
    points
}

/// The sample of an injector's region, its centre first.
pub(super) fn region_points(region: &Region, walls: &[Wall]) -> Vec<DVec3> {
    match *region {
        Region::Box { min, max } => box_points(min, max, walls),
        Region::Disk { center, normal, radius, e1, e2 } => {
            // A point of the disk: `x` moved into its plane and within its radius.
            let onto = |x: DVec3| {
                let d = x - center;
                let d = d - d.dot(normal) * normal;
                let l = d.length();
                if l > radius { center + d * (radius / l) } else { center + d }
            };
            let mut points = vec![center];
            points.extend(container_centres(walls, center).map(onto));
            let at = |rho: f64, theta: f64| center + rho * (theta.cos() * e1 + theta.sin() * e2);
            let mut rng = ChaCha8Rng::seed_from_u64(0);
            points.extend((0..512).map(|_| {
                at(radius * rng.random::<f64>().sqrt(), std::f64::consts::TAU * rng.random::<f64>())
            }));
            for ring in 1..=9 {
                for k in 0..32 {
                    points.push(at(radius * ring as f64 / 9.0, std::f64::consts::TAU * k as f64 / 32.0));
                }
            }
            points
        }
    }
}

/// The centres of the walls that hold particles inside them — a container box's centre, the
/// point of a column's axis nearest `near` — where a large particle has the most room.
fn container_centres(walls: &[Wall], near: DVec3) -> impl Iterator<Item = DVec3> + '_ {
    walls.iter().filter_map(move |w| match &w.shape {
        Shape::Cuboid(b) if b.inside => Some(0.5 * (b.min + b.max)),
        Shape::Cylinder(c) => {
            let along = (near - c.base).dot(c.axis).clamp(c.lo, c.hi);
            Some(c.base + along * c.axis)
        }
        _ => None,
    })
}
