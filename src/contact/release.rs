//! Stage 1 at walls: the contacts that end in the step. (A pair's hold ends in
//! [`super::lasting::release_pairs`].)

use crate::flight::{Kernel, Motion, NO_MEMORY, Segment};
use crate::particles::{NO_WALL, State};
use crate::walls::{Surface, crease};
use glam::DVec3;

/// The start of a particle's path in the step ending at `t1`, after the contacts that end:
/// a particle held at a wall whose release time (`start.t`, which is `max(t0, release time)`)
/// falls before `t1` is released at `v_release` (its path then starts at its release time),
/// and a resting particle whose net force points away from its wall leaves it (docs/physics.md
/// §5.2). `(k, d)`: kind and diameter (m).
#[inline(always)]
pub(crate) fn release_at_wall<M: Motion>(
    flight: &Kernel<M>,
    start: Segment,
    v_release: DVec3,
    (k, d): (usize, f64),
    t1: f64,
) -> Segment {
    match start.state {
        State::Free | State::PairHeld => start,
        State::Held if start.t < t1 => {
            Segment { v: v_release, state: State::Free, wall: NO_WALL, memory: NO_MEMORY, ..start }
        }
        State::Held => start,
        State::Resting => {
            let n = flight.walls[start.wall as usize].shape.gap(start.x, 0.5 * d).normal;
            // On the wall the velocity is tangent: a normal part left by round-off or by the
            // contact solver would otherwise put a drag force across the wall.
            let vt = start.v - start.v.dot(n) * n;
            let a = flight.acceleration((k, d), start.x, vt);
            // "Points away" beyond round-off: on a side wall gravity is tangent, and the sign
            // of a zero would free and re-deposit the particle at every step.
            if a.dot(n) > 1e-9 * a.length() {
                // Resting in a crease, it may be pulled off one wall into the other: it rests
                // on that one then, as it did against it (no new contact).
                let crease = crease(flight.walls, start.wall, start.x, 0.5 * d);
                match crease.iter().find(|&(_, m)| a.dot(m) <= 1e-9 * a.length()) {
                    Some((w, _)) => Segment { wall: w, ..start },
                    None => Segment { state: State::Free, wall: NO_WALL, memory: NO_MEMORY, ..start },
                }
            } else {
                start
            }
        }
    }
}
