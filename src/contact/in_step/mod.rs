//! Stage 4: every contact inside the step — with walls and between particles — is
//! located on the particles' curved paths, resolved by the bounce rule in time order, and the
//! rest of the step integrated from the contact point.
//!
//! Particles that may touch each other this step form *islands* ([`islands`]); a particle
//! alone is an island of one. Each island is resolved sequentially, event by event in time
//! order ([`queue`]); islands run in parallel and are written back in index order, so the
//! result does not depend on the thread count.
//!
//! - [`track`]: one particle's path through the step, and when paths meet walls or each other;
//! - [`impacts`]: the bounce rule applied at a wall event and at a pair event;
//! - [`queue`]: an island's events in time order.

mod impacts;
mod islands;
mod queue;
mod track;

use super::{ContactEvent, Ctx, LastingContact};
use crate::flight::{Motion, NO_MEMORY};
use crate::particles::{NO_WALL, Next, Particles, State, WallHold};
use glam::DVec3;
use queue::IslandResult;
use rayon::prelude::*;

/// Stage 4 for the whole step from `t0` to `t1`: islands from the broad phase's wall
/// candidates and candidate pairs, resolved in parallel, written back in index order into
/// `next` (positions, velocities, states, walls, and the holds begun), `events` (with, for each,
/// the id of the lowest particle of its island in `event_islands`) and `lasting`.
/// Returns true when a particle's new state is not finite.
pub(crate) fn resolve_in_step<M: Motion>(
    ctx: &Ctx<M>,
    p: &Particles,
    (t0, t1): (f64, f64),
    (wall_candidates, pair_candidates): (&[u32], &[[u32; 2]]),
    next: &mut Next,
    (events, event_islands): (&mut Vec<ContactEvent>, &mut Vec<u32>),
    lasting: &mut Vec<LastingContact>,
) -> bool {
    let islands = islands::islands(wall_candidates, pair_candidates);
    let results: Vec<IslandResult<M>> = islands
        .par_iter()
        .map(|island| {
            let tracks = island.members.iter().map(|&i| ctx.track(p, next, i, t0)).collect();
            ctx.resolve_island(p, tracks, &island.pairs, t1)
        })
        .collect();
    let mut suspect = false;
    let width = ctx.flight.memory_width();
    for (island, r) in islands.iter().zip(results) {
        // The events' place in a run split over ranks: by island, islands by their lowest id.
        event_islands.extend(std::iter::repeat_n(p.id[island.members[0]], r.events.len()));
        for tr in r.tracks {
            let i = tr.i;
            // With the history effect, a path that a contact or a release restarted has a new
            // memory, which the particle pass did not see (stage 2 flew the path as it was).
            if let Some(m) = width
                && tr.seg.memory == NO_MEMORY
            {
                let out = &mut next.memory[i * m..(i + 1) * m];
                ctx.flight.fly_remembering(&tr.field, (tr.k, tr.r()), &tr.seg, t1 - tr.seg.t, out);
            }
            let (x, v) = clear_of_walls(ctx, tr.end.x, tr.end.v, tr.r());
            suspect |= !(x.is_finite() && v.is_finite());
            next.pos[i] = x;
            next.vel[i] = v;
            next.state[i] = tr.end.state;
            if ctx.flight.rotation() {
                // The same as stage 2's spin for a particle without contact in the step.
                next.omega[i] = ctx.spin_at(&tr, t1);
            }
            next.wall[i] = if tr.end.state == State::Free { NO_WALL } else { tr.seg.wall };
            if let Some((release_time, release_vel)) = tr.release {
                next.holds.push(WallHold { index: i as u32, release_time, release_vel });
            }
        }
        events.extend(r.events);
        lasting.extend(r.lasting);
    }
    suspect
}

/// Pushes a particle that an event left inside a wall (only possible when an island ran out of
/// its event budget, or by round-off) back out, without velocity into the wall.
fn clear_of_walls<M: Motion>(ctx: &Ctx<M>, mut x: DVec3, mut v: DVec3, r: f64) -> (DVec3, DVec3) {
    for wall in ctx.walls() {
        (x, v, _) = crate::walls::push_out(&wall.shape, x, v, r);
    }
    (x, v)
}
