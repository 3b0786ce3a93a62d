//! **[ext]** The Basset–Boussinesq history force (docs/physics.md §10): its coefficient,
//! bounded-memory sums of exponentials for its `1/√t` kernel, and the exact solution of a sphere
//! released from rest in a still fluid, against which a history-force integrator can be tested.

use super::faddeeva::{Complex, faddeeva_w};
use std::f64::consts::{E, PI};

/// Coefficient of the history force, `K_H = 6 a² sqrt(π ρ μ)` in kg/s^½ (docs/physics.md §10;
/// Basset 1888, Boussinesq 1885; e.g. Maxey & Riley 1983, Phys. Fluids 26, 883), so
/// that `F_H = −K_H ∫_0^t (dw/ds) / sqrt(t − s) ds` (N) for the slip velocity `w` (m/s).
///
/// `radius` `a` in m, fluid density `rho` in kg/m³, viscosity `mu` in Pa·s. Valid where the
/// unsteady Stokes equations are (particle Reynolds number ≪ 1); 0 in a vacuum.
pub fn basset_coefficient(radius: f64, rho: f64, mu: f64) -> f64 {
    6.0 * radius * radius * (PI * rho * mu).sqrt()
}

/// A sum of decaying exponentials `K(t) ≈ Σ_k weights[k] · exp(−rates[k] · t)` standing in for
/// the history kernel `1/√t` (t in s, weights in s^−½, rates in 1/s).
///
/// Each exponential turns into one extra state per particle: with
/// `F_k(t) = ∫_0^{t} e^{−λ_k (t − s)} (dw/ds) ds`, `dF_k/dt = −λ_k F_k + dw/dt`, and the tail of
/// the memory integral is `Σ_k weight_k F_k`: bounded memory and cost per step.
#[derive(Debug, Clone, PartialEq)]
pub struct ExponentialSum {
    /// Weights `w_k` (s^−½).
    pub weights: Vec<f64>,
    /// Decay rates `λ_k` (1/s), increasing.
    pub rates: Vec<f64>,
}

/// van Hinsberg, ten Thije Boonkkamp & Clercx (2011), J. Comput. Phys. 230, 1465–1478: the
/// published time scales `t̃_i` of their m = 10 tail approximation, in units of the window
/// length `t_win`.
pub const VAN_HINSBERG_T: [f64; 10] = [0.1, 0.3, 1.0, 3.0, 10.0, 40.0, 190.0, 1000.0, 6500.0, 50000.0];

/// van Hinsberg et al. (2011): the published weights `a_i` (m = 10) that go with
/// [`VAN_HINSBERG_T`].
pub const VAN_HINSBERG_A: [f64; 10] = [
    0.234_774_813_125_86,
    0.285_495_762_381_94,
    0.284_794_167_182_55,
    0.261_497_755_375_74,
    0.320_562_005_119_38,
    0.353_544_906_891_46,
    0.396_359_044_969_21,
    0.422_539_085_965_14,
    0.483_173_842_252_65,
    0.636_611_465_570_01,
];

impl ExponentialSum {
    /// `Σ_k w_k e^{−λ_k t}`.
    pub fn eval(&self, t: f64) -> f64 {
        self.weights.iter().zip(&self.rates).map(|(w, l)| w * (-l * t).exp()).sum()
    }

    /// Number of exponentials.
    pub fn len(&self) -> usize {
        self.weights.len()
    }

    /// True when there is no exponential.
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }

    /// The tail kernel of van Hinsberg, ten Thije Boonkkamp & Clercx (2011), J. Comput. Phys.
    /// 230, 1465–1478, with their m = 10 coefficients:
    /// `1/√t ≈ Σ_i a_i sqrt(e/(t̃_i t_win)) exp(−t/(2 t̃_i t_win))` for `t ≥ t_win`, with `t_win`
    /// (s) the length of the window over which the memory integral is evaluated directly.
    ///
    /// **Accuracy** (measured here; `van_hinsberg_sum_accuracy_as_published`): maximum relative
    /// error against `1/√t` of 0.28 % on `t ∈ [1, 10] t_win`, 0.70 % on `[1, 100] t_win`,
    /// 3.3 % on `[1, 1000] t_win` and 10.3 % on `[1, 10⁴] t_win`, the sum falling below `1/√t`
    /// beyond (it decays exponentially past `10⁵ t_win`). The paper's point is that this is
    /// enough for the history *integral*, where the tail is weighted by old accelerations;
    /// [`ExponentialSum::inverse_sqrt`] gives a sum with a chosen error instead.
    pub fn van_hinsberg(t_win: f64) -> Self {
        let weights =
            VAN_HINSBERG_A.iter().zip(VAN_HINSBERG_T).map(|(a, t)| a * (E / (t * t_win)).sqrt()).collect();
        let rates = VAN_HINSBERG_T.iter().map(|t| 0.5 / (t * t_win)).collect();
        Self { weights, rates }
    }

    /// A sum of exponentials for `1/√t` with relative error at most `rel_tol` on
    /// `t ∈ [t_min, t_max]` (s) **[ext]**: the trapezoidal rule with step `h` on
    /// `1/√t = (2/√π) ∫_{−∞}^{∞} exp(x − t e^{2x}) dx`, nodes `x_k`, so that
    /// `w_k = (2/√π) h e^{x_k}` and `λ_k = e^{2 x_k}` (the construction of Beylkin & Monzón
    /// 2010, Appl. Comput. Harmon. Anal. 28, 131–149, applied to this kernel), with its slow
    /// tail lumped into one exponential.
    ///
    /// The error budget: the discretisation error of the rule, relative and independent of
    /// `t`, is `2|Γ(½ + iπ/h)|/√π = 2/sqrt(cosh(π²/h)) ≤ 0.7 rel_tol`; the nodes stop above at
    /// `x_U` where `erfc(√t_min e^{x_U}) ≤ 0.3 rel_tol`. The slow tail: every node whose rate
    /// is below `θ/t_max`, `θ = min(10 rel_tol, 10⁻³)`, is nearly constant over the whole
    /// interval (`e^{−λt} = 1 − λt + …`), so those nodes are replaced by one exponential of
    /// their total weight `W = Σ w_k` and mean rate `Σ w_k λ_k / W`: the same value and slope
    /// at `t = 0`, a difference of order `(θ t/t_max)²` of `W` after (below 1e-3 of `rel_tol`
    /// for `t ≤ t_max`). Lumped, the tail costs one state however far down it goes, so it is
    /// taken down to `1e-3 rel_tol` of `1/√t_max` and its truncation error is negligible.
    /// Beyond `t_max` the lumped exponential decays at about `θ/t_max`: older accelerations
    /// are under-weighted, then forgotten after some `1/θ` windows.
    ///
    /// Examples (before the lumping and the new budget in brackets): `[1, 10⁴]` s at 1e-3
    /// takes 17 exponentials (27), measured error 7.0e-4; `[1e-10, 1]` s at 1e-4, 37 (55),
    /// 7.0e-5; `[1e-4, 10⁶]` s at 1e-5, 48 (73); `[1e-3, 10³]` s at 1e-8, 68 (119); test
    /// `inverse_sqrt_sum_meets_its_tolerance`, on 2000 points per decade.
    ///
    /// # Panics
    /// Unless `0 < t_min < t_max` and `0 < rel_tol < 1`.
    pub fn inverse_sqrt(t_min: f64, t_max: f64, rel_tol: f64) -> Self {
        assert!(0.0 < t_min && t_min < t_max && 0.0 < rel_tol && rel_tol < 1.0);
        // 2/sqrt(cosh(π²/h)) ≈ 2√2 e^{−π²/(2h)} = 0.7 rel_tol.
        let h = PI * PI / (2.0 * (2.0 * 2f64.sqrt() / (0.7 * rel_tol)).ln());
        let c = 2.0 / PI.sqrt();
        // Left tail: c e^{x_L} h / (1 − e^{−h}) · √t_max = 1e-3 rel_tol.
        let x_lo = (1e-3 * rel_tol * (-h).exp_m1().abs() / (h * c * t_max.sqrt())).ln();
        // Right tail: erfc(z) ≤ e^{−z²}, z = √t_min e^{x_U}.
        let x_hi = ((1.0 / (0.3 * rel_tol)).ln().sqrt() / t_min.sqrt()).ln();
        let n = ((x_hi - x_lo) / h).ceil() as usize + 1;
        let slow = (10.0 * rel_tol).min(1e-3) / t_max;
        let (mut weights, mut rates) = (vec![0.0], vec![0.0]);
        let (mut lumped, mut moment) = (0.0, 0.0);
        for k in 0..n {
            let x = x_lo + k as f64 * h;
            let (w, rate) = (c * h * x.exp(), (2.0 * x).exp());
            if rate < slow {
                lumped += w;
                moment += w * rate;
            } else {
                weights.push(w);
                rates.push(rate);
            }
        }
        (weights[0], rates[0]) = (lumped, moment / lumped);
        Self { weights, rates }
    }
}

/// A sphere released from rest at `t = 0` in a still fluid under a constant force, with Stokes
/// drag, added mass and the history force **[ext]** (docs/physics.md §10): the equation
///
/// `m_eff dv/dt = F − 6π μ a v − 6 a² sqrt(π ρ μ) ∫_0^t (dv/ds)/sqrt(t − s) ds`, `v(0) = 0`,
///
/// whose Laplace transform is `V(s) = A / (s (s + c √s + 1/τ))` with
/// `A = F/m_eff`, `1/τ = 6π μ a / m_eff` and `c = 6π a² sqrt(ρ μ) / m_eff`
/// (the transform of `∫ v′(s)/√(t−s) ds` being `√π √s V`). Fields in SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HistorySettling {
    /// `A = F / m_eff` (m/s²), signed: positive along the force.
    pub accel: f64,
    /// `τ = m_eff / (6π μ a)` (s).
    pub tau: f64,
    /// `c = 6π a² sqrt(ρ μ) / m_eff` (s^−½); 0 without history force.
    pub history_rate: f64,
}

impl HistorySettling {
    /// The coefficients for a sphere of density `rho_p` and radius `radius` settling under
    /// gravity `g` (m/s², magnitude) through a fluid of density `rho` and viscosity `mu`, with
    /// buoyancy and the added mass `C_M∞ = 1/2`: `F = (ρp − ρ) Vp g`, `m_eff = (ρp + ρ/2) Vp`.
    /// The velocity is positive downwards (negative for a rising, lighter sphere). Needs
    /// `mu > 0` and `radius > 0` (a finite `τ`).
    pub fn sphere(rho_p: f64, rho: f64, mu: f64, radius: f64, g: f64) -> Self {
        let volume = 4.0 / 3.0 * PI * radius.powi(3);
        let m_eff = (rho_p + 0.5 * rho) * volume;
        Self {
            accel: (rho_p - rho) * volume * g / m_eff,
            tau: m_eff / (6.0 * PI * mu * radius),
            history_rate: 6.0 * PI * radius * radius * (rho * mu).sqrt() / m_eff,
        }
    }

    /// Terminal velocity `V_t = A τ` (m/s), reached as `t → ∞`.
    pub fn terminal_velocity(&self) -> f64 {
        self.accel * self.tau
    }

    /// The one dimensionless number of the problem, `κ = c √τ`; for a sphere
    /// `κ² = 9ρ/(2ρp + ρ)`, so `κ < 3`, and `κ = 2` (a double root) at `ρp = 5ρ/8`.
    pub fn kappa(&self) -> f64 {
        self.history_rate * self.tau.sqrt()
    }

    /// The coefficient `C` (s^½) of the slow approach to the terminal velocity,
    /// `V ≈ V_t (1 − C/√t)` for `t ≫ τ`: `C = c τ / √π` (from `V(s) ≈ V_t (1/s − c τ/√s)` as
    /// `s → 0`). Without history force the approach is exponential and `C = 0`.
    pub fn long_time_coefficient(&self) -> f64 {
        self.history_rate * self.tau / PI.sqrt()
    }
}

/// Exact velocity (m/s) at time `t` (s) of the sphere of [`HistorySettling`], released from
/// rest at `t = 0`: the inverse Laplace transform of `A / (s (s + c √s + 1/τ))` **[ext]**.
///
/// In units of `V_t` and `τ` (`T = t/τ`, `κ = c√τ`) the velocity is `V_t v̂(T)`, and with
/// `x² + κ x + 1 = (x − x₁)(x − x₂)` partial fractions and the pair
/// `L[e^{b²t} erfc(−b√t)] = 1/(√s (√s − b))` give
///
/// `v̂(T) = 1 + [g(x₁) − g(x₂)] / (x₁ − x₂)`, `g(b) = e^{b²T} erfc(−b√T) / b = w(−i b √T) / b`,
///
/// with `w` the Faddeeva function (both `−i x_j √T` lie in the closed upper half plane, where
/// `w` is bounded). The roots are complex conjugate for `κ < 2` (solid spheres, `ρp > 5ρ/8`;
/// `v̂ = 1 + Im g(x₁)/Im x₁`), real for `κ > 2` (bubbles and light drops), and double at
/// `κ = 2`, where (for `|x₁ − x₂| < 2e-4`) the divided difference becomes `g′(m) + g‴(m) δ²/6`,
/// `m = −κ/2`, `δ² = (κ² − 4)/4`, the derivatives from `E′ = 2bT E + 2√(T/π)`. Small times,
/// `T < 1/2`, use the convergent series `v̂ = Σ_k d_k T^{1+k/2} / Γ(2 + k/2)`
/// (`1/(1 + κy + y²) = Σ d_k y^k`), which keeps the relative accuracy as `v → A t`; a double
/// root at `T > 50` uses the asymptotic series `v̂ ~ 1 + Σ_m d_{2m+1} T^{−m−½} / Γ(½ − m)`.
///
/// **Accuracy**: better than 4e-13 relative wherever measured. Against the no-history solution
/// `V_t (1 − e^{−t/τ})` for `c = 0`: 4e-16 (`T ∈ [1e-8, 1e3]`). Against two independent
/// numerical inversions of `V(s)` on 61 values of `κ ∈ (0, 3)` (and `κ = 2 ± 5e-5`) times
/// `T ∈ [0.01, 1000]`: the Bromwich contour folded onto the branch cut `s = −u²` (a real
/// integral, tanh-sinh quadrature) agrees to 4.1e-13 (the largest gap at `T = 0.01`, where the
/// reference loses digits to the cancellation in `1 − ∫`), Talbot's contour (32 nodes) to
/// 2.4e-11, its own limit in f64. The long-time form `V_t (1 − C/√t + …)` holds to its next
/// term. Tests `settling_*`. `t ≤ 0` returns 0.
pub fn history_settling_velocity(t: f64, params: &HistorySettling) -> f64 {
    if t <= 0.0 {
        return 0.0;
    }
    params.terminal_velocity() * unit_response(t / params.tau, params.kappa())
}

/// `v̂(T)` for `κ = c√τ`: the response of `1/(ŝ (ŝ + κ √ŝ + 1))`.
fn unit_response(t: f64, kappa: f64) -> f64 {
    if t < 0.5 {
        return small_time_series(t, kappa);
    }
    let delta_sq = 0.25 * (kappa * kappa - 4.0);
    let m = -0.5 * kappa;
    if delta_sq.abs() < 1e-8 {
        if t > 50.0
            && let Some(v) = large_time_series(t, kappa)
        {
            return v;
        }
        return 1.0 + double_root_divided_difference(t, m, delta_sq);
    }
    let root_t = t.sqrt();
    if delta_sq > 0.0 {
        // Two real negative roots: −i x √T = i |x| √T, where w is real (erfcx).
        let d = delta_sq.sqrt();
        let g = |x: f64| faddeeva_w(Complex::new(0.0, -x * root_t)).re / x;
        let (x1, x2) = (m + d, m - d);
        1.0 + (g(x1) - g(x2)) / (x1 - x2)
    } else {
        // Complex pair x₁ = m + iω, x₂ = conj(x₁): g(x₂) = conj(g(x₁)).
        let omega = (-delta_sq).sqrt();
        let x1 = Complex::new(m, omega);
        let z = Complex::new(omega * root_t, -m * root_t); // −i x₁ √T
        let g1 = faddeeva_w(z) / x1;
        1.0 + g1.im / omega
    }
}

/// `v̂(T) = Σ_k d_k T^{1+k/2} / Γ(2 + k/2)`, convergent for every `T`, used for `T < 1/2`.
fn small_time_series(t: f64, kappa: f64) -> f64 {
    let r = t.sqrt();
    // d_{k−1}, d_k; Γ(2 + (k−1)/2), Γ(2 + k/2); T^{1 + k/2}.
    let (mut d_prev, mut d) = (0.0, 1.0);
    let (mut gamma_prev, mut gamma) = (0.5 * PI.sqrt(), 1.0);
    let mut power = t;
    let (mut sum, mut previous) = (0.0, f64::INFINITY);
    for k in 0..400 {
        let term = d * power / gamma;
        sum += term;
        // Two small terms in a row (odd terms vanish when κ = 0).
        if k > 4 && term.abs().max(previous) < 1e-18 * sum.abs() {
            break;
        }
        previous = term.abs();
        let d_next = -kappa * d - d_prev;
        (d_prev, d) = (d, d_next);
        // Γ(2 + (k+1)/2) = (1 + (k+1)/2) Γ(2 + (k−1)/2).
        let gamma_next = (1.0 + 0.5 * (k as f64 + 1.0)) * gamma_prev;
        (gamma_prev, gamma) = (gamma, gamma_next);
        power *= r;
    }
    sum
}

/// Asymptotic series `v̂ ~ 1 + Σ_m d_{2m+1} T^{−m−½} / Γ(½ − m)` (Watson's lemma on
/// `V(s)` about `s = 0`), returned only if its terms fall below 1e-17 before they grow.
fn large_time_series(t: f64, kappa: f64) -> Option<f64> {
    let (mut d_prev, mut d) = (1.0, -kappa); // d_0, d_1
    let mut inv_gamma = 1.0 / PI.sqrt(); // 1/Γ(½ − m) at m = 0
    let mut power = 1.0 / t.sqrt();
    let mut sum = 1.0;
    let mut last = f64::INFINITY;
    for m in 0..200 {
        let term = d * inv_gamma * power;
        if term.abs() > last {
            return None;
        }
        sum += term;
        if term.abs() < 1e-17 {
            return Some(sum);
        }
        last = term.abs();
        // d_{2m+3} from d_{2m+1}, d_{2m}: two steps of d_k = −κ d_{k−1} − d_{k−2}.
        let d_even = -kappa * d - d_prev;
        let d_odd = -kappa * d_even - d;
        d_prev = d_even;
        d = d_odd;
        inv_gamma *= -(m as f64 + 0.5);
        power /= t;
    }
    None
}

/// `[g(x₁) − g(x₂)]/(x₁ − x₂)` for nearly equal roots `m ± δ` (`|δ| < 1e-4`), to O(δ⁴):
/// `g′(m) + g‴(m) δ²/6` with `g = E/b`, `E(b) = e^{b²T} erfc(−b√T)`.
fn double_root_divided_difference(t: f64, b: f64, delta_sq: f64) -> f64 {
    let e0 = faddeeva_w(Complex::new(0.0, -b * t.sqrt())).re;
    let e1 = 2.0 * b * t * e0 + 2.0 * (t / PI).sqrt();
    let e2 = 2.0 * t * e0 + 2.0 * b * t * e1;
    let e3 = 4.0 * t * e1 + 2.0 * b * t * e2;
    let (b2, b3, b4) = (b * b, b * b * b, b * b * b * b);
    let g1 = e1 / b - e0 / b2;
    let g3 = e3 / b - 3.0 * e2 / b2 + 6.0 * e1 / b3 - 6.0 * e0 / b4;
    g1 + g3 * delta_sq / 6.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn log_grid(lo: f64, hi: f64, per_decade: usize) -> impl Iterator<Item = f64> {
        let n = ((hi - lo) * per_decade as f64).round() as usize;
        (0..=n).map(move |i| 10f64.powf(lo + (hi - lo) * i as f64 / n as f64))
    }

    fn unit(kappa: f64) -> HistorySettling {
        HistorySettling { accel: 1.0, tau: 1.0, history_rate: kappa }
    }

    #[test]
    fn basset_coefficient_of_a_millimetre_bead_in_water() {
        // 6 (1e-3)² sqrt(π · 1000 · 1e-3) = 6e-6 √π.
        let k = basset_coefficient(1e-3, 1000.0, 1e-3);
        assert!((k - 6e-6 * PI.sqrt()).abs() < 1e-20);
    }

    #[test]
    fn van_hinsberg_sum_accuracy_as_published() {
        let k = ExponentialSum::van_hinsberg(1.0);
        assert!((k.eval(1.0) - 1.0).abs() < 1e-4, "matches 1/√t at the window edge");
        for (hi, bound) in [(10.0, 0.0028), (100.0, 0.0070), (1e3, 0.0333), (1e4, 0.103)] {
            let worst = log_grid(0.0, f64::log10(hi), 2000)
                .map(|t| (k.eval(t) * t.sqrt() - 1.0).abs())
                .fold(0.0, f64::max);
            assert!(worst < bound, "[1, {hi}]: {worst}");
            assert!(worst > 0.9 * bound, "[1, {hi}]: the stated error is not loose: {worst}");
        }
        // Scaling with the window: K(t) for t_win = 0.01 s is the same curve in t/t_win.
        let small = ExponentialSum::van_hinsberg(0.01);
        assert!((small.eval(0.37) * 0.1 - k.eval(37.0)).abs() < 1e-15);
    }

    #[test]
    fn inverse_sqrt_sum_meets_its_tolerance() {
        for (t_min, t_max, tol, terms) in
            [(1.0, 1e4, 1e-3, 17), (1e-10, 1.0, 1e-4, 37), (1e-3, 1e3, 1e-8, 68), (1e-4, 1e6, 1e-5, 48)]
        {
            let k = ExponentialSum::inverse_sqrt(t_min, t_max, tol);
            let worst = log_grid(t_min.log10(), t_max.log10(), 2000)
                .map(|t| (k.eval(t) * t.sqrt() - 1.0).abs())
                .fold(0.0, f64::max);
            assert!(worst < tol, "[{t_min}, {t_max}] at {tol}: {worst}");
            assert!(worst > 0.5 * tol, "[{t_min}, {t_max}] at {tol}: the budget is not wasted: {worst}");
            eprintln!("[{t_min}, {t_max}] at {tol}: {} terms, worst {worst:.2e}", k.len());
            assert_eq!(k.len(), terms, "[{t_min}, {t_max}] at {tol}");
        }
    }

    #[test]
    fn settling_without_history_is_the_exponential_approach() {
        for t in [1e-6, 0.01, 0.3, 0.49, 0.5, 0.7, 1.0, 2.0, 5.0, 20.0, 60.0, 200.0] {
            let v = history_settling_velocity(t, &unit(0.0));
            let exact = -(-t).exp_m1();
            assert!((v / exact - 1.0).abs() < 1e-14, "t = {t}: {v} vs {exact}");
        }
        // A vanishing history coefficient: the solution moves by O(c).
        for t in [0.2, 1.0, 4.0] {
            let v = history_settling_velocity(t, &unit(1e-9));
            assert!((v + (-t).exp_m1()).abs() < 3e-9, "t = {t}");
        }
    }

    #[test]
    fn settling_approaches_terminal_velocity_like_one_over_root_t() {
        for kappa in [0.05, 0.7, 1.5, 1.99, 2.0, 2.5, 2.95] {
            let p = unit(kappa);
            let c = p.long_time_coefficient();
            // Next terms of the asymptotic series: −(2κ − κ³)/(2√π) t^{−3/2}, then
            // d₅ t^{−5/2}/Γ(−3/2) with d₅ = κ⁵ − 4κ³ + 3κ and 1/Γ(−3/2) = 3/(4√π).
            let d5 = kappa.powi(5) - 4.0 * kappa.powi(3) + 3.0 * kappa;
            for t in [1e4, 1e6, 1e8] {
                let v = history_settling_velocity(t, &p);
                let two_terms =
                    1.0 - c / t.sqrt() - (2.0 * kappa - kappa.powi(3)) / (2.0 * PI.sqrt()) * t.powf(-1.5);
                let bound = 2.0 * d5.abs() * 3.0 / (4.0 * PI.sqrt()) * t.powf(-2.5) + 1e-15;
                assert!((v - two_terms).abs() < bound, "κ = {kappa}, t = {t}: {v} vs {two_terms}");
                assert!((1.0 - v) * t.sqrt() > 0.99 * c, "κ = {kappa}: slower than the exponential");
            }
        }
    }

    /// `v̂(T) = 1 − (2κ/π) ∫_0^∞ e^{−u²T} du / ((1 − u²)² + κ²u²)`: the Bromwich integral of
    /// `1/(s (s + κ√s + 1))` folded onto the branch cut `s = −u²` (no poles on the principal
    /// sheet), by tanh-sinh quadrature on `[0, 1]` and, with `u = 1/v`, on `[1, ∞)`.
    fn branch_cut_inversion(t: f64, kappa: f64) -> f64 {
        // f on [0, 1] given u and 1 − u (exact near u = 1, where the peak of width κ/2 sits).
        let lower = |u: f64, one_minus_u: f64| {
            let a = one_minus_u * (1.0 + u);
            (-u * u * t).exp() / (a * a + kappa * kappa * u * u)
        };
        // u = 1/v on (1, ∞): du = dv / v², 1 − u² = (v² − 1)/v².
        let upper = |v: f64, one_minus_v: f64| {
            let b = one_minus_v * (1.0 + v); // 1 − v²
            (-t / (v * v)).exp() * v * v / (b * b + kappa * kappa * v * v)
        };
        let tanh_sinh = |f: &dyn Fn(f64, f64) -> f64| {
            let h = 1.0 / 256.0;
            let mut sum = 0.0;
            for j in -(12 * 256)..=(12 * 256) {
                let s = j as f64 * h;
                let q = 0.5 * PI * s.sinh();
                // u = (1 + tanh q)/2 and 1 − u = 1/(1 + e^{2q}), both without cancellation.
                let one_minus_u = 1.0 / (1.0 + (2.0 * q).exp());
                let u = 1.0 / (1.0 + (-2.0 * q).exp());
                let weight = 0.5 * h * 0.5 * PI * s.cosh() / (q.cosh() * q.cosh());
                if weight > 0.0 && u > 0.0 && one_minus_u > 0.0 {
                    sum += weight * f(u, one_minus_u);
                }
            }
            sum
        };
        1.0 - 2.0 * kappa / PI * (tanh_sinh(&lower) + tanh_sinh(&upper))
    }

    #[test]
    fn settling_matches_branch_cut_inversion() {
        for kappa in [0.05, 0.3, 0.7352, 1.2, 1.9999, 2.0, 2.0001, 2.3, 2.9] {
            for t in [0.05, 0.2, 0.5, 0.8, 1.0, 3.0, 10.0, 30.0, 100.0] {
                let v = unit_response(t, kappa);
                let reference = branch_cut_inversion(t, kappa);
                assert!(
                    (v - reference).abs() < 2e-13 * v.abs().max(1e-3),
                    "κ = {kappa}, T = {t}: {v} vs {reference}"
                );
            }
        }
    }

    /// Fixed Talbot inversion (Abate & Valkó 2004, Int. J. Numer. Meth. Eng. 60, 979–993) of
    /// `1/(s (s + κ √s + 1))`, with `M` nodes.
    fn talbot_inversion(t: f64, kappa: f64, nodes: usize) -> f64 {
        let f = |s: Complex| Complex::real(1.0) / (s * (s + s.sqrt().scale(kappa) + Complex::real(1.0)));
        let r = 2.0 * nodes as f64 / (5.0 * t);
        let mut sum = (f(Complex::real(r)) * Complex::real(r * t).exp()).re * 0.5;
        for k in 1..nodes {
            let theta = k as f64 * PI / nodes as f64;
            let cot = theta.cos() / theta.sin();
            let s = Complex::new(r * theta * cot, r * theta);
            let sigma = theta + (theta * cot - 1.0) * cot;
            sum += ((s.scale(t)).exp() * f(s) * Complex::new(1.0, sigma)).re;
        }
        r / nodes as f64 * sum
    }

    #[test]
    fn settling_matches_talbot_inversion() {
        for kappa in [0.1, 0.7352, 2.0, 2.6] {
            for t in [0.1, 0.4, 0.6, 1.0, 5.0, 40.0, 300.0] {
                let v = unit_response(t, kappa);
                let reference = talbot_inversion(t, kappa, 32);
                assert!((v - reference).abs() < 1e-10 * v.abs(), "κ = {kappa}, T = {t}: {v} vs {reference}");
            }
        }
    }

    #[test]
    fn settling_series_and_closed_form_agree_where_they_meet() {
        for kappa in [0.0, 0.5, 1.0, 2.0, 2.5, 2.99] {
            for t in [0.3, 0.49, 0.6, 1.0] {
                let series = small_time_series(t, kappa);
                let closed = if kappa == 2.0 {
                    1.0 + double_root_divided_difference(t, -1.0, 0.0)
                } else {
                    closed_form(t, kappa)
                };
                assert!((series - closed).abs() < 1e-14, "κ = {kappa}, T = {t}: {series} vs {closed}");
            }
        }
    }

    /// The closed form of `unit_response` without its series shortcuts.
    fn closed_form(t: f64, kappa: f64) -> f64 {
        let delta_sq = 0.25 * (kappa * kappa - 4.0);
        let m = -0.5 * kappa;
        let root_t = t.sqrt();
        if delta_sq > 0.0 {
            let d = delta_sq.sqrt();
            let g = |x: f64| faddeeva_w(Complex::new(0.0, -x * root_t)).re / x;
            1.0 + (g(m + d) - g(m - d)) / (2.0 * d)
        } else {
            let omega = (-delta_sq).sqrt();
            let g1 = faddeeva_w(Complex::new(omega * root_t, -m * root_t)) / Complex::new(m, omega);
            1.0 + g1.im / omega
        }
    }

    #[test]
    fn settling_is_continuous_through_the_double_root() {
        for t in [0.7, 3.0, 30.0, 49.0, 51.0, 1e3, 1e6] {
            let at = unit_response(t, 2.0);
            for kappa in [2.0 - 1e-4, 2.0 + 1e-4, 2.0 - 3e-4, 2.0 + 3e-4] {
                let near = unit_response(t, kappa);
                // dv̂/dκ is O(1): the difference is O(|κ − 2|), no jump at the switch.
                assert!(
                    (near - at).abs() < 0.5 * (kappa - 2.0f64).abs(),
                    "T = {t}, κ = {kappa}: {near} vs {at}"
                );
            }
        }
    }

    #[test]
    fn settling_of_a_glass_bead_in_water_starts_at_net_gravity_over_effective_mass() {
        // 1 mm glass bead in water: early on v ≈ A t (history force ∝ √t t, slower).
        let p = HistorySettling::sphere(2500.0, 1000.0, 1e-3, 0.5e-3, 9.81);
        assert!((p.accel - 1500.0 * 9.81 / 3000.0).abs() < 1e-12);
        assert!((p.kappa() - (9.0 * 1000.0 / 6000.0f64).sqrt()).abs() < 1e-12);
        let t = 1e-6 * p.tau;
        assert!((history_settling_velocity(t, &p) / (p.accel * t) - 1.0).abs() < 2e-3);
        assert!(history_settling_velocity(100.0 * p.tau, &p) < p.terminal_velocity());
        // A rising drop comes out negative.
        let drop = HistorySettling::sphere(860.0, 997.0, 0.89e-3, 1e-4, 9.81);
        assert!(history_settling_velocity(drop.tau, &drop) < 0.0);
    }
}
