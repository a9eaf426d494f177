//! One side's technique in the viewer: its name and the value of every setting in its table,
//! each validated against the documented range before it reaches the renderer.

use nearfield_render::TechniqueParams;
use nearfield_render::technique::{self, Setting, TechniqueDesc};

#[derive(Clone)]
pub struct TechniqueState {
    pub desc: &'static TechniqueDesc,
    /// Every setting of the table with its current value, in table order.
    pub values: Vec<(&'static str, String)>,
    /// The keys the user gave (on the command line, in the panel, through a preset); the others
    /// hold their defaults, or the technique's own for the far field shown ([`Self::follow_far`]).
    given: Vec<&'static str>,
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
            given: Vec::new(),
        })
    }

    /// The settings the technique takes by itself with a probe volume (its declaration's
    /// `with_volume`) that the user did not give: the renderer chooses them by its far field
    /// (`Spec::params_for`), so they stay out of [`Self::params`] and [`Self::spec`].
    fn chosen_by_far(&self, key: &str) -> bool {
        let given = |k: &str| self.given.contains(&k);
        self.desc.takes_with_volume(given)
            && self
                .desc
                .with_volume
                .iter()
                .any(|(k, _)| *k == key && !given(k))
    }

    /// Shows the values the renderer takes under the far field (`volume`: a probe volume, else
    /// the sky) for the settings it chooses by itself.
    pub fn follow_far(&mut self, volume: bool) {
        for (key, with) in self.desc.with_volume {
            if !self.chosen_by_far(key) {
                continue;
            }
            let default = self.setting(key).expect("a declared key").default;
            let slot = self
                .values
                .iter_mut()
                .find(|(k, _)| k == key)
                .expect("a table key");
            slot.1 = if volume { with } else { default }.to_string();
        }
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
        if !self.given.contains(&setting.key) {
            self.given.push(setting.key);
        }
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

    /// What the renderer gets: every setting explicitly, but those it chooses by its far field.
    pub fn params(&self) -> TechniqueParams {
        TechniqueParams {
            samples: None,
            radius: None,
            set: self
                .values
                .iter()
                .filter(|(k, _)| !self.chosen_by_far(k))
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
            .filter(|(s, (k, v))| !same_value(s.default, v) && !self.chosen_by_far(k))
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
    fn the_settings_a_technique_takes_with_a_volume_are_left_to_the_renderer_unless_given() {
        let mut s = TechniqueState::from_command_line("ssdo", &Default::default()).unwrap();
        let keys = |s: &TechniqueState| -> Vec<String> {
            s.params().set.into_iter().map(|(k, _)| k).collect()
        };
        assert!(!keys(&s).contains(&"layers".to_string()));
        assert!(!keys(&s).contains(&"steps".to_string()));
        s.follow_far(true);
        assert_eq!(s.value("layers"), Some("2"));
        assert_eq!(s.spec(), "ssdo");
        s.follow_far(false);
        assert_eq!(s.value("layers"), Some("1"));
        // A step count set in the panel refines the volume's layers; a layer count is the user's.
        s.set("steps", "8").unwrap();
        assert!(keys(&s).contains(&"steps".to_string()));
        assert!(!keys(&s).contains(&"layers".to_string()));
        s.set("layers", "1").unwrap();
        s.follow_far(true);
        assert_eq!(s.value("layers"), Some("1"));
        assert!(keys(&s).contains(&"layers".to_string()));
    }

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
