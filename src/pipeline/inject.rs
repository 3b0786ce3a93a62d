//! Stage 7 (inflow): injectors add particles at a steady rate, in a region, with drawn sizes.
//!
//! Injection runs on one thread, in injector order, each injector with its own seeded ChaCha8
//! generator, so the particles it adds (and their ids) do not depend on the thread count.

use crate::contact::detect::PlacedSpheres;
use crate::particles::Particles;
use crate::walls::{Surface, Wall};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// Draws of a position (and size) tried for one particle before it is skipped: a region that
/// is this crowded would otherwise make the step's cost unbounded.
pub const MAX_ATTEMPTS: u32 = 100;

/// Draws of a truncated size distribution before the value is clamped to the range (the scene
/// checks that the range holds a fair part of the distribution, so this is never reached in
/// practice).
const MAX_SIZE_DRAWS: u32 = 10_000;

/// Where injected particles' centres are drawn, uniformly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Region {
    /// A flat disk of `radius` (m) centred on `center` (m), perpendicular to unit `normal`;
    /// `e1`, `e2` complete an orthonormal basis of its plane.
    Disk {
        /// Centre (m).
        center: DVec3,
        /// Unit normal.
        normal: DVec3,
        /// Radius (m).
        radius: f64,
        /// First in-plane unit vector.
        e1: DVec3,
        /// Second in-plane unit vector.
        e2: DVec3,
    },
    /// An axis-aligned box from `min` to `max` (m).
    Box {
        /// Lower corner (m).
        min: DVec3,
        /// Upper corner (m).
        max: DVec3,
    },
}

impl Region {
    /// A disk region (`normal` need not be unit).
    pub fn disk(center: DVec3, normal: DVec3, radius: f64) -> Self {
        let normal = normal.normalize();
        let e1 = normal.any_orthonormal_vector();
        Region::Disk { center, normal, radius, e1, e2: normal.cross(e1) }
    }

    fn sample(&self, rng: &mut ChaCha8Rng) -> DVec3 {
        match *self {
            Region::Disk { center, radius, e1, e2, .. } => {
                // sqrt: uniform per unit area, not per unit radius.
                let rho = radius * rng.random::<f64>().sqrt();
                let theta = std::f64::consts::TAU * rng.random::<f64>();
                center + rho * (theta.cos() * e1 + theta.sin() * e2)
            }
            Region::Box { min, max } => {
                min + (max - min) * DVec3::new(rng.random(), rng.random(), rng.random())
            }
        }
    }

    /// A box holding every point of the region (m).
    fn bounds(&self) -> (DVec3, DVec3) {
        match *self {
            Region::Disk { center, radius, .. } => {
                (center - DVec3::splat(radius), center + DVec3::splat(radius))
            }
            Region::Box { min, max } => (min, max),
        }
    }
}

/// The diameters of injected particles (m), truncated to `[min, max]` by redrawing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SizeDistribution {
    /// Every particle has this diameter.
    Fixed(f64),
    /// Uniform between `min` and `max`.
    Uniform {
        /// Smallest diameter (m).
        min: f64,
        /// Largest diameter (m).
        max: f64,
    },
    /// Normal with `mean` and standard deviation `std_dev` (m), truncated to `[min, max]`.
    Normal {
        /// Mean (m).
        mean: f64,
        /// Standard deviation (m).
        std_dev: f64,
        /// Smallest diameter (m).
        min: f64,
        /// Largest diameter (m).
        max: f64,
    },
    /// Log-normal: `d = median · exp(sigma · N(0, 1))`, truncated to `[min, max]`.
    LogNormal {
        /// Median diameter (m).
        median: f64,
        /// Standard deviation of `ln d` (dimensionless).
        sigma: f64,
        /// Smallest diameter (m).
        min: f64,
        /// Largest diameter (m).
        max: f64,
    },
}

impl SizeDistribution {
    /// The smallest and the largest diameter it can give (m).
    fn bounds(&self) -> (f64, f64) {
        match *self {
            SizeDistribution::Fixed(d) => (d, d),
            SizeDistribution::Uniform { min, max }
            | SizeDistribution::Normal { min, max, .. }
            | SizeDistribution::LogNormal { min, max, .. } => (min, max),
        }
    }

    /// The largest diameter it can give (m).
    pub fn max_diameter(&self) -> f64 {
        self.bounds().1
    }

    /// The smallest diameter it can give (m).
    pub fn min_diameter(&self) -> f64 {
        self.bounds().0
    }

    fn sample(&self, rng: &mut ChaCha8Rng) -> f64 {
        let truncated = |rng: &mut ChaCha8Rng, min: f64, max: f64, draw: &dyn Fn(f64) -> f64| {
            let mut d = f64::NAN;
            for _ in 0..MAX_SIZE_DRAWS {
                d = draw(StandardNormal.sample(rng));
                if (min..=max).contains(&d) {
                    return d;
                }
            }
            d.clamp(min, max)
        };
        match *self {
            SizeDistribution::Fixed(d) => d,
            SizeDistribution::Uniform { min, max } => min + (max - min) * rng.random::<f64>(),
            SizeDistribution::Normal { mean, std_dev, min, max } => {
                truncated(rng, min, max, &|z| mean + std_dev * z)
            }
            SizeDistribution::LogNormal { median, sigma, min, max } => {
                truncated(rng, min, max, &|z| median * (sigma * z).exp())
            }
        }
    }
}

/// A steady source of particles (scene `[[injectors]]`).
#[derive(Debug, Clone)]
pub struct Injector {
    /// Name in summaries (`injectors[0]` unless the scene names it).
    pub name: String,
    /// Particle kind index.
    pub kind: u16,
    /// Particles per second.
    pub rate: f64,
    /// Where the centres are drawn.
    pub region: Region,
    /// Diameters.
    pub diameter: SizeDistribution,
    /// Initial velocity (m/s).
    pub velocity: DVec3,
    /// First injection time (s).
    pub start: f64,
    /// No injection at or after this time (s); may be +∞.
    pub stop: f64,
    /// Seed of its random draws (positions and sizes).
    pub seed: u64,
}

/// What an injector has done so far, and its random generator (part of the world: it changes
/// as the simulation runs).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct InjectorState {
    /// Particles due so far (injected or skipped).
    pub due: u64,
    /// Particles injected so far.
    pub injected: u64,
    /// Particles skipped because no clear place was found in [`MAX_ATTEMPTS`] draws.
    pub skipped: u64,
    rng: ChaCha8Rng,
}

impl Injector {
    /// The state of this injector before it has injected anything: a generator seeded with
    /// its seed.
    pub fn start(&self) -> InjectorState {
        InjectorState { due: 0, injected: 0, skipped: 0, rng: ChaCha8Rng::seed_from_u64(self.seed) }
    }

    /// The box that holds every centre the injector may draw (m).
    pub fn region_bounds(&self) -> (DVec3, DVec3) {
        self.region.bounds()
    }

    /// Particles due by time `t`: the k-th (k = 0, 1, …) is due at `start + k/rate`, if that is
    /// before `stop`; it counts once `t` is past it.
    pub fn due_by(&self, t: f64) -> u64 {
        let t = t.min(self.stop);
        if t <= self.start { 0 } else { (self.rate * (t - self.start)).ceil() as u64 }
    }
}

/// Adds the particles due in the step `(t0, t1]`, placed at `t1` (born then), with new ids
/// from `next_id`. A particle overlapping a wall or another particle is redrawn (position and
/// size) up to [`MAX_ATTEMPTS`] times, then skipped and counted in `states`. Returns true
/// when particles were added (indices changed).
pub(crate) fn run(
    injectors: &[Injector],
    states: &mut [InjectorState],
    walls: &[Wall],
    p: &mut Particles,
    next_id: &mut u32,
    t1: f64,
) -> bool {
    let mut added = false;
    for (inj, state) in injectors.iter().zip(states.iter_mut()) {
        let target = inj.due_by(t1);
        if target <= state.due {
            continue;
        }
        // Only particles near the region can be in the way — each within its own radius plus
        // the largest new one of the region, not within the largest diameter of the scene —
        // gathered once per step, binned by size.
        let r_new = 0.5 * inj.diameter.max_diameter();
        let (lo, hi) = inj.region.bounds();
        let mut near: Vec<(DVec3, f64)> = (0..p.len())
            .filter(|&i| {
                let margin = DVec3::splat(r_new + 0.5 * p.diameter[i]);
                p.pos[i].cmpge(lo - margin).all() && p.pos[i].cmple(hi + margin).all()
            })
            .map(|i| (p.pos[i], 0.5 * p.diameter[i]))
            .collect();
        let smallest = near.iter().map(|&(_, r)| 2.0 * r).fold(inj.diameter.min_diameter(), f64::min);
        let mut placed_near = PlacedSpheres::new(smallest);
        for (k, &(y, ry)) in near.iter().enumerate() {
            placed_near.insert(y, ry, k as u32);
        }
        while state.due < target {
            state.due += 1;
            let placed = (0..MAX_ATTEMPTS).find_map(|_| {
                let d = inj.diameter.sample(&mut state.rng);
                let x = inj.region.sample(&mut state.rng);
                let r = 0.5 * d;
                let clear = walls.iter().all(|w| w.shape.gap(x, r).gap >= 0.0)
                    && placed_near.all_clear(x, r, |k| {
                        let (y, ry) = near[k as usize];
                        (y - x).length_squared() >= (r + ry) * (r + ry)
                    });
                clear.then_some((x, d))
            });
            let Some((x, d)) = placed else {
                state.skipped += 1;
                continue;
            };
            let i = p.push(*next_id, inj.kind, d, x, inj.velocity);
            p.born[i] = t1;
            *next_id += 1;
            placed_near.insert(x, 0.5 * d, near.len() as u32);
            near.push((x, 0.5 * d));
            state.injected += 1;
            added = true;
        }
    }
    added
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn due_counts_one_particle_per_period_from_start_until_stop() {
        let inj = Injector {
            name: "i".into(),
            kind: 0,
            rate: 10.0,
            region: Region::Box { min: DVec3::ZERO, max: DVec3::ONE },
            diameter: SizeDistribution::Fixed(1e-3),
            velocity: DVec3::ZERO,
            start: 1.0,
            stop: 2.0,
            seed: 0,
        };
        assert_eq!(inj.due_by(0.5), 0);
        assert_eq!(inj.due_by(1.0), 0);
        assert_eq!(inj.due_by(1.0001), 1);
        assert_eq!(inj.due_by(1.15), 2);
        assert_eq!(inj.due_by(5.0), 10);
    }

    #[test]
    fn fines_injected_around_one_large_bead_overlap_neither_it_nor_each_other() {
        let inj = Injector {
            name: "fines".into(),
            kind: 0,
            rate: 2e6,
            region: Region::Box { min: DVec3::splat(-0.006), max: DVec3::splat(0.006) },
            diameter: SizeDistribution::Uniform { min: 1e-4, max: 2e-4 },
            velocity: DVec3::ZERO,
            start: 0.0,
            stop: f64::INFINITY,
            seed: 5,
        };
        let mut p = Particles::default();
        p.push(0, 0, 1e-2, DVec3::ZERO, DVec3::ZERO);
        let mut states = vec![inj.start()];
        let mut next_id = 1;
        // 2000 due in one step: those placed earlier in the step are in the later ones' way.
        assert!(run(std::slice::from_ref(&inj), &mut states, &[], &mut p, &mut next_id, 1e-3));
        assert_eq!(states[0].due, 2000);
        assert_eq!(states[0].injected as usize + 1, p.len());
        assert!(states[0].injected > 1500, "{} injected", states[0].injected);
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                let reach = 0.5 * (p.diameter[i] + p.diameter[j]);
                assert!((p.pos[j] - p.pos[i]).length() >= reach, "{i} and {j} overlap");
            }
        }
    }

    #[test]
    fn truncated_log_normal_sizes_stay_in_range_with_the_right_median() {
        let s = SizeDistribution::LogNormal { median: 2.5e-3, sigma: 0.3, min: 1.5e-3, max: 4e-3 };
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut d: Vec<f64> = (0..20_000).map(|_| s.sample(&mut rng)).collect();
        assert!(d.iter().all(|&x| (1.5e-3..=4e-3).contains(&x)));
        d.sort_by(f64::total_cmp);
        // The range is nearly symmetric in ln d about the median, so the median survives.
        assert!((d[10_000] / 2.5e-3 - 1.0).abs() < 0.02, "median {}", d[10_000]);
    }
}
