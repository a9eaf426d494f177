//! The declaration macros: [`declare_settings!`](crate::declare_settings) and the role and kind
//! of its lines (the module above explains the declaration).

use super::{Role, Setting, SettingKind};

/// The [`Role`] of a declaration line.
#[macro_export]
macro_rules! setting_role {
    (count) => {
        $crate::settings::Role::Count
    };
    (structural) => {
        $crate::settings::Role::Structural
    };
    (uniform) => {
        $crate::settings::Role::Uniform
    };
    (denoiser) => {
        $crate::settings::Role::Denoiser
    };
    (filter) => {
        $crate::settings::Role::Filter
    };
}

/// The [`SettingKind`] of a declaration line.
#[macro_export]
macro_rules! setting_kind {
    (integer($lo:expr, $hi:expr), $ty:ty) => {
        $crate::settings::SettingKind::Number { lo: $lo as f32, hi: $hi as f32, integer: true, log: false }
    };
    (number($lo:expr, $hi:expr), $ty:ty) => {
        $crate::settings::SettingKind::Number { lo: $lo as f32, hi: $hi as f32, integer: false, log: false }
    };
    (log($lo:expr, $hi:expr), $ty:ty) => {
        $crate::settings::SettingKind::Number { lo: $lo as f32, hi: $hi as f32, integer: false, log: true }
    };
    (toggle, $ty:ty) => {
        $crate::settings::SettingKind::Toggle
    };
    (choice, $ty:ty) => {
        $crate::settings::SettingKind::Choice(<$ty as $crate::settings::Choice>::WORDS)
    };
    (values($($v:literal),+), $ty:ty) => {
        $crate::settings::SettingKind::Choice(&[$($v),+])
    };
}

/// Declares a settings struct: one line per setting,
/// `key: Type = "default", kind(range), role("technique", …), "unit", "doc line";` where kind is
/// `integer(lo, hi)`, `number(lo, hi)`, `log(lo, hi)` (a number best shown on a log scale),
/// `toggle` (on | off), `choice` (an enum of [`choice!`]) or `values("1", "2")` (whole numbers
/// from a list), and role is `count`, `structural`, `uniform`, `denoiser` or `filter` ([`Role`]), with the
/// techniques it applies to in parentheses where it is not all of the family's.
/// `flatten { field: Type, ... }` embeds other declared structs, whose keys join this one's
/// (after its own; `@first { field: Type }` before the struct's lines puts a group first).
/// Attributes before a line (`#[cfg(…)]`) apply to everything it declares.
#[macro_export]
macro_rules! declare_settings {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $(@first { $($pfield:ident : $pty:ty),* $(,)? })?
            $($(#[$fattr:meta])* $field:ident : $ty:ty = $default:literal, $kind:ident $(($($arg:tt)*))?, $role:ident $(($($only:literal),+))?, $unit:literal, $doc:literal;)*
        }
        $(flatten { $($ffield:ident : $fty:ty),* $(,)? })?
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct $name {
            $($(
                #[doc = concat!("The settings of [`", stringify!($pty), "`], under their own keys.")]
                pub $pfield: $pty,
            )*)?
            $(
                $(#[$fattr])*
                #[doc = concat!("`", stringify!($field), "`: ", $doc, ". Default ", $default, ".")]
                pub $field: $ty,
            )*
            $($(
                #[doc = concat!("The settings of [`", stringify!($fty), "`], under their own keys.")]
                pub $ffield: $fty,
            )*)?
        }

        impl $name {
            /// This struct's own lines of the table (without flattened groups).
            const OWN: &'static [$crate::settings::Setting] = &[$(
                $(#[$fattr])*
                $crate::settings::Setting {
                    key: stringify!($field),
                    kind: $crate::setting_kind!($kind $(($($arg)*))?, $ty),
                    role: $crate::setting_role!($role),
                    only: &[$($($only),+)?],
                    default: $default,
                    unit: $unit,
                    doc: $doc,
                },
            )*];
            const TABLE_LEN: usize = Self::OWN.len()
                $($(+ <$pty as $crate::settings::Declared>::TABLE.len())*)?
                $($(+ <$fty as $crate::settings::Declared>::TABLE.len())*)?;
            const TABLE_ARRAY: [$crate::settings::Setting; Self::TABLE_LEN] = $crate::settings::concat(&[
                $($(<$pty as $crate::settings::Declared>::TABLE,)*)?
                Self::OWN,
                $($(<$fty as $crate::settings::Declared>::TABLE,)*)?
            ]);
        }

        impl Default for $name {
            fn default() -> Self {
                $name {
                    $($($pfield: <$pty>::default(),)*)?
                    $(
                        $(#[$fattr])*
                        $field: <$ty as $crate::settings::SettingValue>::parse(
                            stringify!($field),
                            $default,
                            &$crate::setting_kind!($kind $(($($arg)*))?, $ty),
                        )
                        .expect("a declared default parses under its own kind"),
                    )*
                    $($($ffield: <$fty>::default(),)*)?
                }
            }
        }

        impl $crate::settings::Declared for $name {
            const TABLE: &'static [$crate::settings::Setting] = &Self::TABLE_ARRAY;

            fn set(&mut self, key: &str, value: &str) -> Result<bool, String> {
                match key {
                    $(
                        $(#[$fattr])*
                        stringify!($field) => {
                            self.$field = <$ty as $crate::settings::SettingValue>::parse(
                                key,
                                value,
                                &$crate::setting_kind!($kind $(($($arg)*))?, $ty),
                            )?;
                            Ok(true)
                        }
                    )*
                    _ => {
                        $($(
                            if $crate::settings::Declared::set(&mut self.$pfield, key, value)? {
                                return Ok(true);
                            }
                        )*)?
                        $($(
                            if $crate::settings::Declared::set(&mut self.$ffield, key, value)? {
                                return Ok(true);
                            }
                        )*)?
                        Ok(false)
                    }
                }
            }

            fn same_build(&self, other: &Self) -> bool {
                $(
                    $(#[$fattr])*
                    if $crate::setting_role!($role).rebuilds() && self.$field != other.$field {
                        return false;
                    }
                )*
                true
                $($(&& $crate::settings::Declared::same_build(&self.$pfield, &other.$pfield))*)?
                $($(&& $crate::settings::Declared::same_build(&self.$ffield, &other.$ffield))*)?
            }

            fn counts(&self) -> Vec<(&'static str, f64)> {
                #[allow(unused_mut)]
                let mut out: Vec<(&'static str, f64)> = Vec::new();
                $($(out.extend($crate::settings::Declared::counts(&self.$pfield));)*)?
                $(
                    $(#[$fattr])*
                    if $crate::setting_role!($role) == $crate::settings::Role::Count
                        && let Some(v) = $crate::settings::SettingValue::number(self.$field)
                    {
                        out.push((stringify!($field), v));
                    }
                )*
                $($(out.extend($crate::settings::Declared::counts(&self.$ffield));)*)?
                out
            }
        }
    };
}

/// Concatenates tables at compile time (`N` = the sum of their lengths).
pub const fn concat<const N: usize>(tables: &[&[Setting]]) -> [Setting; N] {
    const BLANK: Setting = Setting {
        key: "",
        kind: SettingKind::Toggle,
        role: Role::Uniform,
        only: &[],
        default: "",
        unit: "",
        doc: "",
    };
    let mut out = [BLANK; N];
    let (mut t, mut n) = (0, 0);
    while t < tables.len() {
        let mut i = 0;
        while i < tables[t].len() {
            out[n] = tables[t][i];
            n += 1;
            i += 1;
        }
        t += 1;
    }
    assert!(n == N, "table length");
    out
}
