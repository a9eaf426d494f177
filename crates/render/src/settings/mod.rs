//! Technique settings, each declared once.
//!
//! A settings struct is written with [`declare_settings!`]: one line per setting gives its key
//! (the field's name), type, default (as typed after `key=`), kind and range, unit and doc line.
//! From that one declaration come the struct and its rustdoc, `Default`, the `--set` parser
//! ([`Declared::set`]), the table that the viewer shows as sliders, checkboxes and lists
//! ([`Declared::TABLE`]) and the book's settings tables ([`markdown_table`];
//! `technique::book_pages`, a test checks the committed pages). Word-valued settings are enums
//! written with [`choice!`]. Each line also declares the setting's [`Role`] and, where it is not
//! all of its family's, the techniques it applies to.
//!
//! This module knows nothing of techniques or GPU resources: it holds the machinery and the
//! groups several families share (denoise, layers, march, sampling); each family declares its
//! own settings in `technique/<family>/settings.rs`.

pub mod declare;
pub mod denoise;
pub mod fitted;
pub mod layers;
pub mod march;
pub mod sampling;

pub use declare::concat;

/// Generic settings from the command line, interpreted by each technique: `--samples`,
/// `--radius` and `--set key=value`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TechniqueParams {
    /// Samples per pixel (`--samples`); `None` = the technique's default.
    pub samples: Option<u32>,
    /// Near-field radius in metres (`--radius`, `inf` allowed); `None` = default.
    pub radius: Option<f32>,
    /// `--set key=value` pairs, in order.
    pub set: Vec<(String, String)>,
}

/// The values a setting takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SettingKind {
    /// A number in `lo..=hi`; `integer`: whole numbers only; `log`: best shown on a log scale.
    Number {
        lo: f32,
        hi: f32,
        integer: bool,
        log: bool,
    },
    /// on | off.
    Toggle,
    /// One of the listed words.
    Choice(&'static [&'static str]),
}

/// What a setting is for, declared with it: what the sweep, the fit, the viewer and the book
/// read instead of names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// How much work: samples, steps, slices, lights, cameras (`pareto` scales it; it may
    /// rebuild the pipelines, as a WGSL `override` constant does).
    Count,
    /// Shapes the pipelines or resources (a mode that adds a pass, a texture size): a change
    /// rebuilds the technique.
    Structural,
    /// A value the kernels read from a uniform buffer: written in place, no rebuild (`fit`
    /// fits these).
    Uniform,
    /// Chooses or shapes the denoising (the denoiser, the running mean, svgf's passes): a
    /// change rebuilds the technique; `pareto` tries every value of a toggle or choice.
    Denoiser,
    /// Tunes a denoising filter from a uniform (a blur's width and edge weights, the running
    /// mean's length): written in place, neither fitted nor swept.
    Filter,
}

impl Role {
    /// The word the declaration and the book use.
    pub fn word(self) -> &'static str {
        match self {
            Role::Count => "count",
            Role::Structural => "structural",
            Role::Uniform => "uniform",
            Role::Denoiser => "denoiser",
            Role::Filter => "filter",
        }
    }

    /// Whether a change rebuilds the technique's pipelines and resources (what
    /// [`Declared::same_build`] compares): counts, structure and the denoiser's shape do;
    /// uniforms and filters are written in place.
    pub const fn rebuilds(self) -> bool {
        matches!(self, Role::Count | Role::Structural | Role::Denoiser)
    }
}

/// One `--set key=value` setting of a technique.
#[derive(Clone, Copy, Debug)]
pub struct Setting {
    pub key: &'static str,
    pub kind: SettingKind,
    /// What it is for.
    pub role: Role,
    /// The techniques of the family it applies to; empty: all of them.
    pub only: &'static [&'static str],
    /// The default, as typed after `key=`.
    pub default: &'static str,
    /// The unit of a number (`m`, `pixels`), empty where it has none.
    pub unit: &'static str,
    /// One line: what it does.
    pub doc: &'static str,
}

impl Setting {
    /// Whether the setting changes technique `name` (the family's others ignore it).
    pub fn applies(&self, name: &str) -> bool {
        self.only.is_empty() || self.only.contains(&name)
    }

    /// Checks a typed value against the documented range; the technique's parser has the
    /// last word (some settings constrain each other).
    pub fn check(&self, value: &str) -> Result<(), String> {
        match self.kind {
            SettingKind::Number {
                lo, hi, integer, ..
            } => {
                let x = parse_number(self.key, value, lo, hi)?;
                if integer && x.fract() != 0.0 {
                    return Err(format!("{}={value}: expected a whole number", self.key));
                }
                Ok(())
            }
            SettingKind::Toggle => parse_on_off(self.key, value).map(|_| ()),
            SettingKind::Choice(options) => {
                if options.contains(&value) {
                    Ok(())
                } else {
                    Err(format!(
                        "{}={value}: expected {}",
                        self.key,
                        or_list(options)
                    ))
                }
            }
        }
    }

    /// The settings table's "role" cell: the role, and the techniques where not all of the
    /// family's.
    pub fn role_text(&self) -> String {
        if self.only.is_empty() {
            self.role.word().to_string()
        } else {
            format!("{} ({})", self.role.word(), self.only.join(", "))
        }
    }

    /// The settings table's "unit / range" cell.
    pub fn range_text(&self) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!("{}, ", self.unit)
        };
        match self.kind {
            SettingKind::Number { lo, hi, .. } => {
                format!("{unit}{}..={}", number_text(lo), number_text(hi))
            }
            SettingKind::Toggle => "on \\| off".into(),
            SettingKind::Choice(options) => options.join(" \\| "),
        }
    }
}

/// A bound as a reader writes it: 0.5, 16, 1e-4, 1e6.
fn number_text(x: f32) -> String {
    if x != 0.0 && !(1e-3..1e4).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A named set of settings (`quality=NAME`).
#[derive(Clone, Copy, Debug)]
pub struct Preset {
    pub name: &'static str,
    pub set: &'static [(&'static str, &'static str)],
}

/// A value a setting holds: parsed from what follows `key=` under its kind.
pub trait SettingValue: Sized + Copy {
    fn parse(key: &str, value: &str, kind: &SettingKind) -> Result<Self, String>;
    /// The value as a number, where it is one (what a count specialises a kernel with).
    fn number(self) -> Option<f64> {
        None
    }
}

impl SettingValue for f32 {
    fn parse(key: &str, value: &str, kind: &SettingKind) -> Result<Self, String> {
        match *kind {
            SettingKind::Number { lo, hi, .. } => parse_number(key, value, lo, hi),
            _ => Err(format!("{key}: not a number setting")),
        }
    }
    fn number(self) -> Option<f64> {
        Some(self.into())
    }
}

impl SettingValue for u32 {
    fn parse(key: &str, value: &str, kind: &SettingKind) -> Result<Self, String> {
        match *kind {
            SettingKind::Number { lo, hi, .. } => parse_integer(key, value, lo as u32, hi as u32),
            // Whole numbers from a list (`layers=1|2|4`).
            SettingKind::Choice(options) if options.contains(&value) => value
                .parse()
                .map_err(|_| format!("{key}={value}: expected a whole number")),
            SettingKind::Choice(options) => {
                Err(format!("{key}={value}: expected {}", or_list(options)))
            }
            SettingKind::Toggle => Err(format!("{key}: not a number setting")),
        }
    }
    fn number(self) -> Option<f64> {
        Some(self.into())
    }
}

impl SettingValue for bool {
    fn parse(key: &str, value: &str, _kind: &SettingKind) -> Result<Self, String> {
        parse_on_off(key, value)
    }
}

/// A word-valued setting: an enum declared with [`choice!`].
pub trait Choice: Sized + Copy + 'static {
    /// Every word, in declaration order.
    const WORDS: &'static [&'static str];
    fn from_word(word: &str) -> Option<Self>;
    fn word(self) -> &'static str;
}

/// `a`, `a or b`, `a, b or c`.
pub fn or_list(words: &[&str]) -> String {
    match words {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// Declares an enum whose variants are the words of a setting, with [`Choice`] and
/// [`SettingValue`].
#[macro_export]
macro_rules! choice {
    ($(#[$meta:meta])* pub enum $name:ident { $($(#[$vmeta:meta])* $variant:ident = $word:literal),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum $name { $($(#[$vmeta])* $variant),+ }

        impl $crate::settings::Choice for $name {
            const WORDS: &'static [&'static str] = &[$($word),+];
            fn from_word(word: &str) -> Option<Self> {
                match word { $($word => Some($name::$variant),)+ _ => None }
            }
            fn word(self) -> &'static str {
                match self { $($name::$variant => $word),+ }
            }
        }

        impl $crate::settings::SettingValue for $name {
            fn parse(key: &str, value: &str, _kind: &$crate::settings::SettingKind) -> Result<Self, String> {
                <$name as $crate::settings::Choice>::from_word(value).ok_or_else(|| {
                    format!(
                        "{key}={value}: expected {}",
                        $crate::settings::or_list(<$name as $crate::settings::Choice>::WORDS)
                    )
                })
            }
        }
    };
}

/// A settings struct whose fields are declared once (see the module's documentation).
pub trait Declared: Default {
    /// Every `--set` key with its kind, default, unit and doc line, in declaration order
    /// (flattened groups included).
    const TABLE: &'static [Setting];
    /// Parses `key=value` into the field of that name; `Ok(false)` for a key it does not have.
    fn set(&mut self, key: &str, value: &str) -> Result<bool, String>;
    /// Whether `other` builds the same pipelines and resources: every setting whose role
    /// [`Role::rebuilds`] is equal (a technique's `update` rebuilds otherwise).
    fn same_build(&self, other: &Self) -> bool;
    /// Every count that is a number, by key, in declaration order: a kernel that declares
    /// `override KEY` (the key in capitals) is specialised with it ([`count_constants`]).
    fn counts(&self) -> Vec<(&'static str, f64)>;
}

/// The `override` constants of the kernel `source` among `counts` ([`Declared::counts`]):
/// each count whose key, in capitals, the kernel declares as `override KEY`.
pub fn count_constants(source: &str, counts: &[(&'static str, f64)]) -> Vec<(String, f64)> {
    counts
        .iter()
        .map(|&(key, v)| (key.to_uppercase(), v))
        .filter(|(name, _)| source.contains(&format!("override {name}:")))
        .collect()
}

/// Applies `--samples` (to the field `samples` sets), `--radius` and `--set` on top of the
/// defaults. `aliases` maps other spellings to keys (`samples` → `steps`). An unknown key is an
/// error naming the known ones.
pub fn apply<S: Declared>(
    s: &mut S,
    params: &TechniqueParams,
    aliases: &[(&str, &str)],
) -> Result<(), String> {
    let alias = |k: &str| {
        aliases
            .iter()
            .find(|(from, _)| *from == k)
            .map_or(k.to_string(), |(_, to)| to.to_string())
    };
    // The command line's shortcuts are settings like any other: parsed and checked by the
    // declaration (a family without the key ignores them).
    if let Some(n) = params.samples {
        s.set(&alias("samples"), &n.to_string())
            .map_err(|e| format!("--samples {n}: {e}"))?;
    }
    if let Some(r) = params.radius {
        s.set("radius", &r.to_string())
            .map_err(|e| format!("--radius {r}: {e}"))?;
    }
    for (k, v) in &params.set {
        let key = aliases
            .iter()
            .find(|(from, _)| from == k)
            .map_or(k.as_str(), |(_, to)| to);
        if !s.set(key, v)? {
            let mut known = vec!["quality"];
            known.extend(aliases.iter().map(|(from, _)| *from));
            known.extend(S::TABLE.iter().map(|s| s.key));
            return Err(format!(
                "unknown setting '{k}' (known: {})",
                known.join(", ")
            ));
        }
    }
    Ok(())
}

/// The markdown table of a settings struct: key, meaning, unit / range, default.
pub fn markdown_table(table: &[Setting], presets: &[Preset]) -> String {
    let mut out =
        String::from("| key | meaning | unit / range | default | role |\n|---|---|---|---|---|\n");
    if !presets.is_empty() {
        let names: Vec<String> = presets
            .iter()
            .map(|p| {
                let set: Vec<String> = p.set.iter().map(|(k, v)| format!("{k}={v}")).collect();
                format!("`{}` {}", p.name, set.join(" "))
            })
            .collect();
        out += &format!(
            "| `quality` | preset: {}; `fitted` each technique's constants fitted against the reference (results page, \"Fitted presets\"); explicit settings refine it | | | |\n",
            names.join(", ")
        );
    }
    for s in table {
        out += &format!(
            "| `{}` | {} | {} | {} | {} |\n",
            s.key,
            s.doc,
            s.range_text(),
            s.default,
            s.role_text()
        );
    }
    out
}

/// The keys of a settings table, for error messages.
pub fn keys(settings: &[Setting]) -> String {
    settings
        .iter()
        .map(|s| s.key)
        .collect::<Vec<_>>()
        .join(", ")
}

/// `key=on|off` (also true/false, 1/0).
pub fn parse_on_off(key: &str, v: &str) -> Result<bool, String> {
    match v {
        "on" | "true" | "1" => Ok(true),
        "off" | "false" | "0" => Ok(false),
        _ => Err(format!("{key}={v}: expected on or off")),
    }
}

/// `key=number` within `lo..=hi`.
pub fn parse_number(key: &str, v: &str, lo: f32, hi: f32) -> Result<f32, String> {
    let x: f32 = v
        .parse()
        .map_err(|_| format!("{key}={v}: expected a number"))?;
    if !x.is_finite() {
        return Err(format!("{key}={v}: must be a finite number"));
    }
    if !(x >= lo && x <= hi) {
        return Err(format!("{key}={v}: must be in {lo}..={hi}"));
    }
    Ok(x)
}

/// `key=whole number` within `lo..=hi`.
pub fn parse_integer(key: &str, v: &str, lo: u32, hi: u32) -> Result<u32, String> {
    let x = parse_number(key, v, lo as f32, hi as f32)?;
    if x.fract() != 0.0 {
        return Err(format!("{key}={v}: expected a whole number"));
    }
    Ok(x as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn or_list_reads_like_a_sentence() {
        assert_eq!(or_list(&["a"]), "a");
        assert_eq!(or_list(&["a", "b"]), "a or b");
        assert_eq!(or_list(&["a", "b", "c"]), "a, b or c");
    }
}
