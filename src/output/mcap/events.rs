//! The contacts on the MCAP: `/events`, one JSON message per contact with the columns of
//! `events.csv`, and `/event_log`, the same contact as a line of Foxglove's Log panel.

use foxglove::messages::log::Level;

/// JSON schema of an `/events` message: the columns of `events.csv`. Non-finite numbers (an
/// infinite St in vacuum) are written as `null`, which JSON needs. A particle taken out because
/// its state became non-finite is an event of kind `removed`, outcome `non_finite`, `other`
/// empty and the numbers `null`.
///
/// Each property has one type, `number` even where the value may be `null`: Foxglove's reader
/// of JSON schemas (the one of its MCAP support, which Lichtblick shares) takes a single type
/// per field and refused the whole topic for `["number", "null"]` ("Unsupported type"); it
/// reads a `null` value as empty. The descriptions say where a `null` can be.
pub(super) const EVENT_SCHEMA: &str = r#"{
  "title": "wetbounce.ContactEvent",
  "description": "One contact: the columns of events.csv",
  "type": "object",
  "properties": {
    "t": {"type": "number", "description": "impact time (s)"},
    "id": {"type": "integer", "description": "particle id"},
    "other": {"type": "string", "description": "wall name or other particle's id"},
    "kind": {"type": "string", "enum": ["wall", "particle", "removed"]},
    "normal_speed": {"type": "number", "description": "V_inf (m/s); null if not finite"},
    "st": {"type": "number", "description": "Stokes number; null if infinite (vacuum)"},
    "eps": {"type": "number", "description": "restitution applied; null if not finite"},
    "contact_time": {"type": "number", "description": "t_c (s); null if not finite"},
    "outcome": {"type": "string", "enum": ["held", "bounced", "deposited", "non_finite"]}
  },
  "required": ["t", "id", "other", "kind", "normal_speed", "st", "eps", "contact_time", "outcome"]
}"#;

/// The two properties [`EVENT_SCHEMA`] gains in a scene with rotation, as in `events.csv`.
const SPIN_EVENT_PROPERTIES: &str = r#",
    "tangential_speed": {"type": "number", "description": "contact point's tangential speed at impact (m/s); null if not finite"},
    "incidence_angle": {"type": "number", "description": "angle of the velocity from the normal (rad); null if not finite"}"#;

/// [`EVENT_SCHEMA`], with [`SPIN_EVENT_PROPERTIES`] after its last property when `rotation`.
pub(super) fn event_schema(rotation: bool) -> String {
    let last = r#""enum": ["held", "bounced", "deposited", "non_finite"]}"#;
    if rotation {
        EVENT_SCHEMA.replacen(last, &format!("{last}{SPIN_EVENT_PROPERTIES}"), 1)
    } else {
        EVENT_SCHEMA.to_string()
    }
}

/// An `/events` message: the columns of `events.csv`, in its order.
#[derive(serde::Serialize)]
pub(super) struct EventMessage<'a> {
    pub(super) t: Option<f64>,
    pub(super) id: u32,
    pub(super) other: String,
    pub(super) kind: &'a str,
    pub(super) normal_speed: Option<f64>,
    pub(super) st: Option<f64>,
    pub(super) eps: Option<f64>,
    pub(super) contact_time: Option<f64>,
    pub(super) outcome: &'a str,
    // Left out of the message (not `null`) in a scene without rotation, which keeps its bytes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) tangential_speed: Option<Option<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) incidence_angle: Option<Option<f64>>,
}

/// A number, or `null` for a non-finite one (JSON has no infinity).
pub(super) fn number(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// The Log panel's level of an outcome: what a user filters by. A deposition ends a
/// particle's bouncing (a warning), a particle taken out is a fault (an error).
pub(super) fn event_level(outcome: &str) -> Level {
    match outcome {
        "deposited" => Level::Warning,
        "non_finite" => Level::Error,
        _ => Level::Info,
    }
}

impl EventMessage<'_> {
    /// The contact as one line of text, e.g. `particle 3 bounced on wall bottom: V∞ = 0.12 m/s,
    /// St = 45.1, ε = 0.62, t_c = 2.1e-3 s`.
    pub(super) fn line(&self) -> String {
        let num = |x: Option<f64>| x.map_or_else(|| "∞".to_string(), |v| format!("{v:.3}"));
        if self.kind == "removed" {
            return format!("particle {} removed: its state became non-finite", self.id);
        }
        let mut line = format!(
            "particle {} {} on {} {}: V∞ = {} m/s, St = {}, ε = {}, t_c = {} s",
            self.id,
            self.outcome,
            self.kind,
            self.other,
            num(self.normal_speed),
            num(self.st),
            num(self.eps),
            // A deposit has no contact time: 0, not 0.000e0.
            self.contact_time.map_or_else(
                || "∞".to_string(),
                |v| if v == 0.0 { "0".to_string() } else { format!("{v:.3e}") }
            ),
        );
        if let Some(Some(angle)) = self.incidence_angle {
            line.push_str(&format!(", incidence {:.1}°", angle.to_degrees()));
        }
        line
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rotation_event_schema_is_json_with_two_more_properties() {
        let v: serde_json::Value = serde_json::from_str(&event_schema(true)).unwrap();
        assert!(
            v["properties"]["tangential_speed"].is_object() && v["properties"]["incidence_angle"].is_object()
        );
        assert_eq!(event_schema(false), EVENT_SCHEMA);
    }

    #[test]
    fn every_event_property_has_one_type_as_foxglove_reads_schemas() {
        // Foxglove's (and Lichtblick's) JSON-schema reader refuses the whole topic when a
        // property's type is a list, such as ["number", "null"].
        let v: serde_json::Value = serde_json::from_str(&event_schema(true)).unwrap();
        for (name, property) in v["properties"].as_object().unwrap() {
            let ty = property["type"].as_str();
            assert!(matches!(ty, Some("number" | "integer" | "string")), "{name}: {}", property["type"]);
        }
    }
}
