//! How long a run may be: the frames it writes and the steps it takes.
//!
//! A scene that asks for an absurd run is refused at load, so that a typo (`output_interval =
//! 1e-300`, which wrote a gigabyte of CSV in 30 s and would never end) costs nothing. The
//! limits are far beyond any useful run, and an explicit choice (`wetbounce run
//! --allow-long-run`, [`super::LoadOptions::allow_long_run`]) lifts them.

use super::error::fmt::approx;

/// Most output frames (`duration / output_interval`) a run may write: 10⁷. A frame is a row
/// per particle in trajectories.csv and a message in the MCAP: 10⁷ frames of one particle are
/// about 1 GB of CSV.
pub const MAX_FRAMES: f64 = 1e7;

/// Most time steps (`duration / dt`) a run may take: 10¹⁰. At the fastest measured rate, a
/// few 10⁷ particle steps per second, that is days of computing for a single particle.
pub const MAX_STEPS: f64 = 1e10;

/// Why a run is refused as too long.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TooLong {
    /// `duration / output_interval` frames, more than [`MAX_FRAMES`].
    #[error(
        "duration / output_interval is {} frames, more than the {} a run may write; raise the \
         output interval, or allow it with `wetbounce run --allow-long-run`",
        approx(*.0), approx(MAX_FRAMES)
    )]
    Frames(f64),
    /// `duration / dt` steps, more than [`MAX_STEPS`].
    #[error(
        "duration / dt is {} steps, more than the {} a run may take; shorten the run or raise \
         dt, or allow it with `wetbounce run --allow-long-run`",
        approx(*.0), approx(MAX_STEPS)
    )]
    Steps(f64),
}

/// Checks the frame and step counts of a run of `duration` (s) with frames every
/// `output_interval` (s) and time step `dt` (s): the frames first (the usual typo).
pub fn run_length(duration: f64, output_interval: f64, dt: f64) -> Result<(), TooLong> {
    let frames = duration / output_interval;
    if frames.is_nan() || frames > MAX_FRAMES {
        return Err(TooLong::Frames(frames));
    }
    let steps = duration / dt;
    if steps.is_nan() || steps > MAX_STEPS {
        return Err(TooLong::Steps(steps));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_at_the_limits_pass_and_beyond_them_are_refused_with_the_count() {
        assert_eq!(run_length(1e3, 1e-4, 1e-7), Ok(()));
        assert_eq!(run_length(1e3, 1e-4 * 0.999, 1e-3), Err(TooLong::Frames(1e3 / (1e-4 * 0.999))));
        let e = run_length(0.01, 1e-300, 1e-4).unwrap_err().to_string();
        assert!(e.starts_with("duration / output_interval is 1e298 frames, more than the 1e7"), "{e}");
        let e = run_length(1e8, 1e3, 1e-4).unwrap_err().to_string();
        assert!(e.starts_with("duration / dt is 1e12 steps, more than the 1e10"), "{e}");
    }
}
