//! Log–log line plots drawn straight into an image (the benchmark
//! harness's convergence curves, `bcsdf --compare-mie`'s): decade grid and tick labels, one polyline with markers per
//! series, a legend. Text uses a small built-in 5 × 7 pixel font covering
//! the characters the tools print.

use super::heat_map::display_image;
use crate::image::{Image, ImageError};

/// One curve: points (x, y), both > 0 (others are skipped), in display colour.
pub struct Series {
    pub label: String,
    pub colour: [f32; 3],
    pub points: Vec<(f64, f64)>,
}

/// Colours the tools give their curves: rpbrt blue, pbrt-v4 orange.
pub const BLUE: [f32; 3] = [0.12, 0.35, 0.8];
pub const ORANGE: [f32; 3] = [0.9, 0.45, 0.05];

const WIDTH: usize = 720;
const HEIGHT: usize = 480;
const LEFT: usize = 90;
const RIGHT: usize = 24;
const TOP: usize = 40;
const BOTTOM: usize = 60;
/// Text is drawn at twice the font's size.
const TEXT_SCALE: usize = 2;

struct Canvas {
    data: Vec<f32>,
}

impl Canvas {
    fn set(&mut self, x: i64, y: i64, colour: [f32; 3]) {
        if x >= 0 && y >= 0 && (x as usize) < WIDTH && (y as usize) < HEIGHT {
            let i = (y as usize * WIDTH + x as usize) * 3;
            self.data[i..i + 3].copy_from_slice(&colour);
        }
    }

    fn rect(&mut self, x0: i64, y0: i64, x1: i64, y1: i64, colour: [f32; 3]) {
        for y in y0..=y1 {
            for x in x0..=x1 {
                self.set(x, y, colour);
            }
        }
    }

    /// A line `thickness` pixels wide (a square brush along the DDA path).
    fn line(
        &mut self,
        (x0, y0): (f64, f64),
        (x1, y1): (f64, f64),
        thickness: i64,
        colour: [f32; 3],
    ) {
        let steps = (x1 - x0).abs().max((y1 - y0).abs()).ceil().max(1.0) as i64;
        let half = thickness / 2;
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let (x, y) = (
                (x0 + (x1 - x0) * t).round() as i64,
                (y0 + (y1 - y0) * t).round() as i64,
            );
            self.rect(
                x - half,
                y - half,
                x - half + thickness - 1,
                y - half + thickness - 1,
                colour,
            );
        }
    }

    /// Text with its top-left corner at (x, y).
    fn text(&mut self, x: i64, y: i64, text: &str, colour: [f32; 3]) {
        let advance = (6 * TEXT_SCALE) as i64;
        for (k, c) in text.chars().enumerate() {
            let rows = glyph(c);
            for (row, bits) in rows.iter().enumerate() {
                for (col, bit) in bits.bytes().enumerate() {
                    if bit == b'#' {
                        let (px, py) = (
                            x + k as i64 * advance + (col * TEXT_SCALE) as i64,
                            y + (row * TEXT_SCALE) as i64,
                        );
                        self.rect(
                            px,
                            py,
                            px + TEXT_SCALE as i64 - 1,
                            py + TEXT_SCALE as i64 - 1,
                            colour,
                        );
                    }
                }
            }
        }
    }
}

/// Width in pixels of `text` as [`Canvas::text`] draws it.
fn text_width(text: &str) -> i64 {
    (text.chars().count() * 6 * TEXT_SCALE) as i64 - TEXT_SCALE as i64
}

/// A decade's label: plain for 0.1 … 1000, else `1eK`.
fn decade_label(k: i32) -> String {
    match k {
        -1 => "0.1".into(),
        0..=3 => 10u32.pow(k as u32).to_string(),
        _ => format!("1e{k}"),
    }
}

/// The decades [lo, hi] (as exponents) enclosing all values (> 0).
fn decade_range(values: impl Iterator<Item = f64>) -> (i32, i32) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| *v > 0.0 && v.is_finite()) {
        lo = lo.min(v.log10());
        hi = hi.max(v.log10());
    }
    if lo > hi {
        return (0, 1);
    }
    let (lo, hi) = (lo.floor() as i32, hi.ceil() as i32);
    (lo, hi.max(lo + 1))
}

/// A log–log plot of `series`, titled, with the axes named.
pub fn log_log_plot(
    title: &str,
    x_name: &str,
    y_name: &str,
    series: &[Series],
) -> Result<Image, ImageError> {
    let white = [1.0; 3];
    let black = [0.0; 3];
    let grey = [0.85; 3];
    let mut canvas = Canvas {
        data: [white].repeat(WIDTH * HEIGHT).concat(),
    };
    let valid = |p: &&(f64, f64)| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite();
    let (x_lo, x_hi) = decade_range(
        series
            .iter()
            .flat_map(|s| s.points.iter().filter(valid).map(|p| p.0)),
    );
    let (y_lo, y_hi) = decade_range(
        series
            .iter()
            .flat_map(|s| s.points.iter().filter(valid).map(|p| p.1)),
    );
    let (plot_w, plot_h) = (
        (WIDTH - LEFT - RIGHT) as f64,
        (HEIGHT - TOP - BOTTOM) as f64,
    );
    let to_pixel = |(x, y): (f64, f64)| {
        let u = (x.log10() - x_lo as f64) / (x_hi - x_lo) as f64;
        let v = (y.log10() - y_lo as f64) / (y_hi - y_lo) as f64;
        (LEFT as f64 + u * plot_w, TOP as f64 + (1.0 - v) * plot_h)
    };
    let (left, right) = (LEFT as i64, (WIDTH - RIGHT) as i64);
    let (top, bottom) = (TOP as i64, (HEIGHT - BOTTOM) as i64);
    for k in x_lo..=x_hi {
        let (x, _) = to_pixel((10f64.powi(k), 1.0));
        let x = x.round() as i64;
        canvas.rect(x, top, x, bottom, grey);
        let label = decade_label(k);
        canvas.text(x - text_width(&label) / 2, bottom + 8, &label, black);
    }
    for k in y_lo..=y_hi {
        let (_, y) = to_pixel((1.0, 10f64.powi(k)));
        let y = y.round() as i64;
        canvas.rect(left, y, right, y, grey);
        let label = decade_label(k);
        canvas.text(left - 8 - text_width(&label), y - 7, &label, black);
    }
    canvas.rect(left, top, left + 1, bottom, black);
    canvas.rect(left, bottom - 1, right, bottom, black);
    canvas.text(
        (left + right) / 2 - text_width(x_name) / 2,
        bottom + 34,
        x_name,
        black,
    );
    canvas.text(8, 12, y_name, black);
    canvas.text((left + right) / 2 - text_width(title) / 2, 12, title, black);
    for (index, s) in series.iter().enumerate() {
        let points: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(valid)
            .map(|&p| to_pixel(p))
            .collect();
        for pair in points.windows(2) {
            canvas.line(pair[0], pair[1], 2, s.colour);
        }
        for &(x, y) in &points {
            let (x, y) = (x.round() as i64, y.round() as i64);
            canvas.rect(x - 3, y - 3, x + 3, y + 3, s.colour);
        }
        let ly = top + 12 + 22 * index as i64;
        let lx = right - 16 - text_width(&s.label) - 40;
        canvas.line(
            (lx as f64, ly as f64 + 7.0),
            (lx as f64 + 30.0, ly as f64 + 7.0),
            3,
            s.colour,
        );
        canvas.text(lx + 38, ly, &s.label, black);
    }
    display_image(WIDTH as u32, HEIGHT as u32, canvas.data)
}

/// The 5 × 7 glyph of `c` ('#' is ink); characters outside the font are
/// blank.
fn glyph(c: char) -> [&'static str; 7] {
    const BLANK: &str = "     ";
    match c {
        '0' => [
            " ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### ",
        ],
        '1' => [
            "  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### ",
        ],
        '2' => [
            " ### ", "#   #", "    #", "   # ", "  #  ", " #   ", "#####",
        ],
        '3' => [
            "#####", "   # ", "  #  ", "   # ", "    #", "#   #", " ### ",
        ],
        '4' => [
            "   # ", "  ## ", " # # ", "#  # ", "#####", "   # ", "   # ",
        ],
        '5' => [
            "#####", "#    ", "#### ", "    #", "    #", "#   #", " ### ",
        ],
        '6' => [
            "  ## ", " #   ", "#    ", "#### ", "#   #", "#   #", " ### ",
        ],
        '7' => [
            "#####", "    #", "   # ", "  #  ", " #   ", " #   ", " #   ",
        ],
        '8' => [
            " ### ", "#   #", "#   #", " ### ", "#   #", "#   #", " ### ",
        ],
        '9' => [
            " ### ", "#   #", "#   #", " ####", "    #", "   # ", " ##  ",
        ],
        '.' => [BLANK, BLANK, BLANK, BLANK, BLANK, " ##  ", " ##  "],
        ',' => [BLANK, BLANK, BLANK, BLANK, " ##  ", "  #  ", " #   "],
        '-' => [BLANK, BLANK, BLANK, " ### ", BLANK, BLANK, BLANK],
        '+' => [BLANK, "  #  ", "  #  ", "#####", "  #  ", "  #  ", BLANK],
        '(' => [
            "   # ", "  #  ", " #   ", " #   ", " #   ", "  #  ", "   # ",
        ],
        ')' => [
            " #   ", "  #  ", "   # ", "   # ", "   # ", "  #  ", " #   ",
        ],
        '/' => [BLANK, "    #", "   # ", "  #  ", " #   ", "#    ", BLANK],
        '@' => [
            " ### ", "#   #", "# ###", "# # #", "# ###", "#    ", " ####",
        ],
        'a' => [BLANK, BLANK, " ### ", "    #", " ####", "#   #", " ####"],
        'b' => [
            "#    ", "#    ", "# ## ", "##  #", "#   #", "#   #", "#### ",
        ],
        'c' => [BLANK, BLANK, " ### ", "#    ", "#    ", "#   #", " ### "],
        'd' => [
            "    #", "    #", " ## #", "#  ##", "#   #", "#   #", " ####",
        ],
        'e' => [BLANK, BLANK, " ### ", "#   #", "#####", "#    ", " ### "],
        'f' => [
            "  ## ", " #  #", " #   ", "###  ", " #   ", " #   ", " #   ",
        ],
        'g' => [BLANK, " ####", "#   #", "#   #", " ####", "    #", " ### "],
        'h' => [
            "#    ", "#    ", "# ## ", "##  #", "#   #", "#   #", "#   #",
        ],
        'i' => ["  #  ", BLANK, " ##  ", "  #  ", "  #  ", "  #  ", " ### "],
        'k' => [
            "#    ", "#    ", "#  # ", "# #  ", "##   ", "# #  ", "#  # ",
        ],
        'l' => [
            " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### ",
        ],
        'm' => [BLANK, BLANK, "## # ", "# # #", "# # #", "#   #", "#   #"],
        'n' => [BLANK, BLANK, "# ## ", "##  #", "#   #", "#   #", "#   #"],
        'o' => [BLANK, BLANK, " ### ", "#   #", "#   #", "#   #", " ### "],
        'p' => [BLANK, BLANK, "#### ", "#   #", "#### ", "#    ", "#    "],
        'r' => [BLANK, BLANK, "# ## ", "##  #", "#    ", "#    ", "#    "],
        's' => [BLANK, BLANK, " ####", "#    ", " ### ", "    #", "#### "],
        't' => [
            " #   ", " #   ", "###  ", " #   ", " #   ", " #  #", "  ## ",
        ],
        'u' => [BLANK, BLANK, "#   #", "#   #", "#   #", "#  ##", " ## #"],
        'v' => [BLANK, BLANK, "#   #", "#   #", "#   #", " # # ", "  #  "],
        'w' => [BLANK, BLANK, "#   #", "#   #", "# # #", "# # #", " # # "],
        'x' => [BLANK, BLANK, "#   #", " # # ", "  #  ", " # # ", "#   #"],
        'y' => [BLANK, BLANK, "#   #", "#   #", " ####", "    #", " ### "],
        'B' => [
            "#### ", "#   #", "#   #", "#### ", "#   #", "#   #", "#### ",
        ],
        'E' => [
            "#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####",
        ],
        'M' => [
            "#   #", "## ##", "# # #", "# # #", "#   #", "#   #", "#   #",
        ],
        'R' => [
            "#### ", "#   #", "#   #", "#### ", "# #  ", "#  # ", "#   #",
        ],
        'S' => [
            " ####", "#    ", "#    ", " ### ", "    #", "    #", "#### ",
        ],
        'V' => [
            "#   #", "#   #", "#   #", "#   #", "#   #", " # # ", "  #  ",
        ],
        'H' => [
            "#   #", "#   #", "#   #", "#####", "#   #", "#   #", "#   #",
        ],
        _ => [BLANK; 7],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decades_enclose_the_data() {
        assert_eq!(decade_range([0.5, 20.0].into_iter()), (-1, 2));
        assert_eq!(decade_range([10.0].into_iter()), (1, 2));
        assert_eq!(decade_range([0.0, f64::NAN].into_iter()), (0, 1));
        assert_eq!(decade_label(-3), "1e-3");
        assert_eq!(decade_label(2), "100");
    }

    #[test]
    fn curves_are_drawn_in_their_colours() {
        let series = [
            Series {
                label: "rpbrt".into(),
                colour: BLUE,
                points: vec![(1.0, 0.1), (10.0, 0.01)],
            },
            Series {
                label: "pbrt-v4".into(),
                colour: ORANGE,
                points: vec![(2.0, 0.1), (20.0, 0.01), (0.0, 1.0)],
            },
        ];
        let image = log_log_plot("scene", "seconds", "MRSE", &series).unwrap();
        assert_eq!(
            (image.width(), image.height()),
            (WIDTH as u32, HEIGHT as u32)
        );
        let count = |colour: [f32; 3]| {
            image
                .data()
                .chunks_exact(3)
                .filter(|p| *p == colour)
                .count()
        };
        assert!(count(BLUE) > 200, "{}", count(BLUE));
        assert!(count(ORANGE) > 200, "{}", count(ORANGE));
        // x spans the decades 1–100, y 0.01–0.1: the first curve's midpoint
        // (10^0.5, 10^-1.5) is a quarter across and half down, and blue.
        let (u, v) = (0.25, 0.5);
        let x = LEFT + (u * (WIDTH - LEFT - RIGHT) as f64) as usize;
        let y = TOP + (v * (HEIGHT - TOP - BOTTOM) as f64) as usize;
        assert_eq!(image.pixel(x as u32, y as u32), BLUE);
    }
}
