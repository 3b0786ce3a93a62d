//! A run split over ranks gives one process's results bit for bit (docs/distributed.md). The
//! ranks here are threads of the test ([`Threads`]), through the same split and the same run
//! loop as `mpirun` (CI also runs the shipped scenes under Open MPI: tools/ranks_same.sh):
//! every frame's particles and every contact event compared, for the border cases the
//! design must get right — an impact between particles that started on different ranks, a
//! held pair formed across ranks, an island of lasting contacts across ranks, a held pair that
//! changes rank during its hold.

use crate::common;
use glam::DVec3;
use std::sync::atomic::AtomicBool;
use wetbounce::output::{OutputError, Sink};
use wetbounce::ranks::comm::{Comm, Threads};
use wetbounce::ranks::{Split, SplitReport};
use wetbounce::run::{Plan, run_plan};
use wetbounce::{ContactEvent, Outcome, Simulation};

/// A particle in a frame: its id, the bits of its position and velocity, its state's code.
type Row = (u32, [u64; 6], u8);

/// Every frame's particles (time's bits, rows) and every event, as bits.
#[derive(Default, PartialEq, Debug)]
struct Seen {
    frames: Vec<(u64, Vec<Row>)>,
    events: Vec<String>,
}

impl Sink for Seen {
    fn frame(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        let p = &sim.world.particles;
        let bits = |a: DVec3, b: DVec3| {
            [a.x.to_bits(), a.y.to_bits(), a.z.to_bits(), b.x.to_bits(), b.y.to_bits(), b.z.to_bits()]
        };
        let rows = (0..p.len()).map(|i| (p.id[i], bits(p.pos[i], p.vel[i]), p.state[i].code())).collect();
        self.frames.push((sim.world.time.to_bits(), rows));
        Ok(())
    }

    fn events(&mut self, _sim: &Simulation, events: &[ContactEvent]) -> Result<(), OutputError> {
        self.events.extend(events.iter().map(|e| format!("{e:?}")));
        Ok(())
    }
}

/// The scene `text` run by one process.
fn alone(text: &str) -> Seen {
    let scene = common::scene(text);
    let (duration, interval) = (scene.duration, scene.output_interval);
    let mut sim = scene.simulation();
    let mut seen = Seen::default();
    let plan = Plan { duration, output_interval: interval, from: None, checkpoints: None, steps: None };
    run_plan(&mut sim, plan, &mut [&mut seen], &AtomicBool::new(false)).unwrap();
    seen
}

/// The scene `text` run on `ranks` thread-ranks: what rank 0's sinks saw, and how the run was
/// split.
fn on_ranks(text: &str, ranks: usize) -> (Seen, SplitReport) {
    let handles: Vec<_> = Threads::set(ranks)
        .into_iter()
        .map(|comm| {
            let text = text.to_string();
            std::thread::spawn(move || {
                let scene = common::scene(&text);
                let (duration, interval) = (scene.duration, scene.output_interval);
                let mut sim = scene.simulation();
                let mut split = Split::new(&comm, &sim).unwrap();
                let mut seen = Seen::default();
                let plan = Plan {
                    duration,
                    output_interval: interval,
                    from: None,
                    checkpoints: None,
                    steps: Some(&mut split),
                };
                let sinks: &mut [&mut dyn Sink] = if comm.rank() == 0 { &mut [&mut seen] } else { &mut [] };
                run_plan(&mut sim, plan, sinks, &AtomicBool::new(false)).unwrap();
                assert!(split.failure().is_none(), "{:?}", split.failure());
                (seen, split.report.clone())
            })
        })
        .collect();
    let mut results: Vec<(Seen, SplitReport)> = handles.into_iter().map(|h| h.join().unwrap()).collect();
    results.swap_remove(0)
}

/// Asserts that 2 and 3 ranks see what one process sees, and returns one process's run and
/// the reports of the splits.
fn same_on_ranks(text: &str) -> (Seen, Vec<SplitReport>) {
    let one = alone(text);
    assert!(!one.frames.is_empty());
    let mut reports = Vec::new();
    for ranks in [2, 3] {
        let (seen, report) = on_ranks(text, ranks);
        assert_eq!(seen.events, one.events, "events on {ranks} ranks");
        assert!(seen.frames == one.frames, "particles differ on {ranks} ranks");
        reports.push(report);
    }
    (one, reports)
}

/// The shipped scene `name` with its duration (s) and, if given, its output interval replaced.
fn shipped_cut(name: &str, duration: &str, output_interval: Option<&str>) -> String {
    let path = format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    let lines: Vec<String> = text
        .lines()
        .map(|l| match output_interval {
            _ if l.starts_with("duration =") => format!("duration = {duration}"),
            Some(i) if l.starts_with("output_interval =") => format!("output_interval = {i}"),
            _ => l.to_string(),
        })
        .collect();
    lines.join("\n")
}

/// Glass beads in water, no walls but what `walls` says, the beads given as `[[particles]]`.
fn beads(effects: &str, walls: &str, particles: &[(DVec3, DVec3)], duration: f64) -> String {
    let mut text = format!(
        r#"
[simulation]
dt = 1e-4
duration = {duration}
output_interval = 0.01
[fluid]
density = 997.0
viscosity = 0.89e-3
[effects]
{effects}
[[kinds]]
name = "glass"
type = "solid"
density = 2500.0
youngs_modulus = 6.3e10
poisson_ratio = 0.23
restitution_max = 0.97
{walls}
"#
    );
    for (x, v) in particles {
        text += &format!(
            "[[particles]]\nkind = \"glass\"\ndiameter = 3e-3\nposition = [{:?}, {:?}, {:?}]\nvelocity = [{:?}, {:?}, {:?}]\n",
            x.x, x.y, x.z, v.x, v.y, v.z
        );
    }
    text
}

#[test]
fn two_beads_from_different_ranks_collide_as_in_one_process() {
    // Ten pairs 120 mm apart along x (the longest side: the first split cuts between the
    // halves), each pair meeting head-on at 0.6 m/s, with no force acting.
    let mut particles = Vec::new();
    for k in 0..10 {
        let y = k as f64 * 0.005;
        particles.push((DVec3::new(-0.06, y, 0.0), DVec3::new(0.3, 0.0, 0.0)));
        particles.push((DVec3::new(0.06, y, 0.0), DVec3::new(-0.3, 0.0, 0.0)));
    }
    let (one, reports) = same_on_ranks(&beads("", "", &particles, 0.3));
    assert!(one.events.iter().any(|e| e.contains("Particle")), "the beads must meet");
    for r in &reports {
        assert!(r.moved > 0, "a bead changed rank to meet its partner: {r:?}");
    }
}

/// Eight pairs of toluene drops in water, each pair's drops starting 60 mm apart along x (the
/// longest side: the first split cuts between them, so partners start on different ranks),
/// meeting head-on at 1 m/s and held together for their contact time; `drift` (m/s) along x
/// carries a held pair across that cut during its hold.
fn drops(drift: f64) -> String {
    let mut text = String::from(
        r#"
[simulation]
dt = 1e-4
duration = 0.3
output_interval = 0.01
[fluid]
density = 997.0
viscosity = 0.89e-3
[effects]
contact_time = {}
[[kinds]]
name = "toluene"
type = "drop"
density = 860.0
surface_tension = 0.026
restitution_max = 0.91
"#,
    );
    for k in 0..8 {
        let y = 0.005 * k as f64;
        for (x, vx) in [(-0.03, 0.5 + drift), (0.03, -0.5 + drift)] {
            text += &format!(
                "[[particles]]\nkind = \"toluene\"\ndiameter = 2.5e-3\nposition = [{x:?}, {y:?}, 0.0]\nvelocity = [{vx:?}, 0.0, 0.0]\n"
            );
        }
    }
    text
}

#[test]
fn drops_held_together_across_ranks_are_held_as_in_one_process() {
    let (one, reports) = same_on_ranks(&drops(0.0));
    assert!(one.events.iter().any(|e| e.contains(&format!("{:?}", Outcome::Held))), "the drops must be held");
    for r in &reports {
        assert!(r.moved > 0, "partners met on one rank: {r:?}");
    }
}

#[test]
fn a_held_pair_that_changes_rank_during_its_hold_is_released_as_in_one_process() {
    // Drifting along x at 0.1 m/s, a held pair's lowest drop crosses the first cut (x = 0)
    // during the 22 ms hold; a re-clustering then moves the pair to the other rank.
    let (one, reports) = same_on_ranks(&drops(0.1));
    assert!(one.events.iter().any(|e| e.contains(&format!("{:?}", Outcome::Held))), "the drops must be held");
    for r in &reports {
        assert!(r.moved > 0 && r.reclusterings > 2, "{r:?}");
    }
}

#[test]
fn an_island_of_lasting_contacts_across_ranks_settles_as_in_one_process() {
    // Nine beads resting on a floor, and eighteen more falling onto them from 25 mm above: two
    // sets too far apart to touch at first, which the first split puts on different ranks, and
    // which end as one island of lasting contacts.
    let mut particles = Vec::new();
    for k in 0..27 {
        let (i, j, l) = ((k % 3) as f64, ((k / 3) % 3) as f64, (k / 9) as f64);
        let z = if l == 0.0 { 1.6e-3 } else { 25e-3 + l * 3.4e-3 };
        particles.push((DVec3::new(i * 3.3e-3, j * 3.3e-3, z), DVec3::ZERO));
    }
    let walls = r#"
[[walls]]
name = "floor"
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
"#;
    let effects = "gravity = {}\nbuoyancy = {}\ndrag = {}\nadded_mass = {}";
    let (one, reports) = same_on_ranks(&beads(effects, walls, &particles, 0.4));
    assert!(one.events.iter().any(|e| e.contains("Particle")), "the beads must touch");
    for r in &reports {
        assert!(r.last.largest > 9 && r.moved > 0, "the sets met on one rank: {r:?}");
    }
}

/// The shipped `bench_*` scenes (copies of the peers' benchmarks: 10⁴ beads for 20,000 steps,
/// too long for CI's `mpirun` check of the shipped scenes) cut to 120 steps, on 2 and 3 ranks:
/// the dense bed with friction among them, whose lasting-contact sweeps the ranks agree on.
#[test]
fn the_benchmark_scenes_cut_short_run_as_in_one_process() {
    for name in [
        "bench_bed_friction",
        "bench_dilute",
        "bench_paper",
        "bench_paper_full",
        "bench_paper_history",
        "bench_paper_lubrication",
    ] {
        let text = shipped_cut(name, "1.0524e-3", Some("2.631e-4"));
        let (one, _) = same_on_ranks(&text);
        assert_eq!(one.frames.len(), 5, "{name}");
    }
}

/// What rank 0 gathers for a checkpoint is the world one process holds at that step, and one
/// process going on from it writes what a run never split writes: drops colliding and held
/// while pairs drift across the ranks' domains, checkpointed during their holds.
#[test]
fn a_checkpoint_of_a_run_on_ranks_is_one_process_world_and_goes_on_alike() {
    use wetbounce::run::Steps;
    let text = drops(0.1);
    // The pairs meet at 0.0575 s and are held for 22 ms.
    let stop_at = 0.065;
    let scene = common::scene(&text);
    let (duration, interval) = (scene.duration, scene.output_interval);
    // One process, to the checkpoint's time and on to the end.
    let mut whole = scene.simulation();
    whole.advance_to(stop_at);
    let at_checkpoint = whole.world.clone();
    // The events so far belong to the run before the checkpoint.
    assert!(!whole.record.events.is_empty());
    whole.record.events.clear();
    let rest = |mut sim: Simulation| {
        let mut seen = Seen::default();
        let plan = Plan { duration, output_interval: interval, from: None, checkpoints: None, steps: None };
        run_plan(&mut sim, plan, &mut [&mut seen], &AtomicBool::new(false)).unwrap();
        seen
    };
    let expected = rest(whole);
    // Two thread-ranks to the same time; rank 0 gathers the world as for a checkpoint.
    let gathered: Vec<Option<wetbounce::World>> = std::thread::scope(|s| {
        let handles: Vec<_> = Threads::set(2)
            .into_iter()
            .map(|comm| {
                let text = &text;
                s.spawn(move || {
                    let mut sim = common::scene(text).simulation();
                    let mut split = Split::new(&comm, &sim).unwrap();
                    while sim.world.time < stop_at {
                        let target = (sim.world.time + sim.setup.dt).min(stop_at);
                        split.advance(&mut sim, target);
                    }
                    split.before_checkpoint(&mut sim);
                    assert!(split.report.moved > 0);
                    (comm.rank() == 0).then_some(sim.world)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let world = gathered.into_iter().flatten().next().unwrap();
    let (p, q) = (&world.particles, &at_checkpoint.particles);
    assert_eq!((&p.id, &p.pos, &p.vel, &p.state), (&q.id, &q.pos, &q.vel, &q.state));
    assert_eq!((&p.release_time, &p.release_vel, &p.wall), (&q.release_time, &q.release_vel, &q.wall));
    let pairs = |w: &wetbounce::World| {
        let mut v: Vec<String> = w.lasting.iter().map(|c| format!("{c:?}")).collect();
        v.sort();
        v
    };
    assert!(!world.lasting.is_empty(), "the checkpoint falls during holds");
    assert_eq!(pairs(&world), pairs(&at_checkpoint));
    assert_eq!(
        (world.time, world.steps, world.next_id),
        (at_checkpoint.time, at_checkpoint.steps, at_checkpoint.next_id)
    );
    // One process from the gathered world: the rest of the run never split.
    let scene = common::scene(&text);
    let setup = scene.simulation().setup;
    let removed = vec![Vec::new(); setup.outlets.len()];
    let resumed = Simulation::restore(setup, world, (Vec::new(), removed, None)).unwrap();
    let went_on = rest(resumed);
    assert_eq!(went_on.events, expected.events);
    assert!(went_on.frames == expected.frames);
}

/// Injected particles join the cluster of their neighbours on its rank (or start one of their
/// own), as in one process: the heap's pour and the column's drops, cut short.
#[test]
fn injected_particles_run_as_in_one_process() {
    for (name, duration) in [("heap", "0.4"), ("column", "3.0")] {
        let (one, reports) = same_on_ranks(&shipped_cut(name, duration, None));
        assert!(one.frames.last().unwrap().1.len() > 20, "{name}: particles were injected");
        for r in &reports {
            assert!(r.moved > 0 || r.last.counts.iter().filter(|&&c| c > 0).count() > 1, "{name}: {r:?}");
        }
    }
}
