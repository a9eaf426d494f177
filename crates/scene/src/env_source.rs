//! What `--env` names: a map file, the built-in sky or a constant, and how each is loaded (with
//! its sun split out, [`crate::sun`]).

use crate::{Environment, SceneError, sky, sun};
use glam::Vec3;
use std::path::PathBuf;

/// Where the environment comes from, as written after `--env`.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum EnvSource {
    /// A Radiance `.hdr` or OpenEXR `.exr` lat-long map.
    File(PathBuf),
    /// The built-in analytic sky with a sun ([`crate::sky`]).
    #[default]
    Sky,
    /// Uniform radiance (linear RGB).
    Constant(Vec3),
}

impl EnvSource {
    /// Parses `sky`, `constant:R,G,B` (or `constant:L`) or a file path.
    pub fn parse(s: &str) -> Result<Self, SceneError> {
        if s == "sky" {
            return Ok(EnvSource::Sky);
        }
        if let Some(rest) = s.strip_prefix("constant:") {
            let vals: Result<Vec<f32>, _> = rest.split(',').map(|v| v.trim().parse()).collect();
            let bad = || {
                SceneError::Argument(format!(
                    "--env {s}: expected constant:R,G,B (or constant:L) with finite, non-negative numbers"
                ))
            };
            let vals = vals.map_err(|_| bad())?;
            let rgb = match vals.as_slice() {
                [l] => Vec3::splat(*l),
                [r, g, b] => Vec3::new(*r, *g, *b),
                _ => return Err(bad()),
            };
            if !rgb.is_finite() || rgb.min_element() < 0.0 {
                return Err(bad());
            }
            return Ok(EnvSource::Constant(rgb));
        }
        Ok(EnvSource::File(PathBuf::from(s)))
    }

    /// Builds the environment map (whole: `--sun off`).
    pub fn load(&self) -> Result<Environment, SceneError> {
        match self {
            EnvSource::File(p) => Environment::load(p),
            EnvSource::Sky => Ok(sky::Sky::default().to_environment()),
            EnvSource::Constant(c) => Ok(Environment::constant(*c)),
        }
    }

    /// Builds the environment map with its sun split out under `SunMode::Auto`
    /// ([`crate::sun`]): the built-in sky's sun exactly, a file's by [`sun::find`].
    /// Returns the map and the log line saying what was found (none for `off` and constants).
    pub fn load_split(
        &self,
        mode: sun::SunMode,
    ) -> Result<(Environment, Option<String>), SceneError> {
        if mode == sun::SunMode::Off {
            return Ok((self.load()?, None));
        }
        match self {
            EnvSource::Sky => {
                let env = sky::Sky::default().to_split_environment();
                let line = env.sun.map(|s| format!("sky: {}", s.describe()));
                Ok((env, line))
            }
            EnvSource::Constant(c) => Ok((Environment::constant(*c), None)),
            EnvSource::File(p) => {
                let mut env = Environment::load(p)?;
                let line = sun::split(&mut env, mode);
                Ok((env, line))
            }
        }
    }
}

impl std::fmt::Display for EnvSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EnvSource::File(p) => write!(f, "{}", p.display()),
            EnvSource::Sky => write!(f, "sky"),
            EnvSource::Constant(c) => write!(f, "constant:{},{},{}", c.x, c.y, c.z),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_parse() {
        assert_eq!(
            EnvSource::parse("constant:1,2,3").unwrap(),
            EnvSource::Constant(Vec3::new(1.0, 2.0, 3.0))
        );
        assert!(EnvSource::parse("constant:1,2").is_err());
        assert!(EnvSource::parse("constant:-1").is_err());
        assert!(EnvSource::parse("constant:nan").is_err());
    }
}
