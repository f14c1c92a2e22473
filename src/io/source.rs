//! Where a character comes from: a glTF file, or a generated humanoid spelled
//! `generated:humanoid[?vertices=N][&seed=S]`.

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

use crate::humanoid::HumanoidParams;

/// A character source as given on the command line or in a scenario.
#[derive(Clone, Debug, PartialEq)]
pub enum CharacterSource {
    File(PathBuf),
    Humanoid(HumanoidParams),
}

/// Prefix of generated sources.
pub const GENERATED: &str = "generated:";

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SourceError {
    #[error("{spec:?}: unknown generator {name:?}; the one there is: generated:humanoid")]
    UnknownGenerator { spec: String, name: String },
    #[error("{spec:?}: unknown parameter {key:?}; generated:humanoid takes vertices and seed")]
    UnknownParameter { spec: String, key: String },
    #[error("{spec:?}: parameter {key} = {value:?} is not a whole number")]
    BadNumber {
        spec: String,
        key: String,
        value: String,
    },
}

impl FromStr for CharacterSource {
    type Err = SourceError;

    fn from_str(spec: &str) -> Result<Self, SourceError> {
        let Some(rest) = spec.strip_prefix(GENERATED) else {
            return Ok(CharacterSource::File(PathBuf::from(spec)));
        };
        let (name, query) = rest.split_once('?').unwrap_or((rest, ""));
        if name != "humanoid" {
            return Err(SourceError::UnknownGenerator {
                spec: spec.into(),
                name: name.into(),
            });
        }
        let mut p = HumanoidParams::default();
        for pair in query.split('&').filter(|s| !s.is_empty()) {
            let (key, value) = pair.split_once('=').unwrap_or((pair, ""));
            let number = |v: &str| {
                v.replace('_', "")
                    .parse::<u64>()
                    .map_err(|_| SourceError::BadNumber {
                        spec: spec.into(),
                        key: key.into(),
                        value: v.into(),
                    })
            };
            match key {
                "vertices" => p.vertices = number(value)? as usize,
                "seed" => p.seed = number(value)?,
                _ => {
                    return Err(SourceError::UnknownParameter {
                        spec: spec.into(),
                        key: key.into(),
                    });
                }
            }
        }
        Ok(CharacterSource::Humanoid(p))
    }
}

impl fmt::Display for CharacterSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CharacterSource::File(p) => write!(f, "{}", p.display()),
            CharacterSource::Humanoid(h) => write!(
                f,
                "{GENERATED}humanoid?vertices={}&seed={}",
                h.vertices, h.seed
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_sources() {
        assert_eq!(
            "a/b.glb".parse(),
            Ok(CharacterSource::File("a/b.glb".into()))
        );
        let h: CharacterSource = "generated:humanoid?vertices=10_000&seed=3".parse().unwrap();
        assert_eq!(
            h,
            CharacterSource::Humanoid(HumanoidParams {
                vertices: 10_000,
                seed: 3
            })
        );
        assert_eq!(h.to_string(), "generated:humanoid?vertices=10000&seed=3");
        assert_eq!(
            "generated:humanoid".parse::<CharacterSource>(),
            Ok(CharacterSource::Humanoid(HumanoidParams::default()))
        );
        assert!(matches!(
            "generated:robot".parse::<CharacterSource>(),
            Err(SourceError::UnknownGenerator { .. })
        ));
        assert!(matches!(
            "generated:humanoid?legs=3".parse::<CharacterSource>(),
            Err(SourceError::UnknownParameter { .. })
        ));
        assert!(matches!(
            "generated:humanoid?vertices=lots".parse::<CharacterSource>(),
            Err(SourceError::BadNumber { .. })
        ));
    }
}
