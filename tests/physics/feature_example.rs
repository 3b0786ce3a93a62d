//! The worked example of docs/architecture.md, "Features that own their state": a new stateful
//! feature written in one place — a drop's temperature relaxing to the liquid's (a heat balance
//! at Nu = 2) and a count of its contacts — and registered by one line. The store carries its
//! columns through injection, outlets and commit without a line of its own: every drop alive
//! at the end has exactly the temperature of its age and exactly the contacts of its events.

use crate::common;
use std::collections::TryReserveError;
use std::sync::Arc;
use wetbounce::particles::{Feature, Next, Particles, Touch};

/// A drop's temperature `T` (K) under `dT/dt = (T_f − T)/τ`, `τ = ρp c_p d² / (12 k)` (heat
/// transfer to a still liquid, Nu = 2), integrated exactly over each step, and a count of the
/// contacts of each drop (to show [`Feature::after_contact`]).
#[derive(Debug, Clone)]
struct Heat {
    /// The liquid's temperature (K).
    liquid: f64,
    /// A new drop's temperature (K).
    injected: f64,
    /// `ρp c_p / (12 k)` (s/m²): `τ = rate · d²`.
    tau_per_d2: f64,
}

impl Heat {
    fn tau(&self, d: f64) -> f64 {
        self.tau_per_d2 * d * d
    }
}

impl Feature for Heat {
    fn name(&self) -> &'static str {
        "heat"
    }

    fn start(&self, p: &mut Particles) -> Result<(), TryReserveError> {
        p.add_column("temperature", 1, self.injected)?;
        p.add_column("contacts", 1, 0.0)?;
        Ok(())
    }

    fn end_of_step(&self, p: &mut Particles, next: &mut Next, h: f64) {
        let slot = p.column_slot("temperature").expect("started");
        for (t, &d) in next.column_mut(slot).iter_mut().zip(&p.diameter) {
            *t = self.liquid + (*t - self.liquid) * (-h / self.tau(d)).exp();
        }
    }

    fn after_contact(&self, touch: &Touch, next: &mut Next) {
        // The slots are the order `start` made them in.
        next.column_mut(1)[touch.index] += 1.0;
    }
}

#[test]
fn a_feature_written_in_one_place_has_its_columns_carried_through_injection_outlets_and_commit() {
    // Drops injected at 2000/s into a 30 mm box of water, rising through an outlet plane 20 mm
    // above: particles are added, removed and renumbered at most steps.
    let mut scene = common::scene(crate::inject_outlets_counts::RISING);
    // Toluene: ρp c_p = 860 × 1700 J/(m³ K), k = 0.6 W/(m K) for the liquid around it.
    let heat = Heat { liquid: 293.0, injected: 333.0, tau_per_d2: 860.0 * 1700.0 / (12.0 * 0.6) };
    // The one registration line (an effect does it in its `apply`).
    scene.setup.physics.features.add(Arc::new(heat.clone()));
    let mut sim = scene.simulation();
    sim.advance_to(0.6);
    let p = &sim.world.particles;
    let removed: usize = sim.record.removed.iter().map(Vec::len).sum();
    assert!(p.len() > 100 && removed > 100, "{} alive, {removed} removed", p.len());
    let temperature = p.column("temperature").expect("made by the feature").values();
    let contacts = p.column("contacts").expect("made by the feature").values();
    assert_eq!((temperature.len(), contacts.len()), (p.len(), p.len()));
    let mut touched = 0;
    for i in 0..p.len() {
        let age = sim.world.time - p.born[i];
        let exact = heat.liquid + (heat.injected - heat.liquid) * (-age / heat.tau(p.diameter[i])).exp();
        assert!(
            (temperature[i] - exact).abs() < 1e-9 * exact,
            "drop {} aged {age} s: {} K, exactly {exact} K",
            p.id[i],
            temperature[i]
        );
        let events = sim.record.events.iter().filter(|e| e.id == p.id[i]).count();
        assert_eq!(contacts[i], events as f64, "drop {}", p.id[i]);
        touched += usize::from(events > 0);
    }
    assert!(touched > 10, "only {touched} drops touched anything");
}
