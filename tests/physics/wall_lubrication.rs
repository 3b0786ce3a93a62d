//! The wall-lubrication effect and the `e` rule (docs/physics.md §8): a bead slowed by the film of
//! fluid under it, touching at the roughness, rebounding at `e` times its impact speed and
//! leaving through the same film.

use crate::common;
use common::fixture::BeadOnFloor;
use glam::DVec3;
use proptest::prelude::*;
use proptest::test_runner::Config;
use wetbounce::correlations::brenner_normal_exact;
use wetbounce::particles::State;
use wetbounce::{Outcome, Simulation};

/// Contact gap of the tests' beads: the kind's roughness, the floor has none (m).
const H_R: f64 = 1e-6;

fn lubricated() -> BeadOnFloor {
    BeadOnFloor::new()
        .roughness(H_R)
        .effects("gravity = {}\nbuoyancy = {}\ndrag = {}\nadded_mass = {}\nwall_lubrication = {}")
}

/// Quasi-steady Stokes approach: a bead so viscously damped that its inertia does not count
/// (`τ` ~ 0.6 ms against seconds of approach) moves at `V_t / λ⊥(h/a)` under a constant force,
/// so the time from lubrication gap `h1` to contact at `h_r` is `∫ λ⊥(h/a) dh / V_t`
/// (Brenner's exact series, Simpson's rule in `ln h`). The bead starts at `h1 = 2a`, inside
/// the range where the wall terms are not tapered, at its quasi-steady speed there.
#[test]
fn stokes_approach_slows_as_the_integral_of_lambda_perp_predicts_and_touches_at_the_roughness() {
    let (err, speed_err) = stokes_approach((2e-3, 2500.0, 1000.0, 1.0), "", ("rk2", 1e-3), 20.0);
    assert!(err < 5e-3, "contact time against quasi-steady Stokes: relative error {err:.2e}");
    // Contact is at the roughness: the bead's surface is on the floor (its geometric gap, the
    // lubrication gap less h_r, is 0) and its impact speed is the film's, V_t / λ⊥(h_r/a).
    assert!(speed_err < 1e-2, "impact speed against quasi-steady Stokes: relative error {speed_err:.2e}");
}

/// The Stokes approach of a bead of diameter `d`, density `rho_p` in a fluid `(rho, mu)` with
/// the effects `extra` besides gravity, buoyancy, Stokes drag and lubrication, stepped by
/// `integrator` with `dt` for at most `duration` (s): the relative errors of its first contact's time against
/// `∫ λ⊥ dh / V_t` and of its impact speed against `V_t / λ⊥(h_r/a)`.
pub(crate) fn stokes_approach(
    (d, rho_p, rho, mu): (f64, f64, f64, f64),
    extra: &str,
    (integrator, dt): (&str, f64),
    duration: f64,
) -> (f64, f64) {
    let g = 9.81;
    let a = 0.5 * d;
    let v_t = (rho_p - rho) * g * d * d / (18.0 * mu);
    let h1 = 2.0 * a;
    let v1 = v_t / brenner_normal_exact(h1 / a);
    let mut sim = BeadOnFloor::new()
        .roughness(H_R)
        .fluid(rho, mu)
        .density(rho_p)
        .diameter(d)
        .dt(dt)
        .integrator(integrator)
        .duration(duration)
        .output_interval(duration)
        .effects(&format!(
            "gravity = {{}}\nbuoyancy = {{}}\ndrag = {{ law = \"stokes\" }}\nwall_lubrication = {{}}\n{extra}"
        ))
        .particle([0.0, 0.0, a + h1 - H_R], [0.0, 0.0, -v1])
        .scene()
        .simulation();
    let events = common::run_collect(&mut sim, duration);
    let first = events.first().expect("the bead reaches the floor");
    // ∫ λ⊥ dh from h_r to h1, in u = ln h.
    let n = 20_000;
    let (u0, u1) = (H_R.ln(), h1.ln());
    let du = (u1 - u0) / n as f64;
    let f = |j: usize| {
        let h = (u0 + j as f64 * du).exp();
        brenner_normal_exact(h / a) * h
    };
    let simpson: f64 = (0..=n)
        .map(|j| {
            let w = if j == 0 || j == n {
                1.0
            } else if j % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * f(j)
        })
        .sum::<f64>()
        * du
        / 3.0;
    let expected = simpson / v_t;
    let err = (first.time - expected).abs() / expected;
    let v_contact = v_t / brenner_normal_exact(H_R / a);
    let speed_err = (first.normal_speed - v_contact).abs() / v_contact;
    println!(
        "contact after {} s, ∫ λ⊥ dh / V_t = {expected} s: relative error {err:.2e}; impact speed {} m/s, \
         relative error {speed_err:.2e}",
        first.time, first.normal_speed
    );
    (err, speed_err)
}

/// The overall restitution as L06 measures it: a bead shot at the floor at `V0` from 10 radii
/// (where the wall is not yet felt), with neither gravity nor buoyancy and Stokes drag so that
/// `St` is set by the viscosity alone; `ε` is the normal speed when it is back at 10 radii
/// over `V0` (0 if it never comes back).
fn measured_eps(st: f64) -> (f64, Vec<wetbounce::ContactEvent>) {
    let (d, rho_p, rho, v0) = (2e-3, 2500.0, 1000.0, 0.1);
    let a = 0.5 * d;
    let mu = (rho_p + 0.5 * rho) * v0 * d / (9.0 * st);
    let start = a + 10.0 * a - H_R;
    let mut sim = BeadOnFloor::new()
        .roughness(H_R)
        .fluid(rho, mu)
        .density(rho_p)
        .diameter(d)
        .restitution_max(0.9)
        .dt(1e-4)
        .effects("drag = { law = \"stokes\" }\nadded_mass = {}\nwall_lubrication = {}")
        .particle([0.0, 0.0, start], [0.0, 0.0, -v0])
        .scene()
        .simulation();
    let mut events = Vec::new();
    let mut touched = false;
    while sim.world.time < 2.0 {
        sim.step(1e-5);
        events.append(&mut sim.record.events);
        touched |= !events.is_empty();
        let (z, vz) = (sim.world.particles.pos[0].z, sim.world.particles.vel[0].z);
        if touched && z >= start {
            return (vz / v0, events);
        }
        if sim.world.particles.state[0] == State::Resting {
            break;
        }
    }
    (0.0, events)
}

/// docs/physics.md §8: with the `e` rule, the Stokes-number dependence comes from the lubrication.
/// At high St the bead hardly feels the film and `ε → e`; as St falls `ε` falls; at low St
/// the film stops it: no rebound. Printed next to L06's `ε_max exp(−35/St)` (eq. 2).
#[test]
fn measured_restitution_tends_to_e_at_high_st_falls_with_st_and_vanishes_at_low_st() {
    let e = 0.9;
    let mut last = f64::INFINITY;
    for st in [1e4, 1000.0, 300.0, 100.0, 30.0] {
        let (eps, events) = measured_eps(st);
        let l06 = e * (-35.0 / st).exp();
        println!("St = {st:>7}: measured ε = {eps:.4}, L06 eq. 2 = {l06:.4}, {} contact(s)", events.len());
        for ev in &events {
            assert!(ev.energy_after <= ev.energy_before, "{ev:?}");
        }
        assert!(eps <= last, "ε must fall with St: {eps} at St = {st} after {last}");
        if st >= 1e4 {
            assert!((eps - e).abs() < 0.01, "at St = {st}, ε = {eps}, e = {e}");
        }
        last = eps;
    }
    for st in [3.0, 1.0] {
        let (eps, _) = measured_eps(st);
        assert_eq!(eps, 0.0, "at St = {st} the film must stop the bead");
    }
}

/// A bead dropped onto the floor at rest slows in the film, touches at the roughness and ends
/// resting on the floor; every contact loses energy.
#[test]
fn settling_bead_touches_at_the_roughness_and_comes_to_rest_losing_energy_at_every_contact() {
    let mut sim = lubricated().dt(2e-4).particle([0.0, 0.0, 0.02], [0.0; 3]).scene().simulation();
    let events = common::run_collect(&mut sim, 1.0);
    assert!(!events.is_empty());
    assert!(events.iter().any(|e| e.outcome == Outcome::Bounced), "{events:#?}");
    assert_eq!(events.last().unwrap().outcome, Outcome::Deposited);
    assert_eq!(sim.world.particles.state[0], State::Resting);
    for e in &events {
        assert!(e.energy_after <= e.energy_before, "{e:?}");
    }
    common::assert_clear_of_walls(&sim);
}

/// The shipped comparison: the glass bead with and without lubrication. With it, the first
/// impact speed is lower than the terminal speed (the film slowed the bead), and the first
/// rebound's `eps` is `e = ε_max = 0.97` of that speed.
#[test]
fn glass_bead_lubrication_scene_bounces_at_e_of_the_slowed_impact_speed() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glass_bead_lubrication.toml");
    let mut sim = wetbounce::Scene::load(&path).unwrap_or_else(|e| panic!("{e}")).simulation();
    let dry = common::shipped_with("glass_bead.toml", "duration", "1.0").simulation();
    let events = common::run_collect(&mut sim, 1.0);
    let first = events[0];
    assert_eq!(first.outcome, Outcome::Bounced);
    assert_eq!(first.eps, 0.97);
    let mut dry = dry;
    let dry_events = common::run_collect(&mut dry, 1.0);
    println!("dry first impact: {:?}\nlubricated first impact: {first:?}", dry_events[0]);
    assert!(first.normal_speed < 0.95 * dry_events[0].normal_speed);
    common::assert_clear_of_walls(&sim);
}

fn through_the_floor(sim: &Simulation) -> bool {
    let (g, _, _) = common::deepest_overlap(sim);
    g < -1e-9
}

proptest! {
    #![proptest_config(Config { cases: 128, failure_persistence: None, ..Config::default() })]

    /// No particle goes through a wall with lubrication on, whatever its size, density, speed
    /// and the time step; and the state stays finite.
    #[test]
    fn no_bead_goes_through_the_floor_with_lubrication(
        d in 1e-4f64..5e-3,
        rho_p in 1100.0f64..8000.0,
        speed in 0.0f64..2.0,
        angle in 0.0f64..1.2,
        dt in prop::sample::select(vec![1e-5, 1e-4, 5e-4, 2e-3]),
        roughness_fraction in 1e-4f64..1e-2,
        integrator in prop::sample::select(vec!["euler", "rk2", "rk4", "exponential"]),
    ) {
        let v = DVec3::new(speed * angle.sin(), 0.0, -speed * angle.cos());
        let scene = lubricated()
            .diameter(d)
            .density(rho_p)
            .roughness(roughness_fraction * 0.5 * d)
            .dt(dt)
            .integrator(integrator)
            .particle([0.0, 0.0, 0.5 * d + 2.0 * d], v)
            .toml();
        let mut sim = match wetbounce::Scene::from_str(&scene, std::path::Path::new("scenes/test.toml")) {
            Ok(s) => s.simulation(),
            // A step beyond the explicit integrator's stability limit is refused: not a case.
            Err(e) if e.to_string().contains("simulation.dt") => return Ok(()),
            Err(e) => panic!("{e}"),
        };
        while sim.world.time < 0.2 {
            let next = (sim.world.time + 20.0 * dt).min(0.2);
            sim.advance_to(next);
            for e in sim.record.events.drain(..) {
                prop_assert!(e.energy_not_gained(), "{e:?}");
            }
            prop_assert!(!through_the_floor(&sim), "through the floor at t = {}: {:?}", sim.world.time, sim.world.particles.pos[0]);
            prop_assert!(sim.world.particles.pos[0].is_finite() && sim.record.lost.is_empty());
        }
    }
}

/// The hold still applies to drops (docs/physics.md §5.3, §8): L06's 2.75 mm toluene drop rising
/// to the top wall, with wall lubrication instead of L06's ε, is held for `t_c` (L06 eq. 5) at
/// its first impact, then released at `e V_imp` away from the wall and leaves through the film.
#[test]
fn toluene_drop_with_lubrication_is_held_for_t_c_then_leaves_at_e_of_its_impact_speed() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/toluene_drop.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text
        .replace("beta = 35.0\nst_critical = 10.0\n", "")
        .replace("contact_time = {}\n", "contact_time = {}\nwall_lubrication = {}\n")
        .replace("restitution_max = 0.91", "restitution_max = 0.91\nroughness = 1e-6");
    let mut sim = wetbounce::Scene::from_str(&text, &path).unwrap_or_else(|e| panic!("{e}")).simulation();
    let mut events = Vec::new();
    while events.is_empty() {
        sim.step(1e-4);
        events.append(&mut sim.record.events);
    }
    let first = events[0];
    assert_eq!(first.outcome, Outcome::Held, "{first:?}");
    assert_eq!(first.eps, 0.91);
    assert!(first.contact_time > 0.015 && first.contact_time < 0.03, "t_c = {}", first.contact_time);
    // Held: it stays at the wall for t_c.
    sim.advance_to(first.time + 0.9 * first.contact_time);
    assert_eq!(sim.world.particles.state[0], State::Held);
    // Released at e V_imp downwards (away from the top wall), then slowed by the film.
    sim.advance_to(first.time + first.contact_time + 2e-4);
    assert_eq!(sim.world.particles.state[0], State::Free);
    let vz = sim.world.particles.vel[0].z;
    assert!(
        vz < 0.0 && -vz <= 0.91 * first.normal_speed,
        "v_z = {vz}, released at most {}",
        0.91 * first.normal_speed
    );
    common::assert_clear_of_walls(&sim);
}

/// In a corner only the nearest wall's film acts (docs/physics.md §8): beads thrown into the corner
/// of a 10 mm box, along the diagonal and just off it, fast and slow, stay inside, touch, and
/// never gain energy at a contact, with a small and a large step.
#[test]
fn beads_thrown_into_a_box_corner_with_lubrication_stay_inside_and_never_gain_energy() {
    let walls = "[[walls]]\nname = \"box\"\ntype = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [0.01, 0.01, 0.01]\ninside = true\n";
    for dt in [1e-4, 2e-3] {
        let starts: Vec<(DVec3, DVec3)> = [(1.0, 1.0, 1.0), (1.0, 1.0001, 0.9999), (1.0, 1.0, 0.0)]
            .iter()
            .zip([0.8, 3.0, 0.3])
            .map(|(&(a, b, c), s)| (DVec3::splat(0.005), -s * DVec3::new(a, b, c).normalize()))
            .enumerate()
            .map(|(k, (x, v))| (x + DVec3::new(0.0, 0.0, (k as f64 - 1.0) * 2.5e-3), v))
            .collect();
        let mut sim = lubricated()
            .diameter(1e-3)
            .dt(dt)
            .integrator("exponential")
            .walls(walls)
            .particles(&starts)
            .scene()
            .simulation();
        let mut contacts = 0;
        while sim.world.time < 0.5 {
            let next = (sim.world.time + 10.0 * dt).min(0.5);
            sim.advance_to(next);
            for e in sim.record.events.drain(..) {
                assert!(e.energy_not_gained(), "dt {dt}: {e:?}");
                contacts += 1;
            }
            common::assert_clear_of_walls(&sim);
            assert!(sim.record.lost.is_empty());
        }
        assert!(contacts >= 3, "dt {dt}: only {contacts} contacts");
    }
}

/// Beads near a wall fly by lane groups of four (`Kernel::near_wall_lanes`) when they come
/// several at once, and one at a time when alone: 21 beads from a fifth of a radius to twelve
/// radii above the floor, some fast enough towards it to need sub-steps, some touching it in
/// the run, end where each ends alone in the same scene, to the last bit.
#[test]
fn near_wall_beads_flown_by_lane_groups_end_where_each_ends_alone() {
    let a = 1e-3;
    let starts: Vec<(DVec3, DVec3)> = (0..21)
        .map(|i| {
            let gap = a * (0.2 + 0.6 * i as f64);
            let speed = [-0.02, 0.01, -0.3, 0.0, -0.001, 0.05, -1.0][i % 7];
            let x = DVec3::new(20.0 * a * i as f64, 0.0, a + H_R + gap);
            (x, DVec3::new(0.01 * (i % 3) as f64, -0.005, speed))
        })
        .collect();
    let run = |starts: &[(DVec3, DVec3)]| {
        let mut sim = lubricated()
            .diameter(2.0 * a)
            .dt(1e-4)
            .duration(3e-3)
            .output_interval(3e-3)
            .particles(starts)
            .scene()
            .simulation();
        common::run_collect(&mut sim, 3e-3);
        let p = &sim.world.particles;
        (0..p.len()).map(|i| (p.id[i], p.pos[i], p.vel[i])).collect::<Vec<_>>()
    };
    let together = run(&starts);
    assert_eq!(together.len(), starts.len());
    for (i, start) in starts.iter().enumerate() {
        let (_, x, v) = run(std::slice::from_ref(start))[0];
        let &(_, xt, vt) = together.iter().find(|t| t.0 as usize == i).expect("every bead kept");
        assert_eq!((xt, vt), (x, v), "bead {i}, from {start:?}");
    }
}
