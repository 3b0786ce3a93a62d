//! The tests' standard scene: solid beads over a floor plane at z = 0 in water, falling
//! (gravity, buoyancy, drag, added mass). A test changes only what it needs and renders TOML
//! text, or a [`Scene`] through [`super::scene`].
//!
//! Unless changed: `dt = 1e-3`, `duration = 1.0`, `output_interval = 1.0`, the file's default
//! integrator; water (ρ = 998.2 kg/m³, μ = 1.0e-3 Pa·s) with the file's default gravity and no
//! flow; effects `gravity`, `buoyancy`, `drag`, `added_mass`; no `[bounce]` keys; one kind,
//! "glass", solid, ρp = 2500 kg/m³, E = 6e10 Pa, ν = 0.23, the file's default `restitution_max`;
//! the wall [`FLOOR`]; 2 mm particles, none until a test adds them.

use glam::DVec3;
use wetbounce::Scene;

/// The floor: the plane z = 0, facing up.
pub const FLOOR: &str =
    "[[walls]]\nname = \"floor\"\ntype = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n";

/// The effects of a bead falling in a liquid.
pub const FALLING: &str = "gravity = {}\nbuoyancy = {}\ndrag = {}\nadded_mass = {}";

/// The bead-on-a-floor scene; see the module's documentation for what it holds unless changed.
#[derive(Debug, Clone)]
pub struct BeadOnFloor {
    dt: f64,
    duration: f64,
    output_interval: f64,
    integrator: Option<String>,
    fluid: (f64, f64),
    gravity: Option<DVec3>,
    flow: Option<String>,
    effects: String,
    bounce: String,
    kind: String,
    density: f64,
    youngs_modulus: f64,
    poisson_ratio: f64,
    restitution_max: Option<f64>,
    roughness: Option<f64>,
    walls: String,
    diameter: f64,
    particles: Vec<(DVec3, DVec3)>,
    extra: String,
}

impl Default for BeadOnFloor {
    fn default() -> Self {
        BeadOnFloor {
            dt: 1e-3,
            duration: 1.0,
            output_interval: 1.0,
            integrator: None,
            fluid: (998.2, 1.0e-3),
            gravity: None,
            flow: None,
            effects: FALLING.to_string(),
            bounce: String::new(),
            kind: "glass".to_string(),
            density: 2500.0,
            youngs_modulus: 6e10,
            poisson_ratio: 0.23,
            restitution_max: None,
            roughness: None,
            walls: FLOOR.to_string(),
            diameter: 2e-3,
            particles: Vec::new(),
            extra: String::new(),
        }
    }
}

/// `[x, y, z]` with every digit needed to read back the same numbers.
fn vector(v: DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}

impl BeadOnFloor {
    pub fn new() -> Self {
        Self::default()
    }

    /// `simulation.dt` (s).
    pub fn dt(mut self, dt: f64) -> Self {
        self.dt = dt;
        self
    }

    /// `simulation.duration` (s).
    pub fn duration(mut self, duration: f64) -> Self {
        self.duration = duration;
        self
    }

    /// `simulation.output_interval` (s).
    pub fn output_interval(mut self, interval: f64) -> Self {
        self.output_interval = interval;
        self
    }

    /// `simulation.integrator` ("euler", "rk2", "rk4", "exponential").
    pub fn integrator(mut self, name: &str) -> Self {
        self.integrator = Some(name.to_string());
        self
    }

    /// The fluid's density (kg/m³) and viscosity (Pa·s).
    pub fn fluid(mut self, density: f64, viscosity: f64) -> Self {
        self.fluid = (density, viscosity);
        self
    }

    /// No fluid: density and viscosity 0.
    pub fn vacuum(self) -> Self {
        self.fluid(0.0, 0.0)
    }

    /// `fluid.gravity` (m/s²), written out instead of left to the file's default.
    pub fn gravity(mut self, g: impl Into<DVec3>) -> Self {
        self.gravity = Some(g.into());
        self
    }

    /// `fluid.flow`, an inline table such as `{ type = "uniform", velocity = [0.01, 0.0, 0.0] }`.
    pub fn flow(mut self, table: &str) -> Self {
        self.flow = Some(table.to_string());
        self
    }

    /// The `[effects]` table's lines, replacing [`FALLING`] ("" for no effect at all).
    pub fn effects(mut self, lines: &str) -> Self {
        self.effects = lines.to_string();
        self
    }

    /// The `[bounce]` table's lines, e.g. `st_critical = 10.0`.
    pub fn bounce(mut self, lines: &str) -> Self {
        self.bounce = lines.to_string();
        self
    }

    /// The kind's name (the particles refer to it).
    pub fn kind(mut self, name: &str) -> Self {
        self.kind = name.to_string();
        self
    }

    /// The kind's density (kg/m³).
    pub fn density(mut self, density: f64) -> Self {
        self.density = density;
        self
    }

    /// The kind's Young's modulus (Pa) and Poisson's ratio.
    pub fn elastic(mut self, youngs_modulus: f64, poisson_ratio: f64) -> Self {
        self.youngs_modulus = youngs_modulus;
        self.poisson_ratio = poisson_ratio;
        self
    }

    /// The kind's Poisson's ratio alone.
    pub fn poisson_ratio(mut self, poisson_ratio: f64) -> Self {
        self.poisson_ratio = poisson_ratio;
        self
    }

    /// The kind's `restitution_max`.
    pub fn restitution_max(mut self, eps_max: f64) -> Self {
        self.restitution_max = Some(eps_max);
        self
    }

    /// The walls: whole `[[walls]]` tables replacing [`FLOOR`] ("" for none).
    /// The kind's `roughness` (m), for the wall-lubrication effect.
    pub fn roughness(mut self, h_r: f64) -> Self {
        self.roughness = Some(h_r);
        self
    }

    pub fn walls(mut self, tables: &str) -> Self {
        self.walls = tables.to_string();
        self
    }

    /// One more wall after those there are: a whole `[[walls]]` table.
    pub fn wall(mut self, table: &str) -> Self {
        if !self.walls.is_empty() && !self.walls.ends_with('\n') {
            self.walls.push('\n');
        }
        self.walls += table;
        self
    }

    /// The diameter of every particle (m).
    pub fn diameter(mut self, d: f64) -> Self {
        self.diameter = d;
        self
    }

    /// One more particle, at `position` (m) moving at `velocity` (m/s).
    pub fn particle(mut self, position: impl Into<DVec3>, velocity: impl Into<DVec3>) -> Self {
        self.particles.push((position.into(), velocity.into()));
        self
    }

    /// One more particle, at rest at `position` (m).
    pub fn at(self, position: impl Into<DVec3>) -> Self {
        self.particle(position, DVec3::ZERO)
    }

    /// More particles, as (position, velocity).
    pub fn particles<'a>(mut self, starts: impl IntoIterator<Item = &'a (DVec3, DVec3)>) -> Self {
        self.particles.extend(starts);
        self
    }

    /// TOML tables added at the end (outlets, injectors).
    pub fn extra(mut self, tables: &str) -> Self {
        self.extra += tables;
        self.extra.push('\n');
        self
    }

    /// The scene file's text.
    pub fn toml(&self) -> String {
        let mut t = String::from("[simulation]\n");
        t += &format!("dt = {:?}\n", self.dt);
        t += &format!("duration = {:?}\n", self.duration);
        t += &format!("output_interval = {:?}\n", self.output_interval);
        if let Some(name) = &self.integrator {
            t += &format!("integrator = \"{name}\"\n");
        }
        t += &format!("\n[fluid]\ndensity = {:?}\nviscosity = {:?}\n", self.fluid.0, self.fluid.1);
        if let Some(g) = self.gravity {
            t += &format!("gravity = {}\n", vector(g));
        }
        if let Some(flow) = &self.flow {
            t += &format!("flow = {flow}\n");
        }
        if !self.bounce.is_empty() {
            t += &format!("\n[bounce]\n{}\n", self.bounce);
        }
        t += &format!("\n[effects]\n{}\n", self.effects);
        t += &format!(
            "\n[[kinds]]\nname = \"{}\"\ntype = \"solid\"\ndensity = {:?}\nyoungs_modulus = {:?}\npoisson_ratio = {:?}\n",
            self.kind, self.density, self.youngs_modulus, self.poisson_ratio
        );
        if let Some(eps) = self.restitution_max {
            t += &format!("restitution_max = {eps:?}\n");
        }
        if let Some(h_r) = self.roughness {
            t += &format!("roughness = {h_r:?}\n");
        }
        t += &format!("\n{}\n", self.walls);
        for (x, v) in &self.particles {
            t += &format!(
                "[[particles]]\nkind = \"{}\"\ndiameter = {:?}\nposition = {}\nvelocity = {}\n\n",
                self.kind,
                self.diameter,
                vector(*x),
                vector(*v)
            );
        }
        t += &self.extra;
        t
    }

    /// The scene, read from [`Self::toml`] as if from a file in `scenes/`.
    pub fn scene(&self) -> Scene {
        super::scene(&self.toml())
    }
}
