//! Map figures for the HTML reports: a map raster (a PNG beside the report) framed in an inline SVG
//! with axes in metres, a title, and its key: a colour bar with the quantity's unit for scalar
//! layers, or a legend for classes, gaits and overlays. The PNG stays a plain raster (one pixel
//! block per cell) so it can be reused elsewhere; everything a reader needs to read it lives here.

use std::fmt::Write as _;

use crate::render::nice_step;

/// The world rectangle a map raster covers, in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extent {
    pub x_min: f64,
    pub y_min: f64,
    pub x_max: f64,
    pub y_max: f64,
}

impl Extent {
    /// The rectangle covered by the cells of `rect` at cell size `cell_size` (m); cell (i, j)
    /// spans [i·d, (i+1)·d) × [j·d, (j+1)·d).
    pub fn of_cells(rect: strider_core::CellRect, cell_size: f64) -> Self {
        Self {
            x_min: rect.min.i as f64 * cell_size,
            y_min: rect.min.j as f64 * cell_size,
            x_max: (rect.min.i as f64 + rect.width as f64) * cell_size,
            y_max: (rect.min.j as f64 + rect.height as f64) * cell_size,
        }
    }

    fn width(&self) -> f64 {
        (self.x_max - self.x_min).max(f64::MIN_POSITIVE)
    }
    fn height(&self) -> f64 {
        (self.y_max - self.y_min).max(f64::MIN_POSITIVE)
    }
}

/// How a figure's colours are read.
#[derive(Clone, Debug)]
pub enum Key {
    /// A continuous colormap from `min` to `max` of a quantity in `unit` (empty: dimensionless);
    /// the colours of a range sample `colormap` over [0, 1].
    ColourBar {
        quantity: String,
        unit: String,
        min: f64,
        max: f64,
        colormap: fn(f64) -> [u8; 3],
    },
    /// Discrete colours: one swatch per entry.
    Legend(Vec<(String, [u8; 3])>),
    /// The map's own colours (what the camera saw), with optional overlays drawn on it.
    TrueColour { overlays: Vec<(String, [u8; 3])> },
}

/// One map figure of a report.
#[derive(Clone, Debug)]
pub struct MapFigure {
    /// The PNG's path relative to the report.
    pub src: String,
    pub title: String,
    pub caption: String,
    pub extent: Extent,
    pub key: Key,
}

const PLOT_W: f64 = 300.0;
const MARGIN_LEFT: f64 = 46.0;
const MARGIN_TOP: f64 = 22.0;
const MARGIN_BOTTOM: f64 = 34.0;
const KEY_W: f64 = 150.0;
const UNKNOWN_NOTE: &str = "dark grey: not observed";

impl MapFigure {
    /// The figure as an HTML `<figure>` with an inline SVG; `id` makes SVG ids unique in a page.
    pub fn to_html(&self, id: usize) -> String {
        let plot_h = (PLOT_W * self.extent.height() / self.extent.width()).clamp(60.0, 900.0);
        let width = MARGIN_LEFT + PLOT_W + KEY_W;
        let height = MARGIN_TOP + plot_h.max(key_height(&self.key)) + MARGIN_BOTTOM;
        let mut svg = String::new();
        let _ = write!(
            svg,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {width:.0} {height:.0}\" \
             font-family=\"sans-serif\" font-size=\"10\" role=\"img\" aria-label=\"{}\">",
            escape(&self.title)
        );
        let _ = write!(
            svg,
            "<text x=\"{MARGIN_LEFT}\" y=\"14\" font-size=\"12\" font-weight=\"bold\">{}</text>",
            escape(&self.title)
        );
        let _ = write!(
            svg,
            "<image href=\"{}\" x=\"{MARGIN_LEFT}\" y=\"{MARGIN_TOP}\" width=\"{PLOT_W}\" \
             height=\"{plot_h:.1}\" preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\"/>",
            escape(&self.src)
        );
        let _ = write!(
            svg,
            "<rect x=\"{MARGIN_LEFT}\" y=\"{MARGIN_TOP}\" width=\"{PLOT_W}\" height=\"{plot_h:.1}\" \
             fill=\"none\" stroke=\"#444\"/>"
        );
        self.axes(&mut svg, plot_h);
        let key_x = MARGIN_LEFT + PLOT_W + 14.0;
        match &self.key {
            Key::ColourBar { .. } => self.colour_bar(&mut svg, id, key_x, plot_h),
            Key::Legend(entries) => legend(&mut svg, entries, key_x),
            Key::TrueColour { overlays } => {
                let _ = write!(
                    svg,
                    "<text x=\"{key_x:.1}\" y=\"{:.1}\">map colour (RGB)</text>",
                    MARGIN_TOP + 9.0
                );
                legend_at(&mut svg, overlays, key_x, MARGIN_TOP + 18.0);
            }
        }
        svg.push_str("</svg>");
        format!(
            "<figure>{svg}<figcaption>{}</figcaption></figure>",
            escape(&self.caption)
        )
    }

    fn axes(&self, svg: &mut String, plot_h: f64) {
        let e = self.extent;
        let bottom = MARGIN_TOP + plot_h;
        for x in ticks(e.x_min, e.x_max) {
            let px = MARGIN_LEFT + (x - e.x_min) / e.width() * PLOT_W;
            let _ = write!(
                svg,
                "<line x1=\"{px:.1}\" y1=\"{bottom:.1}\" x2=\"{px:.1}\" y2=\"{:.1}\" stroke=\"#444\"/>\
                 <text x=\"{px:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
                bottom + 4.0,
                bottom + 14.0,
                tick_label(x)
            );
        }
        for y in ticks(e.y_min, e.y_max) {
            let py = bottom - (y - e.y_min) / e.height() * plot_h;
            let _ = write!(
                svg,
                "<line x1=\"{:.1}\" y1=\"{py:.1}\" x2=\"{MARGIN_LEFT}\" y2=\"{py:.1}\" stroke=\"#444\"/>\
                 <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
                MARGIN_LEFT - 4.0,
                MARGIN_LEFT - 6.0,
                py + 3.5,
                tick_label(y)
            );
        }
        let _ = write!(
            svg,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">x [m]</text>\
             <text x=\"12\" y=\"{:.1}\" text-anchor=\"middle\" transform=\"rotate(-90 12 {:.1})\">y [m]</text>",
            MARGIN_LEFT + PLOT_W / 2.0,
            bottom + 28.0,
            MARGIN_TOP + plot_h / 2.0,
            MARGIN_TOP + plot_h / 2.0
        );
    }

    fn colour_bar(&self, svg: &mut String, id: usize, x: f64, plot_h: f64) {
        let Key::ColourBar {
            quantity,
            unit,
            min,
            max,
            colormap,
        } = &self.key
        else {
            return;
        };
        let bar_h = plot_h.clamp(60.0, 220.0);
        let top = MARGIN_TOP + 12.0;
        let _ = write!(
            svg,
            "<defs><linearGradient id=\"cb{id}\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">"
        );
        for s in 0..=10 {
            let t = s as f64 / 10.0;
            let [r, g, b] = colormap(t);
            let _ = write!(
                svg,
                "<stop offset=\"{t:.1}\" stop-color=\"rgb({r},{g},{b})\"/>"
            );
        }
        svg.push_str("</linearGradient></defs>");
        let label = if unit.is_empty() {
            format!("{quantity} (dimensionless)")
        } else {
            format!("{quantity} [{unit}]")
        };
        let _ = write!(
            svg,
            "<text x=\"{x:.1}\" y=\"{:.1}\">{}</text>\
             <rect x=\"{x:.1}\" y=\"{top:.1}\" width=\"14\" height=\"{bar_h:.1}\" fill=\"url(#cb{id})\" stroke=\"#444\"/>",
            top - 4.0,
            escape(&label)
        );
        let (lo, hi) = if min.is_finite() && max.is_finite() && max > min {
            (*min, *max)
        } else {
            (*min, *min + 1.0)
        };
        for v in ticks(lo, hi) {
            let py = top + bar_h - (v - lo) / (hi - lo) * bar_h;
            let _ = write!(
                svg,
                "<line x1=\"{:.1}\" y1=\"{py:.1}\" x2=\"{:.1}\" y2=\"{py:.1}\" stroke=\"#444\"/>\
                 <text x=\"{:.1}\" y=\"{:.1}\">{}</text>",
                x + 14.0,
                x + 18.0,
                x + 20.0,
                py + 3.5,
                tick_label(v)
            );
        }
        let _ = write!(
            svg,
            "<text x=\"{x:.1}\" y=\"{:.1}\" fill=\"#555\">{UNKNOWN_NOTE}</text>",
            top + bar_h + 14.0
        );
    }
}

fn legend(svg: &mut String, entries: &[(String, [u8; 3])], x: f64) {
    legend_at(svg, entries, x, MARGIN_TOP + 4.0);
}

fn legend_at(svg: &mut String, entries: &[(String, [u8; 3])], x: f64, top: f64) {
    for (k, (name, [r, g, b])) in entries.iter().enumerate() {
        let y = top + 15.0 * k as f64;
        let _ = write!(
            svg,
            "<rect x=\"{x:.1}\" y=\"{y:.1}\" width=\"11\" height=\"11\" fill=\"rgb({r},{g},{b})\" stroke=\"#444\"/>\
             <text x=\"{:.1}\" y=\"{:.1}\">{}</text>",
            x + 15.0,
            y + 9.0,
            escape(name)
        );
    }
}

fn key_height(key: &Key) -> f64 {
    match key {
        Key::ColourBar { .. } => 100.0,
        Key::Legend(entries) => 15.0 * entries.len() as f64 + 8.0,
        Key::TrueColour { overlays } => 15.0 * overlays.len() as f64 + 22.0,
    }
}

/// Round tick values within [lo, hi], about five of them.
pub fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
        return vec![];
    }
    let step = nice_step(hi - lo);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

fn tick_label(v: f64) -> String {
    let v = if v.abs() < 1e-12 { 0.0 } else { v };
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Escapes text for HTML text and attribute values.
pub(super) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure(key: Key) -> MapFigure {
        MapFigure {
            src: "a.png".into(),
            title: "Cost <gait>".into(),
            caption: "caption".into(),
            extent: Extent {
                x_min: -2.0,
                y_min: 0.0,
                x_max: 18.0,
                y_max: 25.0,
            },
            key,
        }
    }

    #[test]
    fn ticks_are_round_and_inside() {
        assert_eq!(ticks(-2.0, 18.0), vec![0.0, 5.0, 10.0, 15.0]);
        assert_eq!(ticks(1.0, 5.0), vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        assert!(ticks(1.0, 1.0).is_empty());
        assert!(ticks(f64::NAN, 1.0).is_empty());
    }

    #[test]
    fn colour_bar_figures_name_the_unit_and_both_axes_in_metres() {
        let html = figure(Key::ColourBar {
            quantity: "roll variance".into(),
            unit: "rad²".into(),
            min: 0.0,
            max: 0.05,
            colormap: |t| [(t * 255.0) as u8, 0, 0],
        })
        .to_html(3);
        assert!(html.contains("roll variance [rad²]"));
        assert!(html.contains("x [m]") && html.contains("y [m]"));
        assert!(html.contains("url(#cb3)") && html.contains("id=\"cb3\""));
        assert!(html.contains(">0.05<"), "the bar's top tick");
        assert!(html.contains("Cost &lt;gait&gt;"), "titles are escaped");
        assert!(!html.contains("NaN"));
    }

    #[test]
    fn dimensionless_quantities_say_so() {
        let html = figure(Key::ColourBar {
            quantity: "cost".into(),
            unit: String::new(),
            min: 1.0,
            max: 1.0,
            colormap: |_| [0, 0, 0],
        })
        .to_html(0);
        assert!(html.contains("cost (dimensionless)"));
        assert!(!html.contains("NaN") && !html.contains("inf"));
    }

    #[test]
    fn legends_list_every_entry() {
        let html = figure(Key::Legend(vec![
            ("fast".into(), [1, 2, 3]),
            ("slow".into(), [4, 5, 6]),
        ]))
        .to_html(1);
        assert!(html.contains("rgb(1,2,3)") && html.contains(">fast<"));
        assert!(html.contains("rgb(4,5,6)") && html.contains(">slow<"));
        let html = figure(Key::TrueColour {
            overlays: vec![("path".into(), [255, 0, 255])],
        })
        .to_html(2);
        assert!(html.contains("map colour (RGB)") && html.contains(">path<"));
    }

    #[test]
    fn extent_of_cells_spans_whole_cells() {
        let rect = strider_core::CellRect {
            min: strider_core::Cell::new(-4, 2),
            width: 10,
            height: 5,
        };
        let e = Extent::of_cells(rect, 0.5);
        assert_eq!((e.x_min, e.y_min, e.x_max, e.y_max), (-2.0, 1.0, 3.0, 3.5));
    }
}
