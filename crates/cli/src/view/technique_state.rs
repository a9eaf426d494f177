//! One side's technique in the viewer: its name and the value of every setting in its table,
//! each validated against the documented range before it reaches the renderer.

use nearfield_render::TechniqueParams;
use nearfield_render::technique::{self, Setting, TechniqueDesc};

#[derive(Clone)]
pub struct TechniqueState {
    pub desc: &'static TechniqueDesc,
    /// Every setting of the table with its current value, in table order.
    pub values: Vec<(&'static str, String)>,
}

impl PartialEq for TechniqueState {
    fn eq(&self, other: &Self) -> bool {
        self.desc.name == other.desc.name && self.values == other.values
    }
}

impl std::fmt::Debug for TechniqueState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.spec())
    }
}

impl TechniqueState {
    /// The technique `name` with every setting at its default.
    pub fn defaults(name: &str) -> Result<Self, String> {
        let desc = technique::find(name).map_err(|e| e.to_string())?;
        Ok(TechniqueState {
            desc,
            values: desc
                .settings
                .iter()
                .map(|s| (s.key, s.default.to_string()))
                .collect(),
        })
    }

    /// From a command-line spec (`name` or `name:key=value+…`) with `--samples`, `--radius` and
    /// `--set`: presets expanded, every value checked against the table.
    pub fn from_command_line(spec: &str, params: &TechniqueParams) -> Result<Self, String> {
        let mut state = Self::defaults(spec)?;
        let mut params = params.clone();
        params.set.extend(technique::split_spec(spec).1);
        let expanded = technique::expand_presets(state.desc, &params).map_err(|e| e.to_string())?;
        if let Some(n) = expanded.samples {
            state.set(state.samples_key(), &n.to_string())?;
        }
        // A technique without a radius (`none`) has nothing for `--radius` to set.
        if let Some(r) = expanded.radius
            && state.setting("radius").is_some()
        {
            state.set("radius", &r.to_string())?;
        }
        for (k, v) in &expanded.set {
            let key = if k == "samples" {
                state.samples_key()
            } else {
                k
            };
            state.set(key, v)?;
        }
        Ok(state)
    }

    pub fn name(&self) -> &'static str {
        self.desc.name
    }

    /// The key `--samples` sets: `samples`, or `steps` for the horizon techniques.
    fn samples_key(&self) -> &'static str {
        if self.setting("samples").is_some() {
            "samples"
        } else {
            "steps"
        }
    }

    pub fn setting(&self, key: &str) -> Option<&'static Setting> {
        self.desc.settings.iter().find(|s| s.key == key)
    }

    pub fn value(&self, key: &str) -> Option<&str> {
        self.values
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| v.as_str())
    }

    /// Sets one value after checking it against the table.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), String> {
        let setting = self.setting(key).ok_or_else(|| {
            if self.desc.settings.is_empty() {
                format!("{}: has no settings", self.desc.name)
            } else {
                format!(
                    "{}: unknown setting '{key}' (known: {})",
                    self.desc.name,
                    technique::keys(self.desc.settings)
                )
            }
        })?;
        setting
            .check(value)
            .map_err(|e| format!("{}: {e}", self.desc.name))?;
        let slot = self
            .values
            .iter_mut()
            .find(|(k, _)| *k == key)
            .expect("every table key has a value");
        slot.1 = value.to_string();
        Ok(())
    }

    /// Applies a named quality preset.
    pub fn apply_preset(&mut self, name: &str) -> Result<(), String> {
        let preset = self
            .desc
            .presets
            .iter()
            .find(|p| p.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = self.desc.presets.iter().map(|p| p.name).collect();
                if names.is_empty() {
                    format!("{}: has no quality presets", self.desc.name)
                } else {
                    format!("quality={name}: expected {}", names.join(", "))
                }
            })?;
        for (k, v) in preset.set {
            self.set(k, v)?;
        }
        Ok(())
    }

    /// The preset whose every setting matches the current values, if any.
    pub fn matching_preset(&self) -> Option<&'static str> {
        self.desc
            .presets
            .iter()
            .find(|p| p.set.iter().all(|(k, v)| self.value(k) == Some(*v)))
            .map(|p| p.name)
    }

    /// What the renderer gets: every setting, explicitly.
    pub fn params(&self) -> TechniqueParams {
        TechniqueParams {
            samples: None,
            radius: None,
            set: self
                .values
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect(),
        }
    }

    /// The `name:key=value+…` spec of this state with only the settings that differ from the
    /// defaults (what `compare --methods` and `bench --methods` accept).
    pub fn spec(&self) -> String {
        let changed: Vec<String> = self
            .desc
            .settings
            .iter()
            .zip(&self.values)
            .filter(|(s, (_, v))| !same_value(s.default, v))
            .map(|(_, (k, v))| format!("{k}={v}"))
            .collect();
        if changed.is_empty() {
            self.desc.name.to_string()
        } else {
            format!("{}:{}", self.desc.name, changed.join("+"))
        }
    }
}

/// Equal as typed or as numbers (`0.5` and `0.50`).
fn same_value(a: &str, b: &str) -> bool {
    a == b || matches!((a.parse::<f64>(), b.parse::<f64>()), (Ok(x), Ok(y)) if x == y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn command_line_values_land_in_the_table_and_round_trip_as_a_spec() {
        let params = TechniqueParams {
            samples: Some(4),
            radius: Some(1.5),
            set: vec![("quality".into(), "high".into())],
        };
        let s = TechniqueState::from_command_line("hbil:denoise=off", &params).unwrap();
        assert_eq!(s.value("slices"), Some("4"));
        assert_eq!(s.value("steps"), Some("4"));
        assert_eq!(s.value("radius"), Some("1.5"));
        assert_eq!(s.value("denoise"), Some("off"));
        let again = TechniqueState::from_command_line(&s.spec(), &Default::default()).unwrap();
        assert_eq!(again, s);
        assert_eq!(TechniqueState::defaults("ssdo").unwrap().spec(), "ssdo");
    }

    #[test]
    fn out_of_range_and_unknown_values_are_refused_and_leave_the_state_alone() {
        let mut s = TechniqueState::defaults("ssdo").unwrap();
        let before = s.clone();
        for (k, v) in [
            ("samples", "0"),
            ("samples", "1e9"),
            ("samples", "2.5"),
            ("radius", "-1"),
            ("radius", "inf"),
            ("radius", "NaN"),
            ("mode", "sideways"),
            ("denoise", "perhaps"),
            ("nonsense", "1"),
            ("samples", ""),
        ] {
            assert!(s.set(k, v).is_err(), "{k}={v}");
        }
        assert_eq!(s, before);
        assert!(s.apply_preset("insane").is_err());
        s.apply_preset("high").unwrap();
        assert_eq!(s.matching_preset(), Some("high"));
        assert!(
            TechniqueState::defaults("none")
                .unwrap()
                .set("x", "1")
                .is_err()
        );
    }
}
