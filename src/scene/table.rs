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
    let table: toml::Table =
        rest.0.iter().map(|(k, v)| (k.clone(), dates_as_in_the_file(v.get_ref()))).collect();
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

/// `value` with each date as the file's reader shows it to serde: a table of one private key
/// (toml's own `$__toml_private_datetime`). A `toml::Value` shows a date as a string instead,
/// which would make `[0.0, 0.0, 1979-05-27]` "component 2 is a string", `file = 1979-05-27` a
/// file name, and the messages differ from the file's other tables.
fn dates_as_in_the_file(value: &Value) -> Value {
    match value {
        Value::Datetime(d) => {
            let mut date = toml::Table::new();
            date.insert("$__toml_private_datetime".into(), Value::String(d.to_string()));
            Value::Table(date)
        }
        Value::Array(items) => Value::Array(items.iter().map(dates_as_in_the_file).collect()),
        Value::Table(t) => {
            Value::Table(t.iter().map(|(k, v)| (k.clone(), dates_as_in_the_file(v))).collect())
        }
        other => other.clone(),
    }
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
