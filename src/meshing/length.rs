//! A length in scene units, given outright or as a fraction of the scene's
//! bounding diagonal, and how a settings file writes it.

use serde::ser::SerializeMap;
use serde::{Deserialize, Serialize, de};

/// A length in scene units, given outright or as a fraction of the scene's
/// bounding diagonal (so that settings can be written before a scene exists).
///
/// In a file, a bare number is an absolute length and a one-key table
/// `{ of_diagonal = F }` a fraction of the diagonal:
///
/// ```toml
/// max_edge = 50.0                          # Length::Absolute(50.0)
/// patch_max_edge = { of_diagonal = 0.125 } # Length::OfDiagonal(0.125)
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Length {
    /// This many scene units.
    Absolute(f64),
    /// This fraction of the scene's bounding diagonal.
    OfDiagonal(f64),
}

impl Length {
    /// The length in scene units, for a scene whose diagonal is `diagonal`.
    #[must_use]
    pub fn resolve(self, diagonal: f64) -> f64 {
        match self {
            Length::Absolute(length) => length,
            Length::OfDiagonal(fraction) => fraction * diagonal,
        }
    }

    /// Fails unless the number is positive and finite; the error is named
    /// `name`.
    pub(super) fn validate(self, name: &str) -> crate::Result<()> {
        let (Length::Absolute(x) | Length::OfDiagonal(x)) = self;
        if x > 0.0 && x.is_finite() {
            Ok(())
        } else {
            Err(crate::Error::InvalidSetting {
                name: name.into(),
                message: format!("{x} is not positive"),
            })
        }
    }
}

/// The key of [`Length::OfDiagonal`] in a file.
const OF_DIAGONAL: &str = "of_diagonal";

impl Serialize for Length {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match *self {
            Length::Absolute(length) => serializer.serialize_f64(length),
            Length::OfDiagonal(fraction) => {
                let mut map = serializer.serialize_map(Some(1))?;
                map.serialize_entry(OF_DIAGONAL, &fraction)?;
                map.end()
            }
        }
    }
}

impl<'de> Deserialize<'de> for Length {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(LengthVisitor)
    }
}

/// Reads a [`Length`]: a number, or `{ of_diagonal = F }`.
struct LengthVisitor;

impl<'de> de::Visitor<'de> for LengthVisitor {
    type Value = Length;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a length in scene units or { of_diagonal = fraction }")
    }

    fn visit_f64<E: de::Error>(self, length: f64) -> Result<Length, E> {
        Ok(Length::Absolute(length))
    }

    fn visit_i64<E: de::Error>(self, length: i64) -> Result<Length, E> {
        Ok(Length::Absolute(length as f64))
    }

    fn visit_u64<E: de::Error>(self, length: u64) -> Result<Length, E> {
        Ok(Length::Absolute(length as f64))
    }

    fn visit_map<A: de::MapAccess<'de>>(self, mut map: A) -> Result<Length, A::Error> {
        let mut fraction = None;
        while let Some(key) = map.next_key::<String>()? {
            if key != OF_DIAGONAL {
                return Err(de::Error::unknown_field(&key, &[OF_DIAGONAL]));
            }
            if fraction.is_some() {
                return Err(de::Error::duplicate_field(OF_DIAGONAL));
            }
            fraction = Some(map.next_value::<f64>()?);
        }
        fraction
            .map(Length::OfDiagonal)
            .ok_or_else(|| de::Error::missing_field(OF_DIAGONAL))
    }
}
