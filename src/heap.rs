//! The angle of repose of a pile of particles on a floor **[ext]** (issue 16): a measurement
//! for tools and tests, not a stage of the step.
//!
//! Definition (docs/physics.md §9.2, "Heaps"): the floor is the lowest particle's bottom; the
//! pile's axis is vertical through its centroid (`x`, `y`: gravity along `−z`). The particles are
//! binned by their horizontal distance `r` from the axis, one mean diameter per bin, and each
//! bin's surface height is its highest particle's top above the floor. The flank is the bins
//! whose surface lies between 20 % and 80 % of the pile's height, from the summit outwards up
//! to the first bin below 20 %; the angle is `atan(−s)`, `s` the least-squares slope of height
//! against `r` over the flank. `None` when the flank has fewer than three bins.

use glam::DVec3;

/// A measured angle of repose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Repose {
    /// The angle of the flank above the horizontal (degrees).
    pub degrees: f64,
    /// The pile's height above the floor (m).
    pub height: f64,
    /// Bins in the flank's fit.
    pub bins: usize,
}

/// The angle of repose of the pile of particles at `pos` with diameters `diameter` (m).
pub fn angle_of_repose(pos: &[DVec3], diameter: &[f64]) -> Option<Repose> {
    let n = pos.len();
    if n < 10 {
        return None;
    }
    let d = diameter.iter().sum::<f64>() / n as f64;
    let floor = (0..n).map(|i| pos[i].z - 0.5 * diameter[i]).fold(f64::INFINITY, f64::min);
    let centre = pos.iter().fold(DVec3::ZERO, |s, &x| s + x) / n as f64;
    let radius = |x: DVec3| ((x.x - centre.x).powi(2) + (x.y - centre.y).powi(2)).sqrt();
    let bins = (pos.iter().map(|&x| radius(x)).fold(0.0, f64::max) / d) as usize + 1;
    let mut top = vec![0.0f64; bins];
    for i in 0..n {
        let b = (radius(pos[i]) / d) as usize;
        top[b] = top[b].max(pos[i].z + 0.5 * diameter[i] - floor);
    }
    let height = top.iter().copied().fold(0.0, f64::max);
    let summit = top.iter().position(|&h| h == height)?;
    let (low, high) = (0.2 * height, 0.8 * height);
    let mut pts = Vec::new();
    for (b, &h) in top.iter().enumerate().skip(summit) {
        if h < low {
            break;
        }
        if h <= high {
            pts.push(((b as f64 + 0.5) * d, h));
        }
    }
    if pts.len() < 3 {
        return None;
    }
    let k = pts.len() as f64;
    let (mr, mh) = (pts.iter().map(|p| p.0).sum::<f64>() / k, pts.iter().map(|p| p.1).sum::<f64>() / k);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mr) * (p.1 - mh)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mr).powi(2)).sum();
    Some(Repose { degrees: (-sxy / sxx).atan().to_degrees(), height, bins: pts.len() })
}
