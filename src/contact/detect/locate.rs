//! Time of impact on the curved path inside a step.

use crate::walls::Crossing;

/// Finds the first time `s ∈ [0, h]` at which the gap `g(s)` between a particle on its curved
/// path and a wall (or another particle) reaches 0, given the chord test's `crossing` and the
/// gap `end_gap` at `s = h`.
///
/// The chord `x(0) → x(h)` only detects the contact (a thin wall is caught however fast the
/// particle moves); the time is then found on the integrator's own path, so that it is as
/// accurate as the integrator (docs/physics.md §5.5: the contact is located inside the step).
/// A bracket `[s_a, s_b]` with the gap positive at `s_a` and negative at `s_b` is built — `s_b`
/// is the end of the step, or the deepest point of the chord's overlap for a wall the path goes
/// through — and refined by the Illinois variant of regula falsi. `None` when the curved path
/// does not actually reach the wall (the chord grazed a corner the path avoids).
pub fn locate_on_path(
    g: impl Fn(f64) -> f64,
    h: f64,
    crossing: Crossing,
    end_gap: f64,
    length_scale: f64,
) -> Option<f64> {
    let (mut sb, mut gb) = if end_gap < 0.0 {
        (h, end_gap)
    } else {
        let mid = 0.5 * (crossing.enter + crossing.exit) * h;
        let gm = g(mid);
        if gm >= 0.0 {
            return None;
        }
        (mid, gm)
    };
    // The gap counts as closed within this (the location's own accuracy).
    let tol_gap = 1e-13 * length_scale;
    let (mut sa, mut ga) = (0.0, g(0.0));
    if ga <= tol_gap {
        // Starting in contact, to round-off: right after a rebound, or at one face of a box
        // corner while the other is still ahead. Departing first and coming back (a weak
        // rebound), or going on to another part: find a point in between where the gap is
        // open. (Taking the start as the root would report a second contact at the first.)
        let mut s = sb;
        let mut found = false;
        for _ in 0..60 {
            s *= 0.5;
            let gs = g(s);
            if gs > tol_gap {
                (sa, ga, found) = (s, gs, true);
                break;
            }
            (sb, gb) = (s, gs);
        }
        if !found {
            return Some(0.0);
        }
    }
    // Illinois: regula falsi that halves the weight of an end point kept twice in a row.
    let mut side = 0;
    for _ in 0..200 {
        let s = (sa * gb - sb * ga) / (gb - ga);
        let gs = g(s);
        if gs.abs() <= tol_gap || sb - sa <= 1e-15 * h {
            return Some(s);
        }
        if gs > 0.0 {
            (sa, ga) = (s, gs);
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        } else {
            (sb, gb) = (s, gs);
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        }
    }
    Some(sa)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn finds_parabola_impact_to_round_off() {
        // Free fall from z = 1 at 0 speed, floor gap = z − 0.1: impact at sqrt(2·0.9/g).
        let g = 9.81;
        let path = |s: f64| (DVec3::new(0.0, 0.0, 1.0 - 0.5 * g * s * s), DVec3::new(0.0, 0.0, -g * s));
        let gap = |x: DVec3| x.z - 0.1;
        let h = 1.0;
        let s = locate_on_path(
            |s| gap(path(s).0),
            h,
            Crossing { enter: 0.9 / 4.905, exit: 1.0 },
            gap(path(h).0),
            0.1,
        )
        .unwrap();
        let exact = (2.0 * 0.9 / g).sqrt();
        assert!((s - exact).abs() < 1e-13, "{s} vs {exact}");
    }

    #[test]
    fn finds_return_after_weak_rebound_not_the_departure() {
        // Leaves the floor at 0.01 m/s against gravity: back at s = 2·0.01/g.
        let g = 9.81;
        let path = |s: f64| (DVec3::new(0.0, 0.0, 0.01 * s - 0.5 * g * s * s), DVec3::ZERO);
        let gap = |x: DVec3| x.z;
        let s = locate_on_path(
            |s| gap(path(s).0),
            0.1,
            Crossing { enter: 0.0, exit: 1.0 },
            gap(path(0.1).0),
            1.0,
        )
        .unwrap();
        assert!((s - 0.02 / g).abs() < 1e-12, "{s}");
    }
}
