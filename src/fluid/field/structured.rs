//! Structured grids (VTK image data and rectilinear grids): nodes on the lines of three
//! coordinate axes, interpolated trilinearly.

use crate::numeric::lanes::{DVec3x4, F64x4, LANES, each};
use glam::DVec3;

/// The node coordinates along one axis of a structured grid, and the stretch of that axis that
/// belongs to the field.
#[derive(Debug, Clone)]
pub struct Axis {
    /// Node coordinates, strictly increasing (m).
    pub nodes: Vec<f64>,
    /// `(first node, 1 / spacing)` when the nodes are evenly spaced (image data): the cell is
    /// found by one division instead of a binary search.
    pub uniform: Option<(f64, f64)>,
    /// The field's extent along the axis (m): the first and last node for point data; the
    /// outer faces of the first and last cell for cell data, whose nodes are cell centres.
    pub lo: f64,
    /// See [`Axis::lo`].
    pub hi: f64,
}

impl Axis {
    /// The axis of nodes `nodes` with the field's extent `[lo, hi]`.
    pub fn new(nodes: Vec<f64>, lo: f64, hi: f64) -> Axis {
        let n = nodes.len();
        let uniform = if n >= 2 {
            let h = (nodes[n - 1] - nodes[0]) / (n - 1) as f64;
            let even =
                nodes.iter().enumerate().all(|(i, x)| (x - (nodes[0] + i as f64 * h)).abs() <= 1e-9 * h);
            even.then_some((nodes[0], 1.0 / h))
        } else {
            None
        };
        Axis { nodes, uniform, lo, hi }
    }

    /// [`Axis::cell`]'s cell index on an axis of two nodes or more.
    #[inline(always)]
    fn index(&self, x: f64) -> usize {
        let n = self.nodes.len();
        match self.uniform {
            // `max` sends s < 0 and NaN to cell 0; the saturating conversion to `i32` is a few instructions (one four lanes wide) where
            // the one to `usize` is a dozen, and the cell is the same (no axis has 2³¹ nodes).
            Some((x0, inv_h)) => (((x - x0) * inv_h).max(0.0) as i32 as usize).min(n - 2),
            None => self.nodes.partition_point(|&c| c <= x).saturating_sub(1).min(n - 2),
        }
    }

    /// Nodes `i` and `i + 1`, one bounds check for the two.
    #[inline(always)]
    fn pair(&self, i: usize) -> (f64, f64) {
        let pair = &self.nodes[i..i + 2];
        (pair[0], pair[1])
    }

    /// The cell `i` (nodes `i` and `i + 1`) and the fraction `t` along it for coordinate `x`,
    /// already clamped to `[lo, hi]`. In the half cell between the outer node and the extent
    /// (cell data), `t` leaves `[0, 1]`: the outer cell's line is extended rather than cut
    /// off flat, which keeps the interpolation second order up to the edge.
    #[inline(always)]
    fn cell(&self, x: f64) -> (usize, f64) {
        // `< 2` rather than `== 1` (an axis has a node at least): the cell is then below n − 1
        // for the compiler too, and reading its two nodes needs no bounds check.
        if self.nodes.len() < 2 {
            return (0, 0.0);
        }
        let i = self.index(x);
        let (a, b) = self.pair(i);
        (i, (x - a) / (b - a))
    }

    /// [`Axis::cell`] of four coordinates, each lane with the same operations as one: the
    /// axis' own choices (one node, even spacing) made once for the four, the arithmetic four
    /// lanes wide.
    #[inline(always)]
    fn cells(&self, x: F64x4) -> ([usize; LANES], F64x4) {
        let n = self.nodes.len();
        // As in `cell`, `< 2` so that the cells below need no bounds check.
        if n < 2 {
            return ([0; LANES], F64x4([0.0; LANES]));
        }
        let i = match self.uniform {
            // `index`'s conversion to an integer is a dozen scalar instructions per lane; this
            // form has vector instructions for each step. `s` is kept in [0, n − 2] (NaN to 0)
            // before it is truncated, which gives the same cell as truncating first (n − 2 is
            // a whole number), and the truncation is read off the mantissa of s + 2⁵² (which
            // rounds to the nearest whole number: one less where that is above s). The last
            // `min` changes nothing but tells the compiler that the cell's nodes are there.
            Some((x0, inv_h)) => {
                const TWO_52: f64 = 4_503_599_627_370_496.0;
                // Through `i64` (exact: a length is below 2⁶³): one instruction, where the
                // conversion of an unsigned integer is several.
                let top = (n - 2) as i64 as f64;
                let s = (x - F64x4([x0; LANES])) * inv_h;
                each(s.0, |s| {
                    let s = if s > 0.0 { s } else { 0.0 };
                    let s = if s < top { s } else { top };
                    let r = s + TWO_52;
                    let k = r.to_bits() - TWO_52.to_bits();
                    ((if r - TWO_52 > s { k - 1 } else { k }) as usize).min(n - 2)
                })
            }
            None => each(x.0, |x| self.index(x)),
        };
        let pairs = each(i, |i| self.pair(i));
        let (a, b) = (F64x4(each(pairs, |p| p.0)), F64x4(each(pairs, |p| p.1)));
        (i, (x - a) / (b - a))
    }

    /// `x` moved into the field's extent along this axis (an axis of one node has none): one
    /// axis of [`Structured::clamp`].
    #[inline(always)]
    fn clamp(&self, x: f64) -> f64 {
        // `f64::clamp`'s comparisons (a NaN stays NaN) without its check that lo ≤ hi, which
        // an axis has: a few instructions per axis of each lookup.
        if self.nodes.len() == 1 {
            return x;
        }
        // Two selects, each one `max`/`min` instruction (four lanes wide in a lane group).
        let x = if x < self.lo { self.lo } else { x };
        if x > self.hi { self.hi } else { x }
    }

    /// Whether `x` lies in the field's extent along this axis (an axis of one node has no
    /// extent to leave: it is the second dimension of an axisymmetric table).
    #[inline]
    fn contains(&self, x: f64) -> bool {
        self.nodes.len() == 1 || (self.lo <= x && x <= self.hi)
    }

    /// The smallest node spacing (m); ∞ for one node.
    pub fn smallest_spacing(&self) -> f64 {
        self.nodes.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min)
    }
}

/// A structured grid: the nodes are every combination of the three axes' coordinates, `x`
/// fastest (VTK's order).
#[derive(Debug, Clone)]
pub struct Structured {
    /// The axes.
    pub axes: [Axis; 3],
}

/// The nodes and weights that make the value at a point: 8 for a trilinear stencil, 4 for a
/// tetrahedron (the rest have weight 0 at node 0).
#[derive(Debug, Clone, Copy, Default)]
pub struct Stencil {
    /// Node indices.
    pub nodes: [u32; 8],
    /// Their weights, summing to 1.
    pub weights: [f64; 8],
    /// The weights' derivatives along x, y and z (1/m): the gradient of the interpolant.
    pub gradient: [DVec3; 8],
}

impl Structured {
    /// The number of nodes along each axis.
    pub fn dims(&self) -> [usize; 3] {
        [self.axes[0].nodes.len(), self.axes[1].nodes.len(), self.axes[2].nodes.len()]
    }

    /// Whether `p` lies in the field.
    #[inline]
    pub fn contains(&self, p: DVec3) -> bool {
        self.axes[0].contains(p.x) && self.axes[1].contains(p.y) && self.axes[2].contains(p.z)
    }

    /// `p` moved to the nearest point of the field.
    #[inline]
    pub fn clamp(&self, p: DVec3) -> DVec3 {
        let [ax, ay, az] = &self.axes;
        DVec3::new(ax.clamp(p.x), ay.clamp(p.y), az.clamp(p.z))
    }

    /// The trilinear stencil at `p`, which must lie in the field ([`Structured::clamp`]).
    #[inline]
    pub fn stencil(&self, p: DVec3) -> Stencil {
        self.stencil_of(p, true)
    }

    /// [`Structured::stencil`] without the gradient (left zero): what a velocity needs.
    #[inline]
    pub fn weights(&self, p: DVec3) -> Stencil {
        self.stencil_of(p, false)
    }

    /// The stencil at `p`, its gradient only `with_gradient`. Corner `c` is `(c & 1, c >> 1 & 1,
    /// c >> 2)` cells along (x, y, z), VTK's order.
    #[inline(always)]
    fn stencil_of(&self, p: DVec3, with_gradient: bool) -> Stencil {
        let [nx, ny, _] = self.dims();
        let (i, tx) = self.axes[0].cell(p.x);
        let (j, ty) = self.axes[1].cell(p.y);
        let (k, tz) = self.axes[2].cell(p.z);
        let step = |a: &Axis, i: usize| {
            if a.nodes.len() == 1 { (0, 0.0) } else { (1, 1.0 / (a.nodes[i + 1] - a.nodes[i])) }
        };
        let (di, gx) = step(&self.axes[0], i);
        let (dj, gy) = step(&self.axes[1], j);
        let (dk, gz) = step(&self.axes[2], k);
        // An axis of one node contributes its single node twice, each with weight 1 − 0 or 0.
        let base = i + nx * (j + ny * k);
        let offset = [[0, di], [0, nx * dj], [0, nx * ny * dk]];
        let (wx, wy, wz) = ([1.0 - tx, tx], [1.0 - ty, ty], [1.0 - tz, tz]);
        let (dx, dy, dz) = ([-gx, gx], [-gy, gy], [-gz, gz]);
        let mut s = Stencil::default();
        for c in 0..8 {
            let (a, b, e) = (c & 1, (c >> 1) & 1, c >> 2);
            s.nodes[c] = (base + offset[0][a] + offset[1][b] + offset[2][e]) as u32;
            s.weights[c] = wx[a] * wy[b] * wz[e];
            if with_gradient {
                s.gradient[c] =
                    DVec3::new(dx[a] * wy[b] * wz[e], wx[a] * dy[b] * wz[e], wx[a] * wy[b] * dz[e]);
            }
        }
        s
    }

    /// The trilinear interpolant at `p` (moved into the field first, [`Structured::clamp`]) of
    /// the node values that `row(n, dx)` gives in pairs: nodes `n` and `n + dx` (VTK's order;
    /// `dx` is 1, or 0 on an axis x of one node), so that a caller checks one range per row of
    /// two rather than each node. The sum over [`Structured::weights`]' stencil, with the same
    /// operations in the same order (the same value to the bit), without filling a stencil
    /// and reading it back: the velocity lookup of a structured field in the hot loop
    /// (issue 14).
    #[inline(always)]
    pub fn blend(&self, p: DVec3, row: impl Fn(usize, usize) -> [DVec3; 2]) -> DVec3 {
        let [ax, ay, az] = &self.axes;
        let (nx, ny, nz) = (ax.nodes.len(), ay.nodes.len(), az.nodes.len());
        let (i, tx) = ax.cell(ax.clamp(p.x));
        let (j, ty) = ay.cell(ay.clamp(p.y));
        let (k, tz) = az.cell(az.clamp(p.z));
        // An axis of one node contributes its single node twice, each with weight 1 − 0 or 0.
        let dx = usize::from(nx > 1);
        let dy = if ny > 1 { nx } else { 0 };
        let dz = if nz > 1 { nx * ny } else { 0 };
        let base = i + nx * (j + ny * k);
        let (wx, wy, wz) = ([1.0 - tx, tx], [1.0 - ty, ty], [1.0 - tz, tz]);
        // Corner (a, b, e) in the stencil's order, x fastest, each weight `wx · wy · wz`, added
        // to a zero sum as `Field::value` adds them.
        let mut u = DVec3::ZERO;
        for (e, oz) in [0, dz].into_iter().enumerate() {
            for (b, oy) in [0, dy].into_iter().enumerate() {
                let [v0, v1] = row(base + oy + oz, dx);
                u += wx[0] * wy[b] * wz[e] * v0;
                u += wx[1] * wy[b] * wz[e] * v1;
            }
        }
        u
    }

    /// [`Structured::blend`] at four points: each lane with the same operations in the same
    /// order as one point (the same value to the bit), the arithmetic four lanes wide.
    #[inline(always)]
    pub fn blend_lanes(&self, p: DVec3x4, row: impl Fn(usize, usize) -> [DVec3; 2]) -> DVec3x4 {
        let [ax, ay, az] = &self.axes;
        let clamp = |a: &Axis, x: F64x4| F64x4(each(x.0, |x| a.clamp(x)));
        let (nx, ny, nz) = (ax.nodes.len(), ay.nodes.len(), az.nodes.len());
        let (i, tx) = ax.cells(clamp(ax, p.x));
        let (j, ty) = ay.cells(clamp(ay, p.y));
        let (k, tz) = az.cells(clamp(az, p.z));
        let dx = usize::from(nx > 1);
        let dy = if ny > 1 { nx } else { 0 };
        let dz = if nz > 1 { nx * ny } else { 0 };
        let base = each([0, 1, 2, 3], |l| i[l] + nx * (j[l] + ny * k[l]));
        let one = F64x4([1.0; LANES]);
        let (wx, wy, wz) = ([one - tx, tx], [one - ty, ty], [one - tz, tz]);
        let zero = F64x4([0.0; LANES]);
        let mut u = DVec3x4 { x: zero, y: zero, z: zero };
        for (e, oz) in [0, dz].into_iter().enumerate() {
            for (b, oy) in [0, dy].into_iter().enumerate() {
                let pairs = each(base, |r| row(r + oy + oz, dx));
                u = u + DVec3x4::from_array(each(pairs, |v| v[0])) * (wx[0] * wy[b] * wz[e]);
                u = u + DVec3x4::from_array(each(pairs, |v| v[1])) * (wx[1] * wy[b] * wz[e]);
            }
        }
        u
    }

    /// The smallest node spacing over the three axes (m).
    pub fn smallest_spacing(&self) -> f64 {
        self.axes.iter().map(Axis::smallest_spacing).fold(f64::INFINITY, f64::min)
    }
}
