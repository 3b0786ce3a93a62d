//! Scene errors: every one names the file, the key path and the bad value.

use std::path::PathBuf;

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{file}: cannot read the scene file: {source}")]
    Read {
        /// The scene file.
        file: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is not valid TOML, or a value has the wrong type, or a key is missing or unknown.
    #[error("{file}: {key}: {message}")]
    Parse {
        /// The scene file.
        file: PathBuf,
        /// Dotted key path (`kinds[0].density`); `(top level)` for the whole file.
        key: String,
        /// What is wrong, with the line and column.
        message: String,
    },
    /// A value is out of range, an unknown name, or inconsistent with the rest of the scene.
    #[error("{file}: {key}: {message}")]
    Invalid {
        /// The scene file.
        file: PathBuf,
        /// Dotted key path.
        key: String,
        /// What is wrong, with the bad value.
        message: String,
    },
}

impl SceneError {
    /// The key path the error is about.
    pub fn key(&self) -> &str {
        match self {
            SceneError::Read { .. } => "",
            SceneError::Parse { key, .. } | SceneError::Invalid { key, .. } => key,
        }
    }
}

/// Collects the key and message of a validation failure; the loader adds the file.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Invalid {
    pub key: String,
    pub message: String,
}

impl Invalid {
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        Invalid { key: key.into(), message: message.into() }
    }
}

/// How numbers are written in scene messages: one helper, so that no message prints a huge
/// or tiny value digit by digit (`{}` writes 1e300 as 301 digits).
pub(crate) mod fmt {
    /// The shortest text that reads back as `v`: plain from 1e-4 up to 1e4 (`0.001`, `2500`,
    /// `-0.00089`), scientific outside (`1e300`, `1e4`, `6.3e10`, `1e-7`); `NaN`, `inf`, `-inf`.
    /// The engine's one rule ([`crate::numeric::num`]), which the field reader below the scene
    /// uses too.
    pub use crate::numeric::num;

    /// A count or a ratio that need not be exact: as [`num`] below 1e4 (to 3 decimals), and
    /// to three significant digits above (`1.2346e12` is `1.23e12`, `1e298` stays `1e298`).
    pub fn approx(v: f64) -> String {
        if !v.is_finite() || v.abs() < 1e4 {
            return num((v * 1e3).round() / 1e3);
        }
        let s = format!("{v:.2e}");
        // `1.00e298` → `1e298`, `1.20e12` → `1.2e12`.
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{mantissa}e{exponent}")
    }

    /// `text` with every number longer than 20 characters rewritten by [`num`]. Scene
    /// messages write their own numbers with [`num`]; this is for the text they quote from
    /// elsewhere, which cannot be told how to print: serde's (``invalid type: floating point
    /// `1000…0.0`, expected a string``), a TOML value's, an effect's or a mesh loader's. It is
    /// applied once, where a [`super::SceneError`] is made. A number written by [`num`] is left
    /// as it is.
    pub fn shorten_long_numbers(text: &str) -> String {
        let b = text.as_bytes();
        let mut out = String::with_capacity(text.len());
        let mut i = 0;
        while i < b.len() {
            let starts_number =
                b[i].is_ascii_digit() || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit));
            let inside_word =
                i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.');
            if !starts_number || inside_word {
                let next = text[i..].chars().next().map_or(1, char::len_utf8);
                out.push_str(&text[i..i + next]);
                i += next;
                continue;
            }
            let mut end = i + 1;
            while end < b.len()
                && (b[end].is_ascii_digit()
                    || b[end] == b'.'
                    || ((b[end] == b'e' || b[end] == b'E') && end + 1 < b.len())
                    || ((b[end] == b'-' || b[end] == b'+') && matches!(b[end - 1], b'e' | b'E')))
            {
                end += 1;
            }
            let token = &text[i..end];
            match token.parse::<f64>() {
                Ok(v) if token.len() > 20 => out.push_str(&num(v)),
                _ => out.push_str(token),
            }
            i = end;
        }
        out
    }

    /// `[x, y, z]`, each written by [`num`].
    pub fn vec3(v: [f64; 3]) -> String {
        format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
    }
}

/// Checks of the scene's fields, each returning the value or an [`Invalid`] naming `key`.
pub(crate) mod check {
    use super::Invalid;
    use super::fmt::{num, vec3};
    use crate::scene::ranges::{COORDINATE, Range};
    use crate::scene::schema::Vec3Spec;
    use glam::DVec3;

    /// A key that the entry's `type` (`what`: "a plane", "a box injector region") needs.
    pub fn required<T>(key: &str, v: Option<T>, what: &str) -> Result<T, Invalid> {
        v.ok_or_else(|| Invalid::new(key, format!("missing: required for {what}")))
    }

    /// A key that the entry's `type` does not have.
    pub fn forbid(key: &str, present: bool, what: &str) -> Result<(), Invalid> {
        if present { Err(Invalid::new(key, format!("not a key of {what}"))) } else { Ok(()) }
    }

    /// Rejects the first key of the table at `key` that is present but not `allowed` for its
    /// `type` (`what`), listing the allowed ones. The one check of every table whose keys
    /// depend on its type (flows, walls, injector regions and sizes, outlets).
    pub fn only(key: &str, present: &[(&str, bool)], allowed: &[&str], what: &str) -> Result<(), Invalid> {
        let Some((extra, _)) = present.iter().find(|(name, here)| *here && !allowed.contains(name)) else {
            return Ok(());
        };
        let keys = if allowed.is_empty() {
            "it has no other keys".to_string()
        } else {
            format!("its keys are: {}", allowed.join(", "))
        };
        Err(Invalid::new(format!("{key}.{extra}"), format!("not a key of {what}; {keys}")))
    }

    pub fn finite(key: &str, v: f64) -> Result<f64, Invalid> {
        if v.is_finite() { Ok(v) } else { Err(Invalid::new(key, format!("must be finite, got {}", num(v)))) }
    }

    pub fn positive(key: &str, v: f64) -> Result<f64, Invalid> {
        finite(key, v)?;
        if v > 0.0 { Ok(v) } else { Err(Invalid::new(key, format!("must be > 0, got {}", num(v)))) }
    }

    pub fn non_negative(key: &str, v: f64) -> Result<f64, Invalid> {
        finite(key, v)?;
        if v >= 0.0 { Ok(v) } else { Err(Invalid::new(key, format!("must be >= 0, got {}", num(v)))) }
    }

    pub fn in_range(key: &str, v: f64, lo: f64, hi: f64) -> Result<f64, Invalid> {
        finite(key, v)?;
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(Invalid::new(key, format!("must be between {} and {}, got {}", num(lo), num(hi), num(v))))
        }
    }

    /// A value > 0 (the sign checked first, with the message of [`positive`]) within `range`.
    pub fn positive_in(key: &str, v: f64, range: &Range) -> Result<f64, Invalid> {
        range.check(key, positive(key, v)?)
    }

    /// A value >= 0 within `range` (0 itself only if the range allows it).
    pub fn non_negative_in(key: &str, v: f64, range: &Range) -> Result<f64, Invalid> {
        range.check(key, non_negative(key, v)?)
    }

    /// A finite value of any sign whose magnitude is within `range` (a coordinate, a speed);
    /// returns the value with its sign.
    pub fn signed_in(key: &str, v: f64, range: &Range) -> Result<f64, Invalid> {
        let v = finite(key, v)?;
        range.check_magnitude(key, v.abs(), &num(v))?;
        Ok(v)
    }

    /// A random seed: 0 to 2^63 - 1, as documented. A TOML integer is a signed 64-bit one, but
    /// the toml crate reads 2^63 to 2^64 - 1 into a `u64` too; a scene that relies on that
    /// would not be TOML that other readers accept.
    pub fn seed(key: &str, v: u64) -> Result<u64, Invalid> {
        if v > i64::MAX as u64 {
            return Err(Invalid::new(key, format!("must be 0 to 2^63 - 1 (a TOML integer), got {v}")));
        }
        Ok(v)
    }

    pub fn vector(key: &str, v: Vec3Spec) -> Result<DVec3, Invalid> {
        let d = DVec3::from(v.0);
        if d.is_finite() {
            Ok(d)
        } else {
            Err(Invalid::new(key, format!("must have finite components, got {}", vec3(v.0))))
        }
    }

    /// A point (m): every coordinate within the range of coordinates.
    pub fn point(key: &str, v: Vec3Spec) -> Result<DVec3, Invalid> {
        let d = vector(key, v)?;
        if COORDINATE.contains(d.abs().max_element()) {
            Ok(d)
        } else {
            let message = format!(
                "every coordinate must be within ±{} m (the range of coordinates), got {}",
                num(COORDINATE.max),
                vec3(v.0)
            );
            Err(Invalid::new(key, message))
        }
    }

    /// A vector whose length is within `range` (a velocity, gravity). The length is computed
    /// without overflow, so that `[1e200, 0, 0]` is reported as 1e200, not as infinite.
    pub fn magnitude_in(key: &str, v: Vec3Spec, range: &Range) -> Result<DVec3, Invalid> {
        let d = vector(key, v)?;
        range.check_magnitude(key, length(d), &format!("{} (length {})", vec3(v.0), num(length(d))))?;
        Ok(d)
    }

    /// The length of a finite vector, without overflow or underflow: scaled by its largest
    /// component first.
    pub fn length(d: DVec3) -> f64 {
        let m = d.abs().max_element();
        if m == 0.0 { 0.0 } else { m * (d / m).length() }
    }

    /// A direction: any finite non-zero vector, returned normalised.
    ///
    /// `length()` squares the components: from about 1e154 up the square overflows and the
    /// vector normalised to zero (an outlet that removed nothing, a flow switched off), and
    /// below about 1e-154 it underflows. Such a vector is scaled by its largest component
    /// first. A vector whose length is an ordinary number is divided by it as before, so that
    /// every direction that worked gives the same bits.
    pub fn direction(key: &str, v: Vec3Spec) -> Result<DVec3, Invalid> {
        let d = vector(key, v)?;
        let len = d.length();
        if len.is_finite() && len > 1e-150 {
            return Ok(d / len);
        }
        let m = d.abs().max_element();
        if m > 0.0 {
            let unit = d / m;
            Ok(unit / unit.length())
        } else {
            Err(Invalid::new(key, format!("must be a non-zero vector, got {}", vec3(v.0))))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::check::direction;
    use super::fmt::{approx, num, shorten_long_numbers, vec3};
    use crate::scene::schema::Vec3Spec;
    use glam::DVec3;
    use proptest::prelude::*;

    #[test]
    fn numbers_are_printed_short_whatever_their_size() {
        assert_eq!(num(1e300), "1e300");
        assert_eq!(num(-1.5e308), "-1.5e308");
        assert_eq!(num(1e-300), "1e-300");
        assert_eq!(num(0.001), "0.001");
        assert_eq!(num(-2500.0), "-2500");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(63e9), "6.3e10");
        assert_eq!(num(9999.0), "9999");
        assert_eq!(num(1e4), "1e4");
        assert_eq!(num(15250.0), "1.525e4");
        assert_eq!(num(0.0001), "0.0001");
        assert_eq!(num(f64::NAN), "NaN");
        assert_eq!(num(f64::NEG_INFINITY), "-inf");
        assert_eq!(vec3([0.0, 1e200, -0.5]), "[0, 1e200, -0.5]");
        assert_eq!(approx(0.01 / 1e-300), "1e298");
        assert_eq!(approx(1.2346e12), "1.23e12");
        assert_eq!(approx(12345.0), "1.23e4");
        assert_eq!(approx(6543.21), "6543.21");
        let serde = format!("invalid type: floating point `{:.1}`, expected a string", 1e300);
        assert_eq!(shorten_long_numbers(&serde), "invalid type: floating point `1e300`, expected a string");
        let effect = format!("must be finite and >= 0, got {} (line 26)", -1.7053473259841148e-5);
        assert_eq!(
            shorten_long_numbers(&effect),
            "must be finite and >= 0, got -1.7053473259841148e-5 (line 26)"
        );
        let kept =
            "walls[2].normal: 0.30000000000000004 (line 12, column 3), rk4, 2.2250738585072014e-308, é";
        assert_eq!(shorten_long_numbers(kept), kept);
    }

    #[test]
    fn a_signed_value_is_bounded_by_its_magnitude_whatever_its_sign() {
        use super::check::signed_in;
        use crate::scene::ranges::SPEED;
        assert_eq!(signed_in("v", -0.008, &SPEED), Ok(-0.008));
        assert_eq!(signed_in("v", 0.008, &SPEED), Ok(0.008));
        assert!(signed_in("v", -2e4, &SPEED).is_err() && signed_in("v", 2e4, &SPEED).is_err());
    }

    proptest! {
        /// Class of finding 6 (issue 13): a direction of any size, 1e-300 to 1e300, normalises
        /// to the same unit vector (to round-off), never to zero or NaN.
        #[test]
        fn direction_of_any_size_normalises_to_the_same_unit_vector(
            x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0, exponent in -300i32..300,
        ) {
            let v = DVec3::new(x, y, z);
            prop_assume!(v.abs().max_element() > 1e-3);
            let scaled = v * 10f64.powi(exponent);
            prop_assume!(scaled.is_finite() && scaled.abs().max_element() > 0.0);
            let unit = direction("n", Vec3Spec(scaled.to_array())).unwrap();
            prop_assert!((unit - v.normalize()).length() < 1e-14, "{unit} for {scaled}");
        }

        /// Every number prints in at most 24 characters (`-2.2250738585072014e-308`).
        #[test]
        fn every_number_prints_in_at_most_24_characters(bits in any::<u64>()) {
            let v = f64::from_bits(bits);
            prop_assert!(num(v).len() <= 24, "{} characters: {}", num(v).len(), num(v));
            if v.is_finite() {
                prop_assert_eq!(num(v).parse::<f64>().unwrap(), v);
            }
        }
    }
}
