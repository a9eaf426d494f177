//! A labelled strip of images: the same view side by side, each with a caption band below it
//! (its name and a second line, e.g. its error against the reference). `compare --strip` and
//! `make demo` write one.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use image::{Rgb, RgbImage};

/// One panel of a strip.
pub struct Panel {
    pub image: RgbImage,
    pub title: String,
    pub subtitle: String,
}

const GAP: u32 = 4;
const BACKGROUND: Rgb<u8> = Rgb([24, 24, 24]);
const TITLE: [u8; 3] = [240, 240, 240];
const SUBTITLE: [u8; 3] = [190, 190, 190];

fn font() -> FontRef<'static> {
    FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT).expect("the bundled font parses")
}

/// Width in pixels of `text` at `size`.
fn text_width(font: &FontRef<'_>, size: f32, text: &str) -> f32 {
    let f = font.as_scaled(PxScale::from(size));
    let mut w = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            w += f.kern(p, id);
        }
        w += f.h_advance(id);
        prev = Some(id);
    }
    w
}

/// Draws `text` centred on column `cx` with its baseline at `baseline`, blending `colour` over
/// what is there by the glyphs' coverage.
fn draw_text(
    img: &mut RgbImage,
    font: &FontRef<'_>,
    size: f32,
    cx: f32,
    baseline: f32,
    colour: [u8; 3],
    text: &str,
) {
    let scaled = font.as_scaled(PxScale::from(size));
    let mut x = cx - text_width(font, size, text) / 2.0;
    let mut prev = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            x += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(PxScale::from(size), point(x, baseline));
        x += scaled.h_advance(id);
        prev = Some(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let bounds = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            let px = bounds.min.x as i64 + i64::from(gx);
            let py = bounds.min.y as i64 + i64::from(gy);
            if px < 0 || py < 0 || px >= i64::from(img.width()) || py >= i64::from(img.height()) {
                return;
            }
            let p = img.get_pixel_mut(px as u32, py as u32);
            let a = coverage.clamp(0.0, 1.0);
            for (c, &target) in p.0.iter_mut().zip(&colour) {
                *c = (f32::from(*c) * (1.0 - a) + f32::from(target) * a).round() as u8;
            }
        });
    }
}

/// The strip: panels left to right (all must have the same size), captions below. The caption
/// font scales with the panel height (at least 11 pixels).
pub fn strip(panels: &[Panel]) -> RgbImage {
    assert!(!panels.is_empty(), "a strip needs a panel");
    let (w, h) = panels[0].image.dimensions();
    let n = panels.len() as u32;
    assert!(
        panels.iter().all(|p| p.image.dimensions() == (w, h)),
        "the panels of a strip have one size"
    );
    let font = font();
    // Titles at about 1/14 of the height, or larger for a long strip, so that they stay
    // readable when the whole strip is shown scaled down to a page's width (~1000 pixels) —
    // never wider than the panel.
    let total_width = (n * w + (n + 1) * GAP) as f32;
    let mut size = (h as f32 / 14.0).max(total_width * 0.012).max(11.0);
    for p in panels {
        for (text, k) in [(&p.title, 1.0), (&p.subtitle, 0.8)] {
            let tw = text_width(&font, size * k, text);
            if tw > w as f32 - 4.0 {
                size *= (w as f32 - 4.0) / tw;
            }
        }
    }
    let size = size.max(8.0);
    let band = (size * 2.6).ceil() as u32;
    let mut out = RgbImage::from_pixel(n * w + (n + 1) * GAP, h + band + 2 * GAP, BACKGROUND);
    for (i, p) in panels.iter().enumerate() {
        let x0 = GAP + i as u32 * (w + GAP);
        image::imageops::replace(&mut out, &p.image, i64::from(x0), i64::from(GAP));
        let cx = x0 as f32 + w as f32 / 2.0;
        let top = (GAP + h) as f32;
        draw_text(
            &mut out,
            &font,
            size,
            cx,
            top + size * 1.15,
            TITLE,
            &p.title,
        );
        draw_text(
            &mut out,
            &font,
            size * 0.8,
            cx,
            top + size * 2.25,
            SUBTITLE,
            &p.subtitle,
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_are_copied_and_captions_drawn_below_them() {
        let red = RgbImage::from_pixel(64, 36, Rgb([200, 10, 10]));
        let blue = RgbImage::from_pixel(64, 36, Rgb([10, 10, 200]));
        let s = strip(&[
            Panel {
                image: red,
                title: "ssao".into(),
                subtitle: "rel. error 0.123".into(),
            },
            Panel {
                image: blue,
                title: "reference".into(),
                subtitle: String::new(),
            },
        ]);
        assert_eq!(s.width(), 2 * 64 + 3 * GAP);
        assert_eq!(*s.get_pixel(GAP + 10, GAP + 10), Rgb([200, 10, 10]));
        assert_eq!(
            *s.get_pixel(2 * GAP + 64 + 10, GAP + 10),
            Rgb([10, 10, 200])
        );
        // Text pixels: some caption pixels under each panel are brighter than the background.
        for x0 in [GAP, 2 * GAP + 64] {
            let lit = (x0..x0 + 64)
                .flat_map(|x| (GAP + 36..s.height()).map(move |y| (x, y)))
                .filter(|&(x, y)| s.get_pixel(x, y).0[0] > 120)
                .count();
            assert!(
                lit > 10,
                "caption under the panel at {x0}: {lit} lit pixels"
            );
        }
    }
}
