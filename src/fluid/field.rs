//! A carrier flow read from files that a CFD code wrote (docs/physics.md §7): the grid, the
//! velocity at its nodes (one set per snapshot of a time series), and what happens outside it.
//!
//! The data live in one [`Field`] behind an `Arc` ([`super::Flow::Field`]), so the scene's
//! `Flow` stays cheap to clone; the hot loop sees a [`FieldAt`], a reference and the step's
//! snapshot weights, which is `Copy` like the analytic flows.

mod appended;
pub mod read;
pub mod structured;
pub mod unstructured;
mod vet;

use super::FlowField;
use crate::numeric::lanes::{DVec3x4, PointMap, Vector};
use glam::DVec3;
use structured::{Stencil, Structured};
use unstructured::{NO_TET, Unstructured};

/// Where the file's velocity values sit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DataAt {
    /// At the grid's points.
    Point,
    /// At its cells (their centres).
    Cell,
}

/// What the flow is at a point outside the field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outside {
    /// The run stops with an error naming the particle, its position and the time (the
    /// velocity inside the step is the nearest point's until then).
    Error,
    /// The fluid is at rest there.
    Zero,
    /// The velocity of the field's nearest point.
    Nearest,
}

impl Outside {
    /// The scene's name of the policy.
    pub fn name(self) -> &'static str {
        match self {
            Outside::Error => "error",
            Outside::Zero => "zero",
            Outside::Nearest => "nearest",
        }
    }
}

/// The frame of a 2-D (r, z) table: the field at `x` is the table's at `r`, the distance from
/// the axis, and `z`, the distance along it, turned about the axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axisymmetric {
    /// A point on the axis, where the table's z = 0 (m).
    pub point: DVec3,
    /// Unit direction of the axis (the table's z).
    pub axis: DVec3,
}

/// The grid of a field.
#[derive(Debug, Clone)]
pub enum Grid {
    /// Image data or a rectilinear grid: trilinear.
    Structured(Structured),
    /// Cells cut into tetrahedra: barycentric.
    Unstructured(Unstructured),
}

/// One snapshot of the field.
#[derive(Debug, Clone)]
pub struct Snapshot {
    /// Its time (s).
    pub time: f64,
    /// Velocity per node of the grid (m/s); `(u_r, u_θ, u_z)` for an axisymmetric table.
    pub values: Vec<DVec3>,
}

/// What `wetbounce check` says about a field, computed when it is read.
#[derive(Debug, Clone, Default)]
pub struct FieldInfo {
    /// The files, in time order.
    pub files: Vec<std::path::PathBuf>,
    /// The format's name.
    pub format: String,
    /// The velocity array and where it sits (`"U" (point data)`).
    pub array: String,
    /// Cells of the grid.
    pub cells: usize,
    /// Nodes carrying a value.
    pub nodes: usize,
    /// Lower and upper corner of the grid (in the table's frame for an axisymmetric table).
    pub bounds: (DVec3, DVec3),
    /// Smallest and largest speed over the nodes and snapshots (m/s).
    pub speed_range: (f64, f64),
    /// Smallest and largest grid spacing or cell size (m).
    pub spacing: (f64, f64),
    /// The largest velocity gradient's size over the cells, `max |∂u_i/∂x_j|` (1/s).
    pub largest_gradient: f64,
}

/// A velocity field read from files.
#[derive(Debug, Clone)]
pub struct Field {
    /// The grid, shared by every snapshot.
    pub grid: Grid,
    /// The snapshots, in increasing time; one for a steady field.
    pub snapshots: Vec<Snapshot>,
    /// The period (s) of a periodic series: after the last snapshot the field goes back to the
    /// first, which it reaches at the first's time plus the period.
    pub period: Option<f64>,
    /// What the flow is outside the grid.
    pub outside: Outside,
    /// The frame of a 2-D (r, z) table, `None` for a 3-D field.
    pub axisymmetric: Option<Axisymmetric>,
    /// What the files were.
    pub info: FieldInfo,
}

/// A point outside the field where the policy is [`Outside::Error`]: the first particle found
/// there (in index order) at the end of a step.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error, serde::Serialize, serde::Deserialize)]
#[error(
    "particle {id} left the flow field at t = {time} s: position ({}, {}, {}) m is outside the field \
     (fluid.flow.outside = \"error\"; \"nearest\" or \"zero\" let it go on)",
    position.x, position.y, position.z
)]
pub struct OutsideField {
    /// The particle's id.
    pub id: u32,
    /// Its position (m).
    pub position: DVec3,
    /// The time (s).
    pub time: f64,
}

impl Field {
    /// A field of these snapshots on `grid`; fills in what [`FieldInfo`] measures (cells,
    /// nodes, bounds, speeds, spacing, gradient) over `info`'s files, format and array.
    pub fn new(
        grid: Grid,
        snapshots: Vec<Snapshot>,
        period: Option<f64>,
        outside: Outside,
        axisymmetric: Option<Axisymmetric>,
        mut info: FieldInfo,
    ) -> Field {
        let (cells, nodes, bounds, spacing) = match &grid {
            Grid::Structured(g) => {
                let d = g.dims();
                let cells = d.iter().map(|&n| (n - 1).max(1)).product();
                let lo = DVec3::new(g.axes[0].lo, g.axes[1].lo, g.axes[2].lo);
                let hi = DVec3::new(g.axes[0].hi, g.axes[1].hi, g.axes[2].hi);
                let largest =
                    g.axes.iter().map(|a| a.nodes.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max));
                (cells, d.iter().product(), (lo, hi), (g.smallest_spacing(), largest.fold(0.0, f64::max)))
            }
            Grid::Unstructured(g) => {
                (g.cells(), g.nodes.len(), (g.bounds.mins, g.bounds.maxs), g.cell_size_range)
            }
        };
        let speeds = snapshots.iter().flat_map(|s| s.values.iter().map(|v| v.length()));
        let speed_range = speeds.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        info.cells = cells;
        info.nodes = nodes;
        info.bounds = bounds;
        info.spacing = spacing;
        info.speed_range = speed_range;
        let mut field = Field { grid, snapshots, period, outside, axisymmetric, info };
        field.info.largest_gradient = field.largest_gradient();
        field
    }

    /// The field at time `t` (s), for the hot loop: the two snapshots around `t` and the weight
    /// of the second, linear in time.
    pub fn at(&self, t: f64) -> FieldAt<'_> {
        let s = &self.snapshots;
        let n = s.len();
        let (first, last) = (s[0].time, s[n - 1].time);
        if n == 1 {
            return FieldAt { field: self, a: 0, b: 0, w: 0.0, hint: NO_TET };
        }
        let t = match self.period {
            Some(p) => first + (t - first).rem_euclid(p),
            None => t.clamp(first, last),
        };
        if t >= last {
            // Only a periodic series gets here with t > last: from the last snapshot back to
            // the first, reached at first + period.
            return match self.period {
                Some(p) if t > last => {
                    FieldAt { field: self, a: n - 1, b: 0, w: (t - last) / (first + p - last), hint: NO_TET }
                }
                _ => FieldAt { field: self, a: n - 1, b: n - 1, w: 0.0, hint: NO_TET },
            };
        }
        let b = s.partition_point(|x| x.time <= t).clamp(1, n - 1);
        let a = b - 1;
        FieldAt { field: self, a, b, w: (t - s[a].time) / (s[b].time - s[a].time), hint: NO_TET }
    }

    /// The field at time `t` (s) on a structured grid, for the hot loop: [`Field::at`] with the
    /// snapshots' values resolved once; `None` on an unstructured grid.
    pub fn structured_at(&self, t: f64) -> Option<StructuredAt<'_>> {
        let Grid::Structured(grid) = &self.grid else {
            return None;
        };
        let at = self.at(t);
        Some(StructuredAt {
            field: self,
            grid,
            before: &self.snapshots[at.a].values,
            after: &self.snapshots[at.b].values,
            w: at.w,
            zero_outside: self.outside == Outside::Zero,
        })
    }

    /// The point of the grid's frame that `x` maps to, and for an axisymmetric table the
    /// radial and azimuthal unit vectors there.
    #[inline]
    fn to_grid(&self, x: DVec3) -> (DVec3, Option<(DVec3, DVec3, DVec3)>) {
        match self.axisymmetric {
            None => (x, None),
            Some(f) => {
                let rel = x - f.point;
                let along = rel.dot(f.axis);
                let perp = rel - along * f.axis;
                let r = perp.length();
                // On the axis u_r = 0 and u_θ = 0 (the table says so), so any radial direction
                // does; zero keeps the value finite.
                let e_r = if r > 0.0 { perp / r } else { DVec3::ZERO };
                (DVec3::new(r, 0.0, along), Some((e_r, f.axis.cross(e_r), f.axis)))
            }
        }
    }

    /// Whether `x` lies in the field.
    pub fn contains(&self, x: DVec3) -> bool {
        let (q, _) = self.to_grid(x);
        match &self.grid {
            Grid::Structured(g) => g.contains(q),
            Grid::Unstructured(g) => g.contains(q),
        }
    }

    /// How far `x` lies outside the field (m), 0 inside: for `wetbounce check`, which must not
    /// call a point on the field's boundary outside for a rounding error.
    pub fn distance_outside(&self, x: DVec3) -> f64 {
        let (q, _) = self.to_grid(x);
        match &self.grid {
            Grid::Structured(g) => (g.clamp(q) - q).length(),
            Grid::Unstructured(g) => g.distance_outside(q),
        }
    }

    /// Whether lookups in this field walk from a remembered tetrahedron (an unstructured
    /// grid): the particles then carry one ([`crate::particles::Particles::tet`]).
    pub fn walks(&self) -> bool {
        matches!(self.grid, Grid::Unstructured(_))
    }

    /// The tetrahedron of an unstructured grid holding `x`, walking from tetrahedron `start`;
    /// [`NO_TET`] outside the grid (and on a structured grid).
    pub fn tet_of(&self, start: u32, x: DVec3) -> u32 {
        match &self.grid {
            Grid::Structured(_) => NO_TET,
            Grid::Unstructured(g) => g.tet_of(start, self.to_grid(x).0),
        }
    }

    /// The stencil at `x`'s grid point (an unstructured grid's lookup walking from tetrahedron
    /// `hint`) without its gradient (the velocity's), whether the point is inside, and the
    /// axisymmetric frame.
    #[inline]
    fn stencil(&self, x: DVec3, hint: u32) -> (Stencil, bool, Option<(DVec3, DVec3, DVec3)>) {
        let (q, frame) = self.to_grid(x);
        let (s, inside) = match &self.grid {
            Grid::Structured(g) => {
                let inside = g.contains(q);
                (g.weights(if inside { q } else { g.clamp(q) }), inside)
            }
            Grid::Unstructured(g) => match g.stencil_from(hint, q, false) {
                Ok(s) => (s, true),
                Err(s) => (s, false),
            },
        };
        (s, inside, frame)
    }

    /// The velocity (m/s) at `x` at time `t` (s), for code outside the hot loop: the hot
    /// loop's lookup ([`StructuredAt`] on a structured grid, [`FieldAt`] otherwise).
    pub fn velocity(&self, x: DVec3, t: f64) -> DVec3 {
        match self.structured_at(t) {
            Some(s) => s.velocity(x),
            None => self.at(t).velocity(x),
        }
    }

    /// The velocity gradient at `x` at time `t`: `J[j] = ∂u/∂x_j` (1/s) in the world frame, by
    /// central differences of the interpolated velocity over a thousandth of the smallest grid
    /// spacing. Differencing the interpolant (rather than the stencil's own gradient) works the
    /// same for every grid and for an axisymmetric table, whose frame turns with the position;
    /// inside a cell it is the interpolant's exact derivative up to rounding, on a cell face the
    /// mean of the two sides.
    pub fn gradient(&self, x: DVec3, t: f64) -> [DVec3; 3] {
        match self.structured_at(t) {
            Some(s) => central_gradient(&s, self.info.spacing.0, x),
            None => self.at(t).gradient(x),
        }
    }

    /// The field at time `t` (s) with its material acceleration, for the fluid-acceleration
    /// effect: [`Field::at`], and the time slope of the two snapshots around `t`.
    pub fn accelerating(&self, t: f64) -> Accelerating<'_> {
        let at = self.at(t);
        let (ta, tb) = (self.snapshots[at.a].time, self.snapshots[at.b].time);
        let interval = match self.period {
            // From the last snapshot back to the first, reached at first + period.
            Some(p) if at.b < at.a => self.snapshots[0].time + p - ta,
            _ => tb - ta,
        };
        // One snapshot, or a series held at its ends: the field does not change there.
        let inv_interval = if at.a != at.b && interval > 0.0 { 1.0 / interval } else { 0.0 };
        Accelerating { at, inv_interval }
    }

    /// The material acceleration `Du/Dt = ∂u/∂t + (u·∇)u` (m/s²) at `x` at time `t` (s), for
    /// code outside the hot loop ([`Accelerating`]).
    pub fn material_acceleration(&self, x: DVec3, t: f64) -> DVec3 {
        self.accelerating(t).material_acceleration(x)
    }

    /// Half the vorticity `½ ∇×u` at `x` at time `t` (rad/s), from [`Field::gradient`].
    pub fn half_vorticity(&self, x: DVec3, t: f64) -> DVec3 {
        let [dx, dy, dz] = self.gradient(x, t);
        0.5 * DVec3::new(dy.z - dz.y, dz.x - dx.z, dx.y - dy.x)
    }

    /// `(∇u)ᵀ`-free form of the interpolant's velocity gradient at `x`: `J[j] = ∂u/∂x_j` of
    /// the grid's values (1/s), in the grid's frame, snapshot `k`; for [`FieldInfo`].
    fn gradient_in_grid(&self, s: &Stencil, k: usize) -> [DVec3; 3] {
        let v = &self.snapshots[k].values;
        let mut j = [DVec3::ZERO; 3];
        for i in 0..8 {
            let u = v[s.nodes[i] as usize];
            j[0] += s.gradient[i].x * u;
            j[1] += s.gradient[i].y * u;
            j[2] += s.gradient[i].z * u;
        }
        j
    }

    /// The largest `|∂u_i/∂x_j|` (1/s) over the grid's cells, sampled at each cell's centre
    /// for the stiffness of the flow (`1/|∇u|` is its shortest time scale).
    pub fn largest_gradient(&self) -> f64 {
        let centres: Vec<DVec3> = match &self.grid {
            Grid::Structured(g) => {
                let mid = |a: &structured::Axis| -> Vec<f64> {
                    if a.nodes.len() == 1 {
                        a.nodes.clone()
                    } else {
                        a.nodes.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
                    }
                };
                let (xs, ys, zs) = (mid(&g.axes[0]), mid(&g.axes[1]), mid(&g.axes[2]));
                let mut c = Vec::with_capacity(xs.len() * ys.len() * zs.len());
                for &z in &zs {
                    for &y in &ys {
                        for &x in &xs {
                            c.push(DVec3::new(x, y, z));
                        }
                    }
                }
                c
            }
            Grid::Unstructured(g) => g.nodes[g.points..].to_vec(),
        };
        let mut largest = 0.0f64;
        for q in centres {
            let s = match &self.grid {
                Grid::Structured(g) => g.stencil(q),
                Grid::Unstructured(g) => match g.stencil(q) {
                    Ok(s) | Err(s) => s,
                },
            };
            for k in 0..self.snapshots.len() {
                let j = self.gradient_in_grid(&s, k);
                for c in j {
                    largest = largest.max(c.abs().max_element());
                }
                if let Some(_f) = self.axisymmetric {
                    // u_r / r, the hoop strain rate, is a gradient too in 3-D.
                    let v = self.value(&s, k, 0, 0.0);
                    if q.x > 0.0 {
                        largest = largest.max((v.x / q.x).abs().max((v.y / q.x).abs()));
                    }
                }
            }
        }
        largest
    }

    #[inline]
    fn value(&self, s: &Stencil, a: usize, b: usize, w: f64) -> DVec3 {
        let va = &self.snapshots[a].values;
        let mut u = DVec3::ZERO;
        if w == 0.0 {
            for i in 0..8 {
                u += s.weights[i] * va[s.nodes[i] as usize];
            }
        } else {
            let vb = &self.snapshots[b].values;
            for i in 0..8 {
                let n = s.nodes[i] as usize;
                u += s.weights[i] * ((1.0 - w) * va[n] + w * vb[n]);
            }
        }
        u
    }
}

/// A [`Field`] at one time, as a [`FlowField`].
#[derive(Debug, Clone, Copy)]
pub struct FieldAt<'a> {
    field: &'a Field,
    a: usize,
    b: usize,
    w: f64,
    /// On an unstructured grid, the tetrahedron the lookups walk from ([`NO_TET`]: the search
    /// tree): one particle's, set by [`FlowField::hinted`].
    hint: u32,
}

/// The velocity gradient `J[j] = ∂u/∂x_j` (1/s) of `flow` at `x`, by central differences over
/// a thousandth of `spacing`, the field's smallest grid spacing (m) ([`Field::gradient`]).
#[inline]
fn central_gradient(flow: &impl FlowField, spacing: f64, x: DVec3) -> [DVec3; 3] {
    let h = 1e-3 * spacing.max(f64::MIN_POSITIVE);
    [DVec3::X, DVec3::Y, DVec3::Z].map(|e| (flow.velocity(x + h * e) - flow.velocity(x - h * e)) / (2.0 * h))
}

impl FieldAt<'_> {
    /// The velocity gradient `J[j] = ∂u/∂x_j` (1/s) at `x`, by central differences of the
    /// interpolant over a thousandth of the smallest grid spacing ([`Field::gradient`]).
    #[inline]
    pub fn gradient(&self, x: DVec3) -> [DVec3; 3] {
        central_gradient(self, self.field.info.spacing.0, x)
    }

    /// The same field at snapshot `k` alone.
    #[inline]
    fn snapshot(&self, k: usize) -> FieldAt<'_> {
        FieldAt { field: self.field, a: k, b: k, w: 0.0, hint: self.hint }
    }
}

/// A [`Field`] at one time with its material acceleration, as a [`FlowField`]: the flow of a
/// field scene with the fluid-acceleration effect **[ext]** (docs/physics.md §7.2). Its velocity is
/// [`FieldAt`]'s; `Du/Dt = ∂u/∂t + (u·∇)u` with `∂u/∂t` the exact time derivative of the
/// linear-in-time interpolation (the two snapshots' difference over their interval) and `∇u`
/// by central differences of the interpolant ([`FieldAt::gradient`]): eight more
/// interpolations per evaluation.
#[derive(Debug, Clone, Copy)]
pub struct Accelerating<'a> {
    at: FieldAt<'a>,
    /// `1/(t_b − t_a)` of the two snapshots around the time (1/s); 0 when the field is steady
    /// there.
    inv_interval: f64,
}

impl FlowField for Accelerating<'_> {
    const ACCELERATES: bool = true;
    const HINTED: bool = true;

    #[inline]
    fn hinted(self, tet: u32) -> Self {
        Accelerating { at: self.at.hinted(tet), ..self }
    }

    #[inline]
    fn velocity(&self, x: DVec3) -> DVec3 {
        self.at.velocity(x)
    }

    #[inline]
    fn material_acceleration(&self, x: DVec3) -> DVec3 {
        let at = &self.at;
        let u = at.velocity(x);
        let [jx, jy, jz] = at.gradient(x);
        let convective = u.x * jx + u.y * jy + u.z * jz;
        if self.inv_interval == 0.0 {
            return convective;
        }
        let unsteady = (at.snapshot(at.b).velocity(x) - at.snapshot(at.a).velocity(x)) * self.inv_interval;
        unsteady + convective
    }
}

impl FlowField for FieldAt<'_> {
    const HINTED: bool = true;

    #[inline]
    fn hinted(self, tet: u32) -> Self {
        FieldAt { hint: tet, ..self }
    }

    #[inline]
    fn velocity(&self, x: DVec3) -> DVec3 {
        let f = self.field;
        let (s, inside, frame) = f.stencil(x, self.hint);
        if !inside && f.outside == Outside::Zero {
            return DVec3::ZERO;
        }
        let u = f.value(&s, self.a, self.b, self.w);
        match frame {
            None => u,
            Some((e_r, e_t, e_z)) => u.x * e_r + u.y * e_t + u.z * e_z,
        }
    }
}

/// A [`Field`] on a structured grid at one time, as a [`FlowField`]: what the hot loop reads
/// of a `.vti` or `.vtr` field. Its own type rather than a case of [`FieldAt`], so that the
/// kernels compiled for it blend the eight nodes directly ([`Structured::blend`]) with the
/// snapshots and the outside policy resolved once per step, and those compiled for an
/// unstructured grid keep their walk as it was. The values are [`FieldAt`]'s, bit for bit.
#[derive(Debug, Clone, Copy)]
pub struct StructuredAt<'a> {
    /// The field, for its frame ([`Field::to_grid`]).
    field: &'a Field,
    /// Its grid.
    grid: &'a Structured,
    /// The values of the snapshot at or before the time and of the one after it (the same
    /// when the field does not change there; [`Field::at`]).
    before: &'a [DVec3],
    /// See [`StructuredAt::before`].
    after: &'a [DVec3],
    /// The weight of `after` (0 for `before` alone).
    w: f64,
    /// Whether the flow is at rest outside the grid ([`Outside::Zero`]); otherwise a point
    /// outside takes the value of the grid's nearest point.
    zero_outside: bool,
}

/// The values of nodes `n` and `n + dx` (`dx` 0 or 1), one range checked for the two.
#[inline(always)]
fn pair(values: &[DVec3], n: usize, dx: usize) -> [DVec3; 2] {
    let row = &values[n..n + 1 + dx];
    [row[0], row[dx]]
}

/// [`pair`] between two snapshots, `w` of the way from `before` to `after` ([`Field::value`]'s
/// sum).
#[inline(always)]
fn in_time(before: &[DVec3], after: &[DVec3], w: f64, n: usize, dx: usize) -> [DVec3; 2] {
    let ([a0, a1], [b0, b1]) = (pair(before, n, dx), pair(after, n, dx));
    [(1.0 - w) * a0 + w * b0, (1.0 - w) * a1 + w * b1]
}

/// The velocity of a [`StructuredAt`], one point or a lane group at a time.
impl PointMap for StructuredAt<'_> {
    #[inline(always)]
    fn one(&self, x: DVec3) -> DVec3 {
        self.velocity(x)
    }

    /// [`FlowField::velocity`] of a lane group: in a 3-D field that takes the nearest point's
    /// value outside (the scenes of issue 14), the cells and weights of the four points four
    /// lanes wide ([`Structured::blend_lanes`]), the same values bit for bit as one point at a
    /// time; otherwise one point at a time.
    #[inline(always)]
    fn four(&self, x: DVec3x4) -> DVec3x4 {
        if self.zero_outside || self.field.axisymmetric.is_some() {
            return x.map_points(|p| self.velocity(p));
        }
        let (g, before, after, w) = (self.grid, self.before, self.after, self.w);
        if w == 0.0 {
            g.blend_lanes(x, |n, dx| pair(before, n, dx))
        } else {
            g.blend_lanes(x, |n, dx| in_time(before, after, w, n, dx))
        }
    }
}

impl FlowField for StructuredAt<'_> {
    #[inline(always)]
    fn velocity_of<V: Vector>(&self, x: V) -> V {
        x.map_by(self)
    }

    #[inline]
    fn velocity(&self, x: DVec3) -> DVec3 {
        let g = self.grid;
        let (q, frame) = self.field.to_grid(x);
        if self.zero_outside && !g.contains(q) {
            return DVec3::ZERO;
        }
        // `blend` moves a point outside to the nearest of the field, and leaves one inside as
        // it is.
        let (before, after, w) = (self.before, self.after, self.w);
        let u = if w == 0.0 {
            g.blend(q, |n, dx| pair(before, n, dx))
        } else {
            g.blend(q, |n, dx| in_time(before, after, w, n, dx))
        };
        match frame {
            None => u,
            Some((e_r, e_t, e_z)) => u.x * e_r + u.y * e_t + u.z * e_z,
        }
    }
}

#[cfg(test)]
mod tests;
