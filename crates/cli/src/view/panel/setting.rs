//! One setting's widget in the panel: a slider, a checkbox or a list, by its declared kind,
//! with its doc line, unit and role as the hover text.

use super::{Panel, Requests};
use crate::view::session::{Change, Side};
use nearfield_render::technique::{self, SettingKind};

impl Panel {
    pub(super) fn setting(
        &mut self,
        ui: &mut egui::Ui,
        side: Side,
        setting: &technique::Setting,
        key: &'static str,
        value: &str,
        req: &mut Requests,
    ) {
        match setting.kind {
            SettingKind::Number {
                lo,
                hi,
                integer,
                log,
            } => {
                let mut v = match self.pending {
                    Some((ps, pk, pv)) if ps == side && pk == key => pv,
                    _ => value.parse::<f32>().unwrap_or(lo),
                };
                let mut slider = egui::Slider::new(&mut v, lo..=hi)
                    .logarithmic(log)
                    .text(key);
                if integer {
                    slider = slider.integer();
                }
                let r = ui.add(slider).on_hover_text(hover_text(setting));
                if r.dragged() {
                    self.pending = Some((side, key, v));
                } else if r.drag_stopped() || r.changed() {
                    self.pending = None;
                    let text = if integer {
                        format!("{}", v.round() as i64)
                    } else {
                        format!("{v}")
                    };
                    req.changes.push(Change::Setting(side, key.into(), text));
                }
            }
            SettingKind::Toggle => {
                let mut on = value == "on";
                if ui
                    .checkbox(&mut on, key)
                    .on_hover_text(hover_text(setting))
                    .changed()
                {
                    let v = if on { "on" } else { "off" };
                    req.changes
                        .push(Change::Setting(side, key.into(), v.into()));
                }
            }
            SettingKind::Choice(options) => {
                egui::ComboBox::from_id_salt(("choice", key))
                    .selected_text(format!("{key}: {value}"))
                    .show_ui(ui, |ui| {
                        for o in options {
                            if ui.selectable_label(*o == value, *o).clicked() && *o != value {
                                req.changes
                                    .push(Change::Setting(side, key.into(), o.to_string()));
                            }
                        }
                    })
                    .response
                    .on_hover_text(hover_text(setting));
            }
        }
    }
}

/// A setting's hover text: its doc line, for numbers its unit, and whether a change rebuilds
/// the technique (its role says: counts, structure and the denoiser's shape do; the history
/// starts over).
fn hover_text(setting: &technique::Setting) -> String {
    let mut text = setting.doc.to_string();
    if !setting.unit.is_empty() {
        text += &format!(" ({})", setting.unit);
    }
    if setting.role.rebuilds() {
        text += "; a change rebuilds the technique";
    }
    text
}
