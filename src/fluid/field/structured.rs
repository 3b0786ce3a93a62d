//! Structured grids (VTK image data and rectilinear grids): nodes on the lines of three
//! coordinate axes, interpolated trilinearly.

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

    /// The cell `i` (nodes `i` and `i + 1`) and the fraction `t` along it for coordinate `x`,
    /// already clamped to `[lo, hi]`. In the half cell between the outer node and the extent
    /// (cell data), `t` leaves `[0, 1]`: the outer cell's line is extended rather than cut
    /// off flat, which keeps the interpolation second order up to the edge.
    #[inline]
    fn cell(&self, x: f64) -> (usize, f64) {
        let n = self.nodes.len();
        if n == 1 {
            return (0, 0.0);
        }
        let i = match self.uniform {
            Some((x0, inv_h)) => {
                // Truncation is the floor for s ≥ 0 (and a call to `floor` where the target
                // has no rounding instruction).
                let s = (x - x0) * inv_h;
                if s < 0.0 { 0 } else { (s as usize).min(n - 2) }
            }
            None => self.nodes.partition_point(|&c| c <= x).saturating_sub(1).min(n - 2),
        };
        let (a, b) = (self.nodes[i], self.nodes[i + 1]);
        (i, (x - a) / (b - a))
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
        let c = |a: &Axis, x: f64| if a.nodes.len() == 1 { x } else { x.clamp(a.lo, a.hi) };
        DVec3::new(c(&self.axes[0], p.x), c(&self.axes[1], p.y), c(&self.axes[2], p.z))
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

    /// The smallest node spacing over the three axes (m).
    pub fn smallest_spacing(&self) -> f64 {
        self.axes.iter().map(Axis::smallest_spacing).fold(f64::INFINITY, f64::min)
    }
}
