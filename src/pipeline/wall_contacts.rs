//! Stages 4 and 5: locate each wall contact inside the step, apply the bounce rule, and
//! integrate the rest of the step from the contact point.

use super::{ContactEvent, Ctx, Flight, Motion, Other, Outcome, Scratch, Segment, fly};
use crate::contact::{locate_on_path, wall_impact};
use crate::particles::{NO_WALL, Particles, State};
use crate::walls::Surface;
use glam::DVec3;
use rayon::prelude::*;

/// Contacts handled for one particle in one step before it is stopped at the last one. Only a
/// particle trapped in a tight corner with a huge step reaches it.
const MAX_CONTACTS_PER_STEP: usize = 32;

/// How a candidate particle ends the step.
struct Resolution {
    i: usize,
    end: Flight,
    wall: u32,
    release: Option<(f64, DVec3)>,
    events: Vec<ContactEvent>,
}

/// Resolves the wall contacts of the broad phase's candidates in parallel, then writes the
/// results back and appends the events in particle order (independent of the thread count).
pub(crate) fn run<M: Motion>(
    ctx: &Ctx<M>,
    p: &mut Particles,
    t0: f64,
    t1: f64,
    scratch: &mut Scratch,
    events: &mut Vec<ContactEvent>,
) {
    let resolved: Vec<Resolution> = scratch
        .candidates
        .par_iter()
        .filter_map(|&i| resolve(ctx, p, scratch, i as usize, t0, t1))
        .collect();
    for r in resolved {
        scratch.next_pos[r.i] = r.end.x;
        scratch.next_vel[r.i] = r.end.v;
        scratch.next_state[r.i] = r.end.state;
        p.wall[r.i] = r.wall;
        if let Some((t, v)) = r.release {
            p.release_time[r.i] = t;
            p.release_vel[r.i] = v;
        }
        events.extend(r.events);
    }
}

/// The contacts of particle `i` in the step `[t0, t1]`; `None` when it touches nothing.
fn resolve<M: Motion>(
    ctx: &Ctx<M>,
    p: &Particles,
    scratch: &Scratch,
    i: usize,
    t0: f64,
    t1: f64,
) -> Option<Resolution> {
    let (k, d) = (p.kind[i] as usize, p.diameter[i]);
    let r = 0.5 * d;
    let kind = &ctx.kinds[k];
    let field = ctx.field(k, d);
    let mut seg = Segment {
        t: t0.max(p.release_time[i]),
        x: p.pos[i],
        v: p.vel[i],
        state: p.state[i],
        wall: p.wall[i],
    };
    let mut end = Flight {
        x: scratch.next_pos[i],
        v: scratch.next_vel[i],
        state: scratch.next_state[i],
    };
    let mut events = Vec::new();
    let mut release = None;
    for _ in 0..MAX_CONTACTS_PER_STEP {
        let h = t1 - seg.t;
        // 4. Narrow phase: the first wall the curved path reaches.
        let path = |s: f64| {
            let f = fly(ctx, &field, r, &seg, s);
            (f.x, f.v)
        };
        let hit = ctx
            .walls
            .iter()
            .enumerate()
            .filter(|&(w, _)| !(seg.state == State::Resting && seg.wall == w as u32))
            .filter_map(|(w, wall)| {
                let crossing = wall.shape.sweep(seg.x, end.x, r)?;
                let gap = |x: DVec3| wall.shape.gap(x, r).gap;
                let s = locate_on_path(path, gap, h, crossing, gap(end.x), r)?;
                Some((w, s))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((w, s)) = hit else {
            let wall = if end.state == State::Free {
                NO_WALL
            } else {
                seg.wall
            };
            return (!events.is_empty()).then_some(Resolution {
                i,
                end,
                wall,
                release,
                events,
            });
        };
        // 5. Response: the bounce rule at the contact point.
        let wall = &ctx.walls[w];
        let (x, v) = path(s);
        let g = wall.shape.gap(x, r);
        let (xc, n) = (x - g.gap * g.normal, g.normal);
        let tc = seg.t + s;
        let impact = wall_impact(kind, d, &wall.material, ctx.fluid, ctx.rule, v, n);
        events.push(ContactEvent {
            time: tc,
            id: p.id[i],
            other: Other::Wall(w as u32),
            normal_speed: (-v.dot(n)).max(0.0),
            st: impact.st,
            eps: impact.eps,
            contact_time: impact.contact_time,
            outcome: impact.outcome,
        });
        let w = w as u32;
        seg = match impact.outcome {
            Outcome::Bounced => Segment {
                t: tc,
                x: xc,
                v: impact.velocity,
                state: State::Free,
                wall: NO_WALL,
            },
            Outcome::Deposited => Segment {
                t: tc,
                x: xc,
                v: impact.velocity,
                state: State::Resting,
                wall: w,
            },
            Outcome::Held => {
                let t_release = tc + impact.contact_time;
                release = Some((t_release, impact.velocity));
                if t_release >= t1 {
                    let end = Flight {
                        x: xc,
                        v: DVec3::ZERO,
                        state: State::Held,
                    };
                    return Some(Resolution {
                        i,
                        end,
                        wall: w,
                        release,
                        events,
                    });
                }
                Segment {
                    t: t_release,
                    x: xc,
                    v: impact.velocity,
                    state: State::Free,
                    wall: NO_WALL,
                }
            }
        };
        end = fly(ctx, &field, r, &seg, t1 - seg.t);
    }
    // Out of contacts for this step: stop at the last contact point.
    let end = Flight {
        x: seg.x,
        v: seg.v,
        state: seg.state,
    };
    Some(Resolution {
        i,
        end,
        wall: seg.wall,
        release,
        events,
    })
}
