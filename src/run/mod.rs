//! The run driver: steps a simulation to its end, feeding frames and events to the sinks, and
//! the signals that stop it cleanly ([`StopSignals`]).

pub mod checkpoint;
mod checkpoints;
mod driver;
pub mod resume;

pub use checkpoint::{CheckpointError, RunPosition};
pub use checkpoints::{CheckpointPolicy, Checkpoints, save_to};
pub use driver::{Driver, Ended};

use crate::output::{OutputError, Sink};
use crate::pipeline::Simulation;
use std::fmt;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
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
    /// True when stopped early by `stop`, or by a particle outside the flow field
    /// (`Record::left_field`).
    pub interrupted: bool,
}

/// A run stopped by output errors: where it stopped, and every error, the first (the one that
/// stopped it) first, then those of the sinks that could not be finished. Each names its file.
#[derive(Debug, thiserror::Error)]
#[error("{}", list(.errors))]
pub struct RunFailed {
    /// How far the run went.
    pub report: RunReport,
    /// The errors, one per file at most.
    pub errors: Vec<OutputError>,
}

fn list(errors: &[OutputError]) -> String {
    errors.iter().map(ToString::to_string).collect::<Vec<_>>().join("\n")
}

/// Runs `sim` to `duration` (s), with a frame to every sink at `t = 0` and at each multiple of
/// `output_interval` (s) — exactly, whatever `Δt` — and at the end. After every step the sinks
/// get [`Sink::step`] and the step's events. Setting `stop` (a signal, [`StopSignals`]) ends the
/// run after the current step, with a last frame at that time (or at once, after the frame at
/// `t = 0`, when it is set before the run starts).
///
/// The first sink error stops the run too. Every sink is finished (flushed, closed) in every
/// case — the others still finish after one failed — so no output is lost or left unreadable
/// beyond the failing file; the error and those of any sink that could not be finished come
/// back in [`RunFailed`], with how far the run went.
pub fn run(
    sim: &mut Simulation,
    duration: f64,
    output_interval: f64,
    sinks: &mut [&mut dyn Sink],
    stop: &AtomicBool,
) -> Result<RunReport, RunFailed> {
    let plan = Plan { duration, output_interval, from: None, checkpoints: None, steps: None };
    run_plan(sim, plan, sinks, stop)
}

/// How a run's loop moves its simulation on: one process steps it ([`OneProcess`]); a run split
/// over ranks steps each rank's part and gathers what the sinks read into the simulation the
/// loop holds (`crate::ranks`).
pub trait Steps {
    /// Steps `sim` to `target` (s), at most one step ahead.
    fn advance(&mut self, sim: &mut Simulation, target: f64);
    /// Before the sinks get a frame: `sim` holds every particle.
    fn before_frame(&mut self, _sim: &mut Simulation) {}
    /// Whether the run stops, given whether this process was asked to (a signal, a particle
    /// outside the flow field): ranks stop together.
    fn stopping(&mut self, asked: bool) -> bool {
        asked
    }
    /// Whether a checkpoint is taken now, given whether this process would take one: ranks
    /// take it together (only rank 0 writes it).
    fn checkpointing(&mut self, due: bool) -> bool {
        due
    }
    /// Before a checkpoint is taken: `sim` holds the whole world.
    fn before_checkpoint(&mut self, _sim: &mut Simulation) {}
}

/// One process steps the whole simulation.
#[derive(Debug, Default, Clone, Copy)]
pub struct OneProcess;

impl Steps for OneProcess {
    fn advance(&mut self, sim: &mut Simulation, target: f64) {
        sim.advance_to(target);
    }
}

/// What [`run_plan`] runs: to `duration` with a frame every `output_interval` (s), from the
/// start or from where a checkpoint left the run loop (`from`), taking checkpoints or not.
pub struct Plan<'a> {
    /// Simulated time to reach (s).
    pub duration: f64,
    /// Simulated time between frames (s).
    pub output_interval: f64,
    /// Where a resumed run's loop stands; `None` for a run from its start.
    pub from: Option<RunPosition>,
    /// The checkpoints to take; `None` for none.
    pub checkpoints: Option<&'a mut Checkpoints>,
    /// How the simulation is stepped; `None`: by this process ([`OneProcess`]).
    pub steps: Option<&'a mut dyn Steps>,
}

/// [`run`], from a checkpoint's position and taking checkpoints as `plan` says. A checkpoint is
/// taken after a whole step, once the sinks have its events, when one is due
/// ([`Checkpoints::due`]), and when `stop` ends the run: within an interval, before the stop's
/// last frame, so that a resumed run, which cuts the files at the checkpoint, writes the files
/// of a run never stopped; at a frame (a signal during its write), after it. A checkpoint that
/// cannot be written stops the run as an output error does.
pub fn run_plan(
    sim: &mut Simulation,
    plan: Plan<'_>,
    sinks: &mut [&mut dyn Sink],
    stop: &AtomicBool,
) -> Result<RunReport, RunFailed> {
    let Plan { duration, output_interval, from, mut checkpoints, steps } = plan;
    let mut one = OneProcess;
    let steps: &mut dyn Steps = match steps {
        Some(s) => s,
        None => &mut one,
    };
    let start = Instant::now();
    let mut at =
        from.unwrap_or(RunPosition { lost_reported: sim.record.lost.len() as u64, ..Default::default() });
    let wall_before = at.wall_time;
    // Takes a checkpoint when this process would (`due`) or another rank would: all together.
    let checkpoint_if = |due: bool,
                         steps: &mut dyn Steps,
                         sim: &mut Simulation,
                         checkpoints: &mut Option<&mut Checkpoints>,
                         at: &mut RunPosition,
                         sinks: &mut [&mut dyn Sink]|
     -> Result<(), OutputError> {
        if steps.checkpointing(due) {
            steps.before_checkpoint(sim);
            if let Some(c) = checkpoints.as_deref_mut() {
                at.wall_time = wall_before + start.elapsed().as_secs_f64();
                c.take(sim, *at, sinks)?;
            }
        }
        Ok(())
    };
    let result = (|| {
        // A resumed run stands either just after frame `k` (at a frame) or on its way to it.
        let mut on_the_way = from.is_some_and(|p| !p.at_frame);
        let mut frame_written = from.is_some_and(|p| p.at_frame);
        loop {
            if !on_the_way {
                if !frame_written {
                    steps.before_frame(sim);
                    for s in sinks.iter_mut() {
                        s.frame(sim)?;
                    }
                    at.frames += 1;
                }
                frame_written = false;
                at.at_frame = true;
                if sim.world.time >= duration {
                    let due = checkpoints.as_deref().is_some_and(Checkpoints::periodic);
                    checkpoint_if(due, steps, sim, &mut checkpoints, &mut at, sinks)?;
                    return Ok(false);
                }
                // A signal that came before the first step (while the scene loaded) or while
                // this frame was written stops the run here, with the frame as its last. The
                // checkpoint a stop takes is taken after it: a run resumed from it goes on
                // without writing the frame again (a signal landing in the frame's write once
                // left no checkpoint at all).
                if steps.stopping(stop.load(Ordering::Relaxed)) {
                    checkpoint_if(checkpoints.is_some(), steps, sim, &mut checkpoints, &mut at, sinks)?;
                    return Ok(true);
                }
                at.k += 1;
                at.at_frame = false;
            }
            on_the_way = false;
            let next = (at.k as f64 * output_interval).min(duration);
            while sim.world.time < next {
                // One step at a time, so that a signal stops within a step; the last step of an
                // interval lands on `next` exactly (`advance_to` shortens or stretches it).
                let (t, dt) = (sim.world.time, sim.setup.dt);
                let target = if next - t <= 1.000_000_001 * dt { next } else { t + dt };
                steps.advance(sim, target);
                for s in sinks.iter_mut() {
                    s.step(sim)?;
                }
                flush_events(sim, sinks)?;
                let lost_reported = at.lost_reported as usize;
                if sim.record.lost.len() > lost_reported {
                    for s in sinks.iter_mut() {
                        s.lost(sim, &sim.record.lost[lost_reported..])?;
                    }
                    at.lost_reported = sim.record.lost.len() as u64;
                }
                // A particle outside a flow field whose outside is an error ends the run like a
                // stop signal, with a last frame; the caller reports `record.left_field`.
                let stopping =
                    steps.stopping(stop.load(Ordering::Relaxed) || sim.record.left_field.is_some());
                let due = checkpoints.as_deref().is_some_and(|c| stopping || c.due(sim));
                checkpoint_if(due, steps, sim, &mut checkpoints, &mut at, sinks)?;
                if stopping {
                    steps.before_frame(sim);
                    for s in sinks.iter_mut() {
                        s.frame(sim)?;
                    }
                    at.frames += 1;
                    return Ok(true);
                }
            }
        }
    })();
    let mut errors: Vec<OutputError> = Vec::new();
    // An output error that stops the run before its end interrupts it as a signal does
    // (summary.json said `"interrupted": false` for such a run: issue 25, finding 13).
    let interrupted = result.unwrap_or_else(|e| {
        errors.push(e);
        sim.world.time < duration
    });
    // The last checkpoint reaches the disk before the run ends.
    if let Some(c) = checkpoints
        && let Err(e) = c.wait()
    {
        errors.push(e);
    }
    // Every sink is finished, whatever happened to the others. A file that already failed may
    // fail again on its last flush: it is named once.
    for s in sinks.iter_mut() {
        if let Err(e) = s.finish()
            && !errors.iter().any(|seen| seen.path == e.path)
        {
            errors.push(e);
        }
    }
    let report = RunReport {
        time: sim.world.time,
        steps: sim.world.steps,
        wall_time: Duration::from_secs_f64(wall_before) + start.elapsed(),
        frames: at.frames,
        interrupted,
    };
    if errors.is_empty() { Ok(report) } else { Err(RunFailed { report, errors }) }
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
    sim.record.event_islands.clear();
    Ok(())
}

/// A signal that stops a run cleanly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StopSignal {
    /// The signal's number (SIGINT 2, SIGTERM 15, SIGHUP 1 on Linux).
    pub number: i32,
    /// Its name, `SIGINT`, `SIGTERM` or `SIGHUP`.
    pub name: &'static str,
}

impl StopSignal {
    /// The exit status of a run it stopped: 128 + the signal's number, what a shell reports for
    /// a process the signal killed (130, 143, 129), so scripts and schedulers see the same code
    /// whether the run was stopped cleanly or killed.
    pub fn exit_status(self) -> u8 {
        (128 + self.number).clamp(0, 255) as u8
    }
}

impl fmt::Display for StopSignal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name)
    }
}

/// The signals that stop a run cleanly: SIGINT (Ctrl-C), SIGTERM (`kill`, `timeout`, batch
/// schedulers, container runtimes) and, on Unix, SIGHUP (the terminal closed).
pub const STOP_SIGNALS: &[StopSignal] = &[
    StopSignal { number: signal_hook::consts::SIGINT, name: "SIGINT" },
    StopSignal { number: signal_hook::consts::SIGTERM, name: "SIGTERM" },
    #[cfg(unix)]
    StopSignal { number: signal_hook::consts::SIGHUP, name: "SIGHUP" },
];

/// How long after the first stop signal a second one still counts as the same stop. GNU
/// `timeout` sends SIGTERM to the run and then to its whole process group, `kill -TERM -PGID`
/// and batch schedulers may reach the run twice as well: the copies come within microseconds and
/// must not turn the graceful stop into an exit with cut files (issue 25, finding 10). A person
/// who insists presses Ctrl-C again after a pause.
pub const REPEAT_SIGNAL_GRACE: Duration = Duration::from_secs(2);

/// The process's handlers for [`STOP_SIGNALS`]: the first such signal sets [`Self::flag`] (the
/// `stop` of [`run`]: the run finishes its step, writes a last frame and closes every file) and
/// records which signal it was; a second one, of any of them, coming at least
/// [`REPEAT_SIGNAL_GRACE`] after the first, exits at once with 128 + its number, without closing
/// the files — which then still hold every frame up to the last one, since the sinks flush at
/// every frame. Copies of the first signal that come sooner are part of the same stop.
#[derive(Debug)]
pub struct StopSignals {
    flag: Arc<AtomicBool>,
    received: Arc<AtomicUsize>,
}

impl StopSignals {
    /// Installs the handlers (replacing the default action, which kills the process with its
    /// files cut). Call it once, early: a signal that comes before is not caught.
    pub fn install() -> std::io::Result<Self> {
        let flag = Arc::new(AtomicBool::new(false));
        let received = Arc::new(AtomicUsize::new(0));
        let numbers: Vec<i32> = STOP_SIGNALS.iter().map(|s| s.number).collect();
        // signal-hook's iterator: the handler only wakes this thread, which may then read the
        // clock and decide, with no code of ours inside the signal handler (and no `unsafe`).
        let mut incoming = signal_hook::iterator::Signals::new(&numbers)?;
        let (stop, which) = (flag.clone(), received.clone());
        std::thread::Builder::new().name("stop-signals".into()).spawn(move || {
            let mut first: Option<Instant> = None;
            for number in incoming.forever() {
                match first {
                    None => {
                        // The signal's number first, then the flag: whoever sees the flag sees
                        // which signal set it.
                        which.store(number as usize, Ordering::SeqCst);
                        stop.store(true, Ordering::SeqCst);
                        first = Some(Instant::now());
                    }
                    Some(at) if at.elapsed() >= REPEAT_SIGNAL_GRACE => {
                        signal_hook::low_level::exit(128 + number)
                    }
                    // The same stop delivered twice (`timeout`, a process group): already stopping.
                    Some(_) => {}
                }
            }
        })?;
        Ok(StopSignals { flag, received })
    }

    /// Set by the first stop signal: pass it to [`run`] as `stop`.
    pub fn flag(&self) -> &AtomicBool {
        &self.flag
    }

    /// The stop signal that came, if any (the last one, if several came at once).
    pub fn received(&self) -> Option<StopSignal> {
        let n = self.received.load(Ordering::SeqCst);
        STOP_SIGNALS.iter().copied().find(|s| s.number as usize == n && n != 0)
    }
}
