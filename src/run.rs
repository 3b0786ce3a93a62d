//! The run driver: steps a simulation to its end, feeding frames and events to the sinks.

use crate::output::{OutputError, Sink};
use crate::pipeline::Simulation;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub struct RunReport {
    /// Simulated time reached (s).
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Wall-clock time of the run.
    pub wall_time: Duration,
    /// Output frames written.
    pub frames: u64,
    /// True when stopped early by `stop`.
    pub interrupted: bool,
}

/// Runs `sim` to `duration` (s), with a frame to every sink at `t = 0` and at each multiple of
/// `output_interval` (s) — exactly, whatever `Δt` — and at the end. After every step the sinks
/// get [`Sink::step`] and the step's events. Setting `stop` (Ctrl-C) ends the run after the
/// current step, with a last frame at that time; every sink is finished (flushed, closed) in
/// every case, even after a sink error, so no output is lost or left unreadable.
pub fn run(
    sim: &mut Simulation,
    duration: f64,
    output_interval: f64,
    sinks: &mut [&mut dyn Sink],
    stop: &AtomicBool,
) -> Result<RunReport, OutputError> {
    let start = Instant::now();
    let mut frames = 0;
    let mut lost_reported = sim.record.lost.len();
    let result = (|| {
        let mut k: u64 = 0;
        loop {
            for s in sinks.iter_mut() {
                s.frame(sim)?;
            }
            frames += 1;
            if sim.world.time >= duration {
                return Ok(false);
            }
            k += 1;
            let next = (k as f64 * output_interval).min(duration);
            while sim.world.time < next {
                // One step at a time, so that Ctrl-C stops within a step; the last step of an
                // interval lands on `next` exactly (`advance_to` shortens or stretches it).
                let (t, dt) = (sim.world.time, sim.setup.dt);
                let target = if next - t <= 1.000_000_001 * dt { next } else { t + dt };
                sim.advance_to(target);
                for s in sinks.iter_mut() {
                    s.step(sim)?;
                }
                flush_events(sim, sinks)?;
                if sim.record.lost.len() > lost_reported {
                    for s in sinks.iter_mut() {
                        s.lost(sim, &sim.record.lost[lost_reported..])?;
                    }
                    lost_reported = sim.record.lost.len();
                }
                if stop.load(Ordering::Relaxed) {
                    for s in sinks.iter_mut() {
                        s.frame(sim)?;
                    }
                    frames += 1;
                    return Ok(true);
                }
            }
        }
    })();
    let finished: Result<(), OutputError> = sinks.iter_mut().try_for_each(|s| s.finish());
    let interrupted = result?;
    finished?;
    Ok(RunReport {
        time: sim.world.time,
        steps: sim.world.steps,
        wall_time: start.elapsed(),
        frames,
        interrupted,
    })
}

fn flush_events(sim: &mut Simulation, sinks: &mut [&mut dyn Sink]) -> Result<(), OutputError> {
    if sim.record.events.is_empty() {
        return Ok(());
    }
    let events = std::mem::take(&mut sim.record.events);
    for s in sinks.iter_mut() {
        s.events(sim, &events)?;
    }
    sim.record.events = events;
    sim.record.events.clear();
    Ok(())
}
