//! Tables whose keys depend on their `type` (`[[walls]]`, `fluid.flow`): each type reads its
//! own struct, as each effect does (`effects::build_effect`).
//!
//! The file is read in one pass, before the type of a table is known, and a table's `type`
//! may come after its other keys. So the keys that every type of the table has (`name`, `type`,
//! `material`) are read with the file, and the others are kept, each with its place in the
//! file ([`Rest`]); once the type is known they are read into its struct ([`read_as`]). A
//! serde internally tagged enum (`#[serde(tag = "type")]`) refuses unknown keys too, but it
//! reads the table into its own buffer first: its errors name the table (`walls[0]`, at the
//! table's first line), never the key nor the key's line (serde 1.0.229, toml 0.9).
//!
//! A type's keys are listed once: the fields of its struct, read from serde ([`declared_names`])
//! for the messages.

use super::error::Invalid;
use serde::de::{self, DeserializeOwned, IntoDeserializer};
use std::path::Path;
use toml::{Spanned, Value};

/// The keys of a table that its type reads, as given, in file order, each with its place.
#[derive(Debug, Clone, Default)]
pub struct Rest(pub Vec<(String, Spanned<Value>)>);

/// Where a typed table is: its key path (`walls[2]`, `fluid.flow`), what messages call its
/// type (`a plane`) and the file's text, for lines.
pub(super) struct Place<'a> {
    pub key: String,
    pub what: &'static str,
    pub source: &'a str,
}

impl Place<'_> {
    /// The key path of the table's key `f`.
    pub fn k(&self, f: &str) -> String {
        format!("{}.{f}", self.key)
    }
}

/// A type's table: read from the keys its struct has, then built into `Out` (a wall's shape,
/// a flow); files are read relative to `base`.
pub(super) trait Table<Out>: DeserializeOwned {
    /// What messages call the type: "a plane", "a uniform flow".
    const WHAT: &'static str;
    fn build(self, at: &Place, base: &Path) -> Result<Out, Invalid>;
}

/// One entry of a registry of types (`WallType::table`, `FlowType::table`).
pub(super) struct Entry<Out> {
    what: &'static str,
    keys: fn() -> &'static [&'static str],
    build: fn(&Rest, &Place, &Path) -> Result<Out, Invalid>,
}

/// The registry entry of the type whose table is `T`.
pub(super) fn entry<T: Table<Out>, Out>() -> Entry<Out> {
    Entry { what: T::WHAT, keys: declared_names::<T>, build: read_and_build::<T, Out> }
}

fn read_and_build<T: Table<Out>, Out>(rest: &Rest, at: &Place, base: &Path) -> Result<Out, Invalid> {
    read_as::<T>(rest, at)?.build(at, base)
}

/// Builds the table `rest` of type `ty` at `key`: refuses a key that the type does not have,
/// listing those it has (and the types that have that key), then reads and builds its struct.
/// `registry` maps each type to its entry.
pub(super) fn build<Ty, Out>(
    ty: Ty,
    registry: fn(Ty) -> Entry<Out>,
    rest: &Rest,
    key: String,
    source: &str,
    base: &Path,
) -> Result<Out, Invalid>
where
    Ty: DeserializeOwned,
{
    let entry = registry(ty);
    let at = Place { key, what: entry.what, source };
    let keys = (entry.keys)();
    if let Some((extra, value)) = rest.0.iter().find(|(k, _)| !keys.contains(&k.as_str())) {
        let list = if keys.is_empty() {
            "it has no other keys".to_string()
        } else {
            format!("its keys are: {}", keys.join(", "))
        };
        let owners: Vec<String> = declared_names::<Ty>()
            .iter()
            .filter(|name| {
                deserialize_name::<Ty>(name).is_some_and(|t| (registry(t).keys)().contains(&extra.as_str()))
            })
            .map(|name| format!("\"{name}\""))
            .collect();
        let owners = if owners.is_empty() {
            String::new()
        } else {
            format!("; it is a key of type = {}", owners.join(" and "))
        };
        let (line, _) = line_and_column(source, value.span().start);
        return Err(Invalid::new(
            at.k(extra),
            format!("not a key of {}; {list}{owners} (line {line})", at.what),
        ));
    }
    (entry.build)(rest, &at, base)
}

/// Reads `rest` into `T`. A value of the wrong type is reported at its key with its line and
/// column, as the file's own errors are; a missing key at its own path (serde reports it as an
/// error of the table), saying which type needs it.
pub(super) fn read_as<T: DeserializeOwned>(rest: &Rest, at: &Place) -> Result<T, Invalid> {
    let table: toml::Table = rest.0.iter().map(|(k, v)| (k.clone(), v.get_ref().clone())).collect();
    serde_path_to_error::deserialize(Value::Table(table)).map_err(|e| {
        let message = e.inner().message().trim_end().to_string();
        if let Some(field) = message.strip_prefix("missing field `").and_then(|m| m.strip_suffix('`')) {
            return Invalid::new(at.k(field), format!("missing: required for {}", at.what));
        }
        let first = match e.path().iter().next() {
            Some(serde_path_to_error::Segment::Map { key }) => Some(key.as_str()),
            _ => None,
        };
        let place = first
            .and_then(|f| rest.0.iter().find(|(k, _)| k == f))
            .map(|(_, v)| {
                let (line, column) = line_and_column(at.source, v.span().start);
                format!(" (line {line}, column {column})")
            })
            .unwrap_or_default();
        let path = key_path(e.path());
        let key = if path == "." { at.key.clone() } else { at.k(&path) };
        Invalid::new(key, format!("{message}{place}"))
    })
}

/// A key path as `serde_path_to_error` writes it (`walls[2].normal`, `.` for the root), less
/// the private fields through which `toml::Spanned` reads a value (`$__serde_spanned_private_value`):
/// the key of a kept value ([`Rest`], an effect's table) is the value's own.
pub(super) fn key_path(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let mut out = String::new();
    let mut separator: Option<&str> = None;
    for segment in path.iter() {
        if matches!(segment, Segment::Map { key } if key.starts_with("$__serde_spanned_private")) {
            continue;
        }
        if !matches!(segment, Segment::Seq { .. }) {
            out.push_str(separator.unwrap_or(""));
        }
        out.push_str(&segment.to_string());
        separator = Some(".");
    }
    if separator.is_none() { ".".to_string() } else { out }
}

/// 1-based line and column (in bytes) of byte offset `at` in `source`.
pub(super) fn line_and_column(source: &str, at: usize) -> (usize, usize) {
    let before = &source[..floor_char_boundary(source, at)];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

fn floor_char_boundary(s: &str, at: usize) -> usize {
    let mut at = at.min(s.len());
    while !s.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// The names a serde type declares: a struct's fields, or an enum's variants (as the file
/// writes them, after renames), read from what its `Deserialize` asks for.
pub(super) fn declared_names<T: DeserializeOwned>() -> &'static [&'static str] {
    let mut names: &'static [&'static str] = &[];
    let _ = T::deserialize(Names(&mut names));
    names
}

/// The value of `T` named `name` (an enum's variant).
fn deserialize_name<T: DeserializeOwned>(name: &str) -> Option<T> {
    let de: de::value::StrDeserializer<de::value::Error> = name.into_deserializer();
    T::deserialize(de).ok()
}

/// A deserializer that records the names a struct or an enum declares, then stops.
struct Names<'a>(&'a mut &'static [&'static str]);

impl<'de> de::Deserializer<'de> for Names<'_> {
    type Error = de::value::Error;

    fn deserialize_any<V: de::Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Self::Error> {
        Err(de::Error::custom("names only"))
    }

    fn deserialize_struct<V: de::Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        _visitor: V,
    ) -> Result<V::Value, Self::Error> {
        *self.0 = fields;
        Err(de::Error::custom("names only"))
    }

    fn deserialize_enum<V: de::Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        _visitor: V,
    ) -> Result<V::Value, Self::Error> {
        *self.0 = variants;
        Err(de::Error::custom("names only"))
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf option
        unit unit_struct newtype_struct seq tuple tuple_struct map identifier ignored_any
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Two {
        first: f64,
        #[serde(rename = "second_key")]
        second: Option<u32>,
    }

    #[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
    #[serde(rename_all = "snake_case")]
    enum Kinds {
        One,
        TwoWords,
    }

    #[test]
    fn names_are_read_from_the_type_as_the_file_writes_them() {
        assert_eq!(declared_names::<Two>(), ["first", "second_key"]);
        assert_eq!(declared_names::<Kinds>(), ["one", "two_words"]);
        assert_eq!(deserialize_name::<Kinds>("two_words"), Some(Kinds::TwoWords));
    }

    #[test]
    fn lines_and_columns_count_from_one() {
        assert_eq!(line_and_column("a = 1\nbb = 2", 11), (2, 6));
        assert_eq!(line_and_column("é", 1), (1, 1));
    }
}

/// Each wall shape and flow type refuses a key of another type, naming it; and reads its own.
#[cfg(test)]
mod typed_tables {
    use crate::scene::{Scene, SceneError};
    use std::path::Path;

    /// A scene in vacuum with `fluid.flow = flow` and one wall (`wall`, its keys after `name`).
    fn scene(flow: &str, wall: &str) -> Result<Scene, SceneError> {
        let text = format!(
            "[simulation]\ndt = 1e-4\nduration = 0.01\noutput_interval = 1e-3\n\n\
             [fluid]\ndensity = 0.0\nviscosity = 0.0\nflow = {flow}\n\n\
             [[kinds]]\nname = \"glass\"\ntype = \"solid\"\ndensity = 2500.0\nyoungs_modulus = 6e10\n\
             poisson_ratio = 0.23\n\n[[walls]]\nname = \"w\"\n{wall}\n"
        );
        Scene::from_str(&text, Path::new("typed.toml"))
    }

    fn wall(keys: &str) -> Result<Scene, SceneError> {
        scene("{}", keys)
    }

    fn flow(table: &str) -> Result<Scene, SceneError> {
        scene(table, "type = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]")
    }

    /// Asserts the error is about `key` and its message contains every one of `parts`.
    fn refused(result: Result<Scene, SceneError>, key: &str, parts: &[&str]) {
        let e = result.expect_err("refused");
        assert_eq!(e.key(), key, "{e}");
        let text = e.to_string();
        assert!(text.starts_with("typed.toml: "), "{text}");
        for p in parts {
            assert!(text.contains(p), "lacks {p:?}: {text}");
        }
    }

    const PLANE: &str = "type = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]";
    const BOX: &str = "type = \"box\"\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\ninside = true";
    const CYLINDER: &str = "type = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\nradius = 0.5\nlength = 1.0";
    const ANNULUS: &str =
        "type = \"annulus\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nouter_radius = 0.5";

    #[test]
    fn each_wall_shape_reads_its_own_keys() {
        for keys in [PLANE, BOX, CYLINDER, ANNULUS] {
            let scene = wall(keys).unwrap_or_else(|e| panic!("{keys}: {e}"));
            assert_eq!(scene.setup.walls.len(), 1);
        }
        // `type` after the shape's keys, and the common keys anywhere.
        let late = "point = [0.0, 0.0, 0.0]\nmaterial = { restitution_max = 0.5 }\nnormal = [0.0, 0.0, 1.0]\ntype = \"plane\"";
        let scene = wall(late).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scene.setup.walls[0].material.restitution_max, Some(0.5));
    }

    #[test]
    fn a_plane_refuses_a_key_of_another_shape_naming_it() {
        refused(
            wall(&format!("{PLANE}\nradius = 0.1")),
            "walls[0].radius",
            &["not a key of a plane; its keys are: point, normal", "type = \"cylinder\"", "(line "],
        );
    }

    #[test]
    fn a_box_refuses_a_key_of_another_shape_naming_it() {
        refused(
            wall(&format!("{BOX}\nnormal = [0.0, 0.0, 1.0]")),
            "walls[0].normal",
            &["not a key of a box; its keys are: min, max, inside", "\"plane\" and \"annulus\""],
        );
    }

    #[test]
    fn a_cylinder_refuses_a_key_of_another_shape_naming_it() {
        refused(
            wall(&format!("{CYLINDER}\nouter_radius = 0.1")),
            "walls[0].outer_radius",
            &["not a key of a cylinder; its keys are: base, axis, radius, length", "\"annulus\""],
        );
    }

    #[test]
    fn a_mesh_refuses_a_key_of_another_shape_naming_it() {
        refused(
            wall("type = \"mesh\"\nfile = \"plate.stl\"\ninside = false"),
            "walls[0].inside",
            &["not a key of a mesh; its keys are: file, scale, translate", "\"box\""],
        );
    }

    #[test]
    fn an_annulus_refuses_a_key_of_another_shape_naming_it() {
        refused(
            wall(&format!("{ANNULUS}\nscale = 2.0")),
            "walls[0].scale",
            &[
                "not a key of an annulus; its keys are: center, normal, inner_radius, outer_radius",
                "\"mesh\"",
            ],
        );
    }

    #[test]
    fn an_unknown_wall_key_is_refused_with_the_keys_of_the_shape() {
        refused(wall(&format!("{PLANE}\nnormall = 1")), "walls[0].normall", &["its keys are: point, normal"]);
    }

    #[test]
    fn a_missing_or_mistyped_wall_key_is_named() {
        refused(
            wall("type = \"plane\"\npoint = [0.0, 0.0, 0.0]"),
            "walls[0].normal",
            &["missing: required for a plane"],
        );
        refused(
            wall("type = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\nradius = \"big\""),
            "walls[0].radius",
            &["invalid type: string \"big\", expected f64", "(line 22, column 10)"],
        );
        refused(
            wall("type = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]"),
            "walls[0].inside",
            &["true: particles inside it"],
        );
        refused(wall("point = [0.0, 0.0, 0.0]"), "walls[0]", &["missing field `type`"]);
        refused(wall("type = \"sphere\""), "walls[0].type", &["unknown variant `sphere`"]);
        refused(
            wall(&format!("{PLANE}\nmaterial = {{ rough = 1 }}")),
            "walls[0].material.rough",
            &["unknown field"],
        );
    }

    /// A value that fails in the file's own reader (a float beyond f64) is reported at its key,
    /// not at the private field through which `toml::Spanned` keeps it.
    #[test]
    fn a_value_that_toml_cannot_read_is_reported_at_its_key() {
        refused(
            wall("type = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\nradius = 1e400"),
            "walls[0].radius",
            &["overflowed", "(line 22, column 10)"],
        );
        refused(
            flow("{ type = \"poiseuille\", point = [0.0, 0.0, 0.0], radius = 1e400, max_velocity = 0.1 }"),
            "fluid.flow.radius",
            &["overflowed"],
        );
    }

    #[test]
    fn each_flow_reads_its_own_keys() {
        for table in [
            "{}",
            "{ type = \"quiescent\" }",
            "{ type = \"uniform\", velocity = [0.1, 0.0, 0.0] }",
            "{ point = [0.0, 0.0, 0.0], radius = 0.1, max_velocity = 0.2, type = \"poiseuille\" }",
        ] {
            flow(table).unwrap_or_else(|e| panic!("{table}: {e}"));
        }
    }

    #[test]
    fn a_quiescent_flow_refuses_any_key_naming_it() {
        refused(
            flow("{ velocity = [0.1, 0.0, 0.0] }"),
            "fluid.flow.velocity",
            &["not a key of a quiescent flow; it has no other keys", "\"uniform\""],
        );
    }

    #[test]
    fn a_uniform_flow_refuses_a_key_of_another_flow_naming_it() {
        refused(
            flow("{ type = \"uniform\", velocity = [0.1, 0.0, 0.0], radius = 0.1 }"),
            "fluid.flow.radius",
            &["not a key of a uniform flow; its keys are: velocity", "\"poiseuille\""],
        );
    }

    #[test]
    fn a_poiseuille_flow_refuses_a_key_of_another_flow_naming_it() {
        refused(
            flow(
                "{ type = \"poiseuille\", point = [0.0, 0.0, 0.0], radius = 0.1, max_velocity = 0.2, period = 1.0 }",
            ),
            "fluid.flow.period",
            &["not a key of a poiseuille flow; its keys are: point, axis, radius", "\"field\""],
        );
    }

    #[test]
    fn a_field_flow_refuses_a_key_of_another_flow_naming_it() {
        refused(
            flow("{ type = \"field\", file = \"u.vti\", velocity = [0.1, 0.0, 0.0] }"),
            "fluid.flow.velocity",
            &["not a key of a field flow; its keys are: file, files, times", "\"uniform\""],
        );
    }

    #[test]
    fn a_missing_or_mistyped_flow_key_is_named() {
        refused(
            flow("{ type = \"uniform\" }"),
            "fluid.flow.velocity",
            &["missing: required for a uniform flow"],
        );
        refused(
            flow("{ type = \"uniform\", velocity = [0.1, 0.0] }"),
            "fluid.flow.velocity",
            &["must be 3 numbers [x, y, z], got 2 values"],
        );
    }
}
