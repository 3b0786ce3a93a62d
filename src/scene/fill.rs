//! Initial particles: an explicit list, lattices and seeded random fills.

use super::error::fmt::{num, vec3};
use super::error::{Invalid, check};
use super::ranges::{DIAMETER, LENGTH, SPEED};
use super::room::{Room, box_points, probe};
use super::schema::{SceneFile, Vec3Spec};
use crate::contact::detect::PlacedSpheres;
use crate::particles::{ParticleKind, Particles};
use crate::walls::{Surface, Wall};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Most particles a scene may create, so that a typo in a spacing cannot exhaust memory.
const MAX_PARTICLES: usize = 50_000_000;

/// The largest fraction of a random fill's region its particles may take (with the particles
/// already there), checked before any is drawn. A random fill places spheres one at a time at
/// random and never moves them (random sequential addition), which jams near 38 % in a large
/// region; no random packing of equal spheres, even shaken and pressed, exceeds random close
/// packing, about 64 %. Above 64 % the request is impossible and refused at once; between the
/// two it fails, but fast ([`place_random`] stops when it can no longer finish).
const MAX_RANDOM_FILL_FRACTION: f64 = 0.64;

/// `particles[i].angular_velocity` **[ext]**: a finite ω whose surface speed `|ω| d/2` is a
/// speed of the scene's range, and only in a scene with rotation (the rotation effect or a
/// friction key). Without rotation the spin is neither integrated nor read by any contact, so
/// a value given would be silently unused: it is refused.
fn angular_velocity(key: &str, w: Vec3Spec, d: f64, rotation: bool) -> Result<DVec3, Invalid> {
    let omega = check::vector(key, w)?;
    if !rotation {
        return Err(Invalid::new(
            key,
            format!(
                "needs rotation (the `rotation` effect, or a friction key on a kind or a wall's \
                 material): without it a particle's spin is neither integrated nor used by its contacts, \
                 got {}",
                vec3(w.0)
            ),
        ));
    }
    let surface = check::length(omega) * 0.5 * d;
    SPEED.check_magnitude(
        key,
        surface,
        &format!("{} rad/s (surface speed |ω| d/2 = {} m/s)", vec3(w.0), num(surface)),
    )?;
    Ok(omega)
}

/// Particles per axis of a lattice from `lo` to `hi` at `spacing`: `floor((hi − lo)/a − ½) + 1`
/// centres per axis, none on an axis where that is negative or not a number.
pub(super) fn lattice_counts(lo: DVec3, hi: DVec3, spacing: f64) -> DVec3 {
    let n = ((hi - lo) / spacing - 0.5).floor() + 1.0;
    // NaN (a NaN bound or spacing) counts as 0: the loader refuses it with its own message.
    DVec3::new(n.x.max(0.0), n.y.max(0.0), n.z.max(0.0))
}

/// Where each group of initial particles came from: `(first index, scene key)`.
pub(super) type Origins = Vec<(usize, String)>;

/// Adds `particles`, then every `lattice`, then every `random_fill`, with ids 0, 1, 2, …
pub(super) fn add_particles(
    file: &SceneFile,
    kinds: &[ParticleKind],
    walls: &[Wall],
    rotation: bool,
    p: &mut Particles,
) -> Result<Origins, Invalid> {
    let mut origins = Origins::new();
    let kind_index = |key: String, name: &str| -> Result<u16, Invalid> {
        kinds.iter().position(|k| k.name == name).map(|i| i as u16).ok_or_else(|| {
            let names: Vec<&str> = kinds.iter().map(|k| k.name.as_str()).collect();
            Invalid::new(key, format!("unknown kind \"{name}\"; kinds are: {}", names.join(", ")))
        })
    };
    let push = |p: &mut Particles, kind: u16, d: f64, x: DVec3, v: DVec3| {
        let id = p.len() as u32;
        p.push(id, kind, d, x, v);
    };
    for (i, s) in file.particles.iter().enumerate() {
        let k = |f: &str| format!("particles[{i}].{f}");
        let kind = kind_index(k("kind"), &s.kind)?;
        let d = check::positive_in(&k("diameter"), s.diameter, &DIAMETER)?;
        let x = check::point(&k("position"), s.position)?;
        let v = check::magnitude_in(&k("velocity"), s.velocity, &SPEED)?;
        origins.push((p.len(), k("position")));
        let i = p.len();
        push(p, kind, d, x, v);
        if let Some(w) = s.angular_velocity {
            let w = angular_velocity(&k("angular_velocity"), w, d, rotation)?;
            p.omega.values_mut()[i] = w;
        }
    }
    for (i, s) in file.lattice.iter().enumerate() {
        let k = |f: &str| format!("lattice[{i}].{f}");
        let kind = kind_index(k("kind"), &s.kind)?;
        let d = check::positive_in(&k("diameter"), s.diameter, &DIAMETER)?;
        let (lo, hi) = region(&k("min"), &k("max"), s.min, s.max)?;
        let a = check::positive_in(&k("spacing"), s.spacing, &LENGTH)?;
        if a < d {
            return Err(Invalid::new(
                k("spacing"),
                format!("must be >= diameter {} so particles do not overlap, got {}", num(d), num(a)),
            ));
        }
        let v = check::magnitude_in(&k("velocity"), s.velocity, &SPEED)?;
        let n = lattice_counts(lo, hi, a);
        if n.x * n.y * n.z + p.len() as f64 > MAX_PARTICLES as f64 {
            return Err(Invalid::new(
                k("spacing"),
                format!("gives {:.3e} particles, more than {MAX_PARTICLES}", n.x * n.y * n.z),
            ));
        }
        origins.push((p.len(), format!("lattice[{i}]")));
        for iz in 0..n.z as usize {
            for iy in 0..n.y as usize {
                for ix in 0..n.x as usize {
                    let x = lo + a * (DVec3::new(ix as f64, iy as f64, iz as f64) + 0.5);
                    push(p, kind, d, x, v);
                }
            }
        }
    }
    // The particles set one by one and the lattices are checked against the walls before any
    // random fill places around them: a 10 m ball through a 0.1 m tank left no room for a fill,
    // which was blamed instead of the ball (issue 25, finding 14).
    if !file.random_fill.is_empty() {
        check_clear_of_walls(&origins, p, walls)?;
    }
    for (i, s) in file.random_fill.iter().enumerate() {
        let k = |f: &str| format!("random_fill[{i}].{f}");
        let kind = kind_index(k("kind"), &s.kind)?;
        let d = check::positive_in(&k("diameter"), s.diameter, &DIAMETER)?;
        let (lo, hi) = region(&k("min"), &k("max"), s.min, s.max)?;
        let v = check::magnitude_in(&k("velocity"), s.velocity, &SPEED)?;
        let seed = check::seed(&k("seed"), s.seed)?;
        if s.count as usize + p.len() > MAX_PARTICLES {
            return Err(Invalid::new(
                k("count"),
                format!("must leave the scene at most {MAX_PARTICLES} particles, got {}", s.count),
            ));
        }
        check_fill_volume((&k("count"), &k("min")), (p, &origins), (lo, hi), d, s.count)?;
        let r = 0.5 * d;
        let (lo, hi) = (lo + r, hi - r);
        if !lo.cmplt(hi).all() {
            return Err(Invalid::new(
                k("max"),
                format!("region is thinner than the diameter {} on some axis", num(d)),
            ));
        }
        origins.push((p.len(), format!("random_fill[{i}]")));
        place_random(p, walls, kind, d, (lo, hi), v, s.count as usize, seed).map(|_tests| ()).map_err(|placed| {
            if placed > 0 {
                return Invalid::new(
                    k("count"),
                    format!(
                        "could place only {placed} of {} non-overlapping particles in the region; enlarge it or \
                         lower the count",
                        s.count
                    ),
                );
            }
            // Not one placed: say whether, and where, a particle of this size fits at all.
            let room = probe(&box_points(lo, hi, walls), r, walls);
            let (field, what) = match room {
                Room::TooLarge { .. } => (
                    "diameter",
                    format!(
                        "a particle of d = {} m fits nowhere in the region clear of the walls: {}",
                        num(d),
                        room.explain()
                    ),
                ),
                Room::Blocked { .. } => (
                    "min",
                    format!(
                        "no point of the region (of the centres, [min + d/2, max - d/2]) is clear of the walls: {}",
                        room.explain()
                    ),
                ),
                Room::Fits { .. } => {
                    // Nothing placed (`placed` is 0): the walls leave room; the particles placed before this fill may take it.
                    // A point is offered only when it is clear of both (the hint named a point
                    // inside a ball placed before).
                    let before = 0..p.len();
                    let points = box_points(lo, hi, walls);
                    let clear_of_walls =
                        |x: &DVec3| walls.iter().all(|w| w.shape.gap(*x, r).gap >= 0.0);
                    let in_the_way = |x: DVec3| {
                        before.clone().find(|&j| (p.pos[j] - x).length() < 0.5 * p.diameter[j] + r)
                    };
                    match points.iter().filter(|x| clear_of_walls(x)).find(|&&x| in_the_way(x).is_none()) {
                        Some(&at) => (
                            "min",
                            format!(
                                "no particle placed in 1000 draws: the region has room for one only in a small \
                                 part of it; shrink it to where the particles fit: one fits at {}",
                                vec3(at.to_array())
                            ),
                        ),
                        None => {
                            let at = points.iter().copied().find(clear_of_walls).unwrap_or(points[0]);
                            let blame = in_the_way(at).map_or_else(
                                || "the particles placed before it".to_string(),
                                |j| {
                                    format!(
                                        "{} (d = {} m at {})",
                                        describe(&origins, j),
                                        num(p.diameter[j]),
                                        vec3(p.pos[j].to_array())
                                    )
                                },
                            );
                            (
                                "min",
                                format!(
                                    "the part of the region clear of the walls is taken by {blame}: move the \
                                     region or that particle"
                                ),
                            )
                        }
                    }
                }
            };
            Invalid::new(k(field), what)
        })?;
    }
    Ok(origins)
}

/// Refuses a particle placed by hand or by a lattice that starts inside a wall, naming the key
/// that placed it.
pub(super) fn check_clear_of_walls(origins: &Origins, p: &Particles, walls: &[Wall]) -> Result<(), Invalid> {
    for i in 0..p.len() {
        let r = 0.5 * p.diameter[i];
        for wall in walls {
            let g = wall.shape.gap(p.pos[i], r);
            if g.gap < -1e-9 * r {
                let x: DVec3 = p.pos[i];
                return Err(Invalid::new(
                    origin_key(origins, i),
                    format!(
                        "particle at {} (d = {} m) starts inside wall \"{}\": it overlaps by {:.3e} m",
                        vec3(x.to_array()),
                        num(p.diameter[i]),
                        wall.name,
                        -g.gap
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Refuses a random fill of `count` particles of diameter `d` that, with the particles already
/// centred in the region `[lo, hi]`, would take more than [`MAX_RANDOM_FILL_FRACTION`] of its
/// volume: impossible for random placement, and formerly minutes of futile draws.
/// When the particles placed before fill the region by themselves, the region is blamed
/// (`region_key`) with the largest of them named, not the count.
fn check_fill_volume(
    (key, region_key): (&str, &str),
    (p, origins): (&Particles, &Origins),
    (lo, hi): (DVec3, DVec3),
    d: f64,
    count: u32,
) -> Result<(), Invalid> {
    let sphere = |d: f64| std::f64::consts::FRAC_PI_6 * d * d * d;
    let region = (hi - lo).x * (hi - lo).y * (hi - lo).z;
    let asked = count as f64 * sphere(d) / region;
    let inside: Vec<usize> =
        (0..p.len()).filter(|&i| p.pos[i].cmpge(lo).all() && p.pos[i].cmple(hi).all()).collect();
    // A particle larger than the region takes at most all of it (a 0.1 m ball around a 2 cm
    // region was said to take 6160 % of it).
    let taken: f64 = inside.iter().map(|&i| sphere(p.diameter[i]).min(region)).sum::<f64>() / region;
    if asked + taken <= MAX_RANDOM_FILL_FRACTION {
        return Ok(());
    }
    if taken > MAX_RANDOM_FILL_FRACTION
        && let Some(&largest) = inside.iter().max_by(|&&a, &&b| p.diameter[a].total_cmp(&p.diameter[b]))
    {
        return Err(Invalid::new(
            region_key,
            format!(
                "the particles placed before this fill already take {:.0} % of its region (the largest, {}, \
                 d = {} m at {}): move the region or those particles",
                100.0 * taken.min(1.0),
                describe(origins, largest),
                num(p.diameter[largest]),
                vec3(p.pos[largest].to_array())
            ),
        ));
    }
    let earlier = if taken > 0.0 {
        format!(" (and the particles placed before it take {:.0} % more)", 100.0 * taken)
    } else {
        String::new()
    };
    Err(Invalid::new(
        key,
        format!(
            "{count} particles of d = {} m would take {:.0} % of the region's volume{earlier}; a random fill \
             cannot exceed about {:.0} % (random close packing; placing spheres one by one at random jams near \
             38 %): enlarge the region, or lower the count or the diameter",
            num(d),
            100.0 * asked,
            100.0 * MAX_RANDOM_FILL_FRACTION
        ),
    ))
}

fn region(kmin: &str, kmax: &str, min: Vec3Spec, max: Vec3Spec) -> Result<(DVec3, DVec3), Invalid> {
    let (lo, hi) = (check::point(kmin, min)?, check::point(kmax, max)?);
    if !lo.cmplt(hi).all() {
        return Err(Invalid::new(
            kmax,
            format!("must exceed min on every axis, got min {}, max {}", vec3(min.0), vec3(max.0)),
        ));
    }
    Ok((lo, hi))
}

/// Random non-overlapping centres in `[lo, hi]` (already shrunk by the radius), clear of the
/// walls and of the particles placed before. Rejection sampling, the particles placed before
/// binned by size ([`PlacedSpheres`]: a grid sized by the largest particle would make every
/// fine look at thousands of others once one large bead is in the scene). Returns the overlap
/// tests made (a measure of the work, for tests); `Err(placed)` when the region is too full:
/// after `1000 × count` draws in all, or as soon as it is clear that the fill cannot finish —
/// a fill asked for 50 % of its region used to draw its whole budget, 10⁸ draws for 10⁵ particles, before failing. Three early stops:
///
/// - no first particle in 1000 draws: no room for one;
/// - the chance that a draw lands clear only falls as the fill goes on, so the rate of the
///   last 64 placements bounds the rate to come: if even at that rate the particles left need
///   more than twice the draws left, stop;
/// - late in random sequential addition (the rate below 1 % of the first 64 placements'), the
///   room left falls as draws^(-1/3), so about `3 × rate × draws` more particles fit however
///   long one draws: stop when more than 1.5 times that are still wanted. (Measured on 10⁵
///   beads: a fill of 30 % of its region finishes with the wanted count 4 to 40 times below
///   that bound; one of 50 % stops after 10⁶ draws, with 2 to 3 times more wanted than fit.)
#[allow(clippy::too_many_arguments)]
fn place_random(
    p: &mut Particles,
    walls: &[Wall],
    kind: u16,
    d: f64,
    (lo, hi): (DVec3, DVec3),
    v: DVec3,
    count: usize,
    seed: u64,
) -> Result<u64, usize> {
    let mut placed_before = PlacedSpheres::new(p.diameter.iter().copied().fold(d, f64::min));
    for i in 0..p.len() {
        placed_before.insert(p.pos[i], 0.5 * p.diameter[i], i as u32);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut placed, mut attempts, mut tests) = (0, 0usize, 0u64);
    let budget = 1000 * count.max(1);
    // The draw counts at the last 64 placements, oldest first; the rate of the first 64.
    let mut recent: std::collections::VecDeque<usize> = std::collections::VecDeque::with_capacity(64);
    let mut first_rate: Option<f64> = None;
    while placed < count {
        attempts += 1;
        if attempts > budget || (placed == 0 && attempts > 1000) {
            return Err(placed);
        }
        if attempts.is_multiple_of(4096)
            && let Some(&oldest) = recent.front()
        {
            let rate = recent.len() as f64 / (attempts - oldest) as f64;
            let wanted = (count - placed) as f64;
            let out_of_draws = wanted / rate > 2.0 * (budget - attempts) as f64;
            let jammed = first_rate.is_some_and(|first| rate < 0.01 * first)
                && wanted > 1.5 * 3.0 * rate * attempts as f64;
            if out_of_draws || jammed {
                return Err(placed);
            }
        }
        let x = DVec3::new(
            rng.random_range(lo.x..=hi.x),
            rng.random_range(lo.y..=hi.y),
            rng.random_range(lo.z..=hi.z),
        );
        let clear_of_walls = walls.iter().all(|w| w.shape.gap(x, 0.5 * d).gap >= 0.0);
        let clear = clear_of_walls
            && placed_before.all_clear(x, 0.5 * d, |j| {
                tests += 1;
                let j = j as usize;
                (p.pos[j] - x).length() >= 0.5 * (p.diameter[j] + d)
            });
        if clear {
            let id = p.len() as u32;
            let i = p.push(id, kind, d, x, v);
            placed_before.insert(x, 0.5 * d, i as u32);
            placed += 1;
            if recent.len() == 64 {
                recent.pop_front();
            }
            recent.push_back(attempts);
            if placed == 64 {
                first_rate = Some(64.0 / attempts as f64);
            }
        }
    }
    Ok(tests)
}

/// The scene key that created particle `i` (`particles[2].position`, `lattice[0]`, …).
pub(super) fn origin_key(origins: &Origins, i: usize) -> String {
    origin(origins, i).map_or_else(|| "particles".into(), |(_, key)| key.to_string())
}

/// Particle `i` as messages name it: `particles[2]`, or `lattice[0] element 17` (its number
/// within its entry, from 0, in the order the entry creates them).
pub(super) fn describe(origins: &Origins, i: usize) -> String {
    match origin(origins, i) {
        Some((_, key)) if key.ends_with(".position") => key.trim_end_matches(".position").to_string(),
        Some((first, key)) => format!("{key} element {}", i - first),
        None => format!("particle {i}"),
    }
}

/// The group of initial particles particle `i` belongs to: its first index and scene key.
fn origin(origins: &Origins, i: usize) -> Option<(usize, &str)> {
    let group = origins.partition_point(|(first, _)| *first <= i);
    origins.get(group.wrapping_sub(1)).map(|(first, key)| (*first, key.as_str()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_fill_of_fines_around_one_large_bead_tests_each_fine_against_a_few_others() {
        // One 10 mm bead in the middle of a 20 mm cube, then 20,000 fines of 100 µm around it.
        let mut p = Particles::default();
        p.push(0, 0, 1e-2, DVec3::ZERO, DVec3::ZERO);
        let (d, count) = (1e-4, 20_000);
        let region = (DVec3::splat(-0.01 + 0.5 * d), DVec3::splat(0.01 - 0.5 * d));
        let tests = place_random(&mut p, &[], 0, d, region, DVec3::ZERO, count, 3).unwrap();
        assert_eq!(p.len(), count + 1);
        for i in 1..p.len() {
            assert!((p.pos[i] - p.pos[0]).length() >= 0.5 * (1e-2 + d), "fine {i} inside the large bead");
        }
        // About one test per draw against the large bead, and the rare fine nearby; with cells
        // sized by the large bead every fine was tested against the ~10⁴ fines placed near it.
        assert!(tests < 2 * count as u64, "{tests} overlap tests for {count} fines");
    }
}
