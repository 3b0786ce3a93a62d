//! The Rust alternative a user might pick: rapier3d-f64's own pipeline stepping the dilute
//! scene's 10,000 beads (`scenes/bench_dilute.toml`), as the benchmark (f).
//!
//! Run: `cargo bench --bench rapier_peer`. Throughput is in particles per second
//! (particle-steps/s), for 1 and 2 threads of rapier's `parallel` pipeline
//! (`rapier_dilute_step`), and for wetbounce stepping the same scene in the same run on pools of
//! 1 and 2 threads (`wetbounce_dilute_step`), so the ratio is measured under one machine load.
//! `cargo run --release --bin step_rate -- scenes/bench_dilute.toml 2000 1` (and `... 2000 2`)
//! gives wetbounce's figure the way docs/performance.md's other rows were measured.
//!
//! The scene is the same as wetbounce's: the bead positions and sizes, the bead density, the step
//! and the fluid come from `scenes/bench_dilute.toml` itself; the box's bounds are copied from
//! it. What rapier cannot express is approximated, as a user would:
//! - the beads are dynamic rigid bodies with ball colliders (density 2540 kg/m³, constant
//!   restitution 0.9 in place of L06's Stokes-number law, friction 0);
//! - buoyancy is folded into gravity, g (1 − ρ/ρp);
//! - Stokes drag is rapier's linear damping at the drag rate 18μ/(ρp d²). Rapier applies damping
//!   as a per-step factor 1/(1 + Δt c) on the velocity (an implicit-Euler decay at rate c), so
//!   this is the linear drag's rate applied once per step, an approximation of the drag force
//!   (it matches the exact decay e^(−Δt c) to first order in Δt c ≈ 1e-3);
//! - the six walls are fixed cuboids just outside the box.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use rapier3d_f64::prelude::*;
use wetbounce::Scene;

/// Half-thickness (m) of the cuboids that make the box's walls: thick compared with a step's
/// travel, so no bead can tunnel through, and outside the box so its inner faces are the scene's.
const WALL_HALF_THICKNESS: f64 = 0.01;

/// Criterion samples per case: a step of 10,000 bodies takes milliseconds, and criterion's
/// default of 100 samples needs 5050 steps at least.
const SAMPLES: usize = 20;

/// Everything `PhysicsPipeline::step` needs, kept together so a bench can step it.
struct World {
    gravity: Vector,
    params: IntegrationParameters,
    pipeline: PhysicsPipeline,
    islands: IslandManager,
    broad_phase: BroadPhaseBvh,
    narrow_phase: NarrowPhase,
    bodies: RigidBodySet,
    colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    ccd_solver: CCDSolver,
    /// Steps taken, for the check that the beads fell as the scene says.
    steps: u64,
    /// The drag rate (1/s) used as linear damping.
    drag_rate: f64,
}

impl World {
    fn step(&mut self) {
        self.pipeline.step(
            self.gravity,
            &self.params,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd_solver,
            &(),
            &(),
        );
        self.steps += 1;
    }

    /// Mean vertical velocity of the beads (m/s) and the Stokes settling law's value at the
    /// same time, −v_t (1 − e^(−c t)) with v_t = g' / c: a check that rapier did step the
    /// scene's physics and not, say, put the beads to sleep.
    fn settling_check(&self) -> (f64, f64) {
        let (sum, n) = self
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic())
            .fold((0.0, 0usize), |(s, n), (_, b)| (s + b.linvel().z, n + 1));
        let t = self.steps as f64 * self.params.dt;
        let expected = self.gravity.z / self.drag_rate * (1.0 - (-self.drag_rate * t).exp());
        (sum / n.max(1) as f64, expected)
    }
}

/// The dilute scene as rapier bodies; `threads` sizes the pipeline's own rayon pool.
fn dilute_world(scene: &Scene, threads: usize) -> World {
    let rho = scene.setup.fluid.density;
    let mu = scene.setup.fluid.viscosity;
    let kind = scene.setup.kinds.first().expect("the dilute scene has one kind");
    let rho_p = kind.density;
    let restitution = 0.9;
    let g = scene.setup.fluid.gravity * (1.0 - rho / rho_p);

    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();

    // The box of bench_dilute.toml, [0, 0.1875] × [0, 0.1875] × [0, 0.2].
    let (lo, hi) = ([0.0, 0.0, 0.0], [0.1875, 0.1875, 0.2]);
    let walls = bodies.insert(RigidBodyBuilder::fixed());
    for axis in 0..3 {
        let mut half = [(hi[0] - lo[0]) / 2.0, (hi[1] - lo[1]) / 2.0, (hi[2] - lo[2]) / 2.0];
        half[axis] = WALL_HALF_THICKNESS;
        for side in [lo[axis] - WALL_HALF_THICKNESS, hi[axis] + WALL_HALF_THICKNESS] {
            let mut centre = [(hi[0] + lo[0]) / 2.0, (hi[1] + lo[1]) / 2.0, (hi[2] + lo[2]) / 2.0];
            centre[axis] = side;
            let wall = ColliderBuilder::cuboid(half[0], half[1], half[2])
                .translation(Vector::new(centre[0], centre[1], centre[2]))
                .restitution(restitution)
                .friction(0.0);
            colliders.insert_with_parent(wall, walls, &mut bodies);
        }
    }

    let p = &scene.particles;
    let mut d_max: f64 = 0.0;
    let mut drag_rate = 0.0;
    for i in 0..p.len() {
        let (x, d) = (p.pos[i], p.diameter[i]);
        d_max = d_max.max(d);
        // Set per bead; the settling check reads it back, valid as this scene has one size.
        drag_rate = 18.0 * mu / (rho_p * d * d);
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(x.x, x.y, x.z))
            .linear_damping(drag_rate)
            // Beads released from rest start below rapier's sleep threshold; asleep they would
            // not be stepped at all, and the bench would time nothing.
            .can_sleep(false);
        let handle = bodies.insert(body);
        let ball = ColliderBuilder::ball(d / 2.0).density(rho_p).restitution(restitution).friction(0.0);
        colliders.insert_with_parent(ball, handle, &mut bodies);
    }

    let params = IntegrationParameters {
        dt: scene.setup.dt,
        // Rapier's tolerances (prediction distance, allowed penetration, speed cap) are scaled by
        // the typical object size in metres; at the default 1 m, the 2 cm prediction distance
        // would make every bead a contact candidate of its ~80 lattice neighbours.
        length_unit: d_max,
        ..IntegrationParameters::default()
    };

    let mut pipeline = PhysicsPipeline::new();
    pipeline.configure_thread_pool(threads).expect("rapier thread pool");
    World {
        gravity: Vector::new(g.x, g.y, g.z),
        params,
        pipeline,
        islands: IslandManager::new(),
        broad_phase: BroadPhaseBvh::new(),
        narrow_phase: NarrowPhase::new(),
        bodies,
        colliders,
        impulse_joints: ImpulseJointSet::new(),
        multibody_joints: MultibodyJointSet::new(),
        soft_bodies: SoftBodySet::new(),
        ccd_solver: CCDSolver::new(),
        steps: 0,
        drag_rate,
    }
}

fn dilute_step(c: &mut Criterion) {
    let scene = Scene::load(format!("{}/scenes/bench_dilute.toml", env!("CARGO_MANIFEST_DIR")))
        .expect("shipped scene");
    let mut group = c.benchmark_group("rapier_dilute_step");
    group.throughput(Throughput::Elements(scene.particles.len() as u64));
    group.sample_size(SAMPLES);
    for threads in [1, 2] {
        let mut world = dilute_world(&scene, threads);
        // The first step builds the broad phase's tree and the islands from nothing; the bench
        // is of the steps after it.
        world.step();
        group
            .bench_with_input(BenchmarkId::new("threads", threads), &threads, |b, _| b.iter(|| world.step()));
        let (mean_vz, expected) = world.settling_check();
        eprintln!(
            "rapier, {threads} thread(s): after {} steps, mean v_z = {mean_vz:.4e} m/s (Stokes settling: {expected:.4e})",
            world.steps
        );
    }
    group.finish();
}

/// The peer scene's step count.
const SCENE_STEPS: u64 = 20_000;

/// wetbounce on the same scene, in the same process, on pools of 1 and 2 threads.
fn wetbounce_dilute_step(c: &mut Criterion) {
    let scene = Scene::load(format!("{}/scenes/bench_dilute.toml", env!("CARGO_MANIFEST_DIR")))
        .expect("shipped scene");
    let mut group = c.benchmark_group("wetbounce_dilute_step");
    group.throughput(Throughput::Elements(scene.particles.len() as u64));
    group.sample_size(SAMPLES);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
        let mut sim = scene.simulation();
        // The steps run inside the pool, as in a real run (`Simulation::run_steps`), and only
        // the scene's own 20,000 steps are timed: criterion asks for far more, and later the
        // beads reach the floor and each other, which is another scene. So the simulation
        // starts again (untimed) before a batch would run past them.
        group.bench_with_input(BenchmarkId::new("threads", threads), &threads, |b, _| {
            b.iter_custom(|iters| {
                let mut elapsed = std::time::Duration::ZERO;
                let mut left = iters as usize;
                while left > 0 {
                    if sim.world.steps >= SCENE_STEPS {
                        sim = scene.simulation();
                    }
                    let n = left.min((SCENE_STEPS - sim.world.steps) as usize);
                    let start = std::time::Instant::now();
                    pool.install(|| sim.run_steps(n, scene.setup.dt));
                    elapsed += start.elapsed();
                    left -= n;
                }
                elapsed
            })
        });
    }
    group.finish();
}

criterion_group!(benches, dilute_step, wetbounce_dilute_step);
criterion_main!(benches);
