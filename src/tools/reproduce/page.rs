//! `index.md` and `index.html` of a `rpbrt reproduce` run: each figure's
//! image, the paper's claim, a table of its panels (render time, mean
//! luminance in each of the figure's regions, saturation), and Table 2 (render time,
//! reference model against dual model, with the ratio). The two pages
//! carry the same content; the HTML opens directly in a browser (images
//! by relative path, no scripts).

use super::{FigureResult, Model};
use crate::error::Result;
use crate::tools::io_error;
use std::fmt::Write;
use std::path::Path;

/// What the run was, for the pages' header.
pub struct Context {
    pub quality: &'static str,
    pub threads: usize,
    /// Which mesh Fig. 13's fur grew on.
    pub bunny: String,
}

/// One row of Table 2: a figure's render times per model (seconds; the
/// dual model's as a range when the figure has several dual panels).
pub struct TimingRow {
    pub figure: &'static str,
    pub reference: Option<f64>,
    pub dual: Vec<f64>,
}

impl TimingRow {
    /// Dual over reference for each dual panel.
    pub fn ratios(&self) -> Vec<f64> {
        match self.reference {
            Some(r) if r > 0.0 => self.dual.iter().map(|d| d / r).collect(),
            _ => Vec::new(),
        }
    }
}

/// Table 2's rows, one per rendered figure.
pub fn timing_rows(results: &[FigureResult]) -> Vec<TimingRow> {
    results
        .iter()
        .filter(|r| !r.panels.is_empty())
        .map(|r| {
            let reference = r
                .panels
                .iter()
                .find(|p| p.model == Model::Reference)
                .map(|p| p.record.render_seconds);
            let dual = r
                .panels
                .iter()
                .filter(|p| p.model == Model::Dual)
                .map(|p| p.record.render_seconds)
                .collect();
            TimingRow {
                figure: r.figure.id,
                reference,
                dual,
            }
        })
        .collect()
}

/// `values`' range as `lo–hi` (one value alone; "—" for none), each
/// written by `show`.
fn range(values: &[f64], show: impl Fn(f64) -> String) -> String {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(*v), hi.max(*v))
        });
    match values.len() {
        0 => "—".into(),
        1 => show(lo),
        _ => format!("{}–{}", show(lo), show(hi)),
    }
}

fn seconds_range(values: &[f64]) -> String {
    match values.len() {
        0 | 1 => range(values, |v| format!("{v:.1} s")),
        _ => format!("{} s", range(values, |v| format!("{v:.1}"))),
    }
}

fn ratio_range(values: &[f64]) -> String {
    match values.len() {
        0 | 1 => range(values, |v| format!("{v:.2}×")),
        _ => format!("{}×", range(values, |v| format!("{v:.2}"))),
    }
}

fn header(context: &Context) -> String {
    format!(
        "Quality: {}; {} render threads; rpbrt {}. Fig. 13's fur grew on {}. \
         Times are the render loop's wall time (the scene build is excluded), \
         measured in this run.",
        context.quality,
        context.threads,
        env!("CARGO_PKG_VERSION"),
        context.bunny
    )
}

/// The Markdown page.
pub fn markdown(results: &[FigureResult], context: &Context) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Benamira & Pattanaik 2021, reproduced with rpbrt\n\n{}\n",
        header(context)
    );
    for r in results {
        let _ = writeln!(
            s,
            "## {}\n\n**The paper:** {}\n\n![{}]({})\n",
            r.figure.title, r.figure.claim, r.figure.id, r.image
        );
        if !r.panels.is_empty() {
            let names: Vec<String> = r
                .figure
                .regions
                .iter()
                .map(|g| format!("mean luminance: {}", g.name))
                .collect();
            let first = r.figure.regions.first().map_or("", |g| g.name);
            let _ = writeln!(
                s,
                "| panel | scene | render time | {} | mean saturation: {first} |\n|---|---|---|{}---|",
                names.join(" | "),
                "---|".repeat(names.len())
            );
            for p in &r.panels {
                let lum: Vec<String> = p
                    .region_luminance
                    .iter()
                    .map(|v| format!("{v:.4}"))
                    .collect();
                let _ = writeln!(
                    s,
                    "| {} | `{}` | {:.1} s{} | {} | {:.3} |",
                    p.label,
                    p.scene,
                    p.record.render_seconds,
                    if p.rendered_now { "" } else { " (kept)" },
                    lum.join(" | "),
                    p.saturation
                );
            }
            s.push('\n');
        }
    }
    let _ = writeln!(
        s,
        "## Table 2: render time, reference model against dual model\n\n\
         | figure | reference | dual | dual / reference |\n|---|---|---|---|"
    );
    for row in timing_rows(results) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} |",
            row.figure,
            row.reference.map_or("—".into(), |r| format!("{r:.1} s")),
            seconds_range(&row.dual),
            ratio_range(&row.ratios())
        );
    }
    s
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The HTML page (same content as the Markdown).
pub fn html(results: &[FigureResult], context: &Context) -> String {
    let mut s = String::from(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n\
         <title>Benamira &amp; Pattanaik 2021, reproduced with rpbrt</title>\n\
         <style>body{font-family:sans-serif;max-width:1400px;margin:auto;padding:1em}\
         img{max-width:100%}table{border-collapse:collapse}\
         td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}</style>\n\
         </head><body>\n<h1>Benamira &amp; Pattanaik 2021, reproduced with rpbrt</h1>\n",
    );
    let _ = writeln!(s, "<p>{}</p>", escape(&header(context)));
    for r in results {
        let _ = writeln!(
            s,
            "<h2>{}</h2>\n<p><b>The paper:</b> {}</p>\n<p><img src=\"{}\" alt=\"{}\"></p>",
            escape(r.figure.title),
            escape(r.figure.claim),
            escape(&r.image),
            r.figure.id
        );
        if !r.panels.is_empty() {
            s.push_str("<table><tr><th>panel</th><th>scene</th><th>render time</th>");
            for g in r.figure.regions {
                let _ = write!(s, "<th>mean luminance: {}</th>", escape(g.name));
            }
            let first = r.figure.regions.first().map_or("", |g| g.name);
            let _ = writeln!(s, "<th>mean saturation: {}</th></tr>", escape(first));
            for p in &r.panels {
                let _ = write!(
                    s,
                    "<tr><td>{}</td><td><code>{}</code></td><td>{:.1} s{}</td>",
                    escape(p.label),
                    escape(p.scene),
                    p.record.render_seconds,
                    if p.rendered_now { "" } else { " (kept)" },
                );
                for v in &p.region_luminance {
                    let _ = write!(s, "<td>{v:.4}</td>");
                }
                let _ = writeln!(s, "<td>{:.3}</td></tr>", p.saturation);
            }
            s.push_str("</table>\n");
        }
    }
    s.push_str("<h2>Table 2: render time, reference model against dual model</h2>\n<table><tr><th>figure</th><th>reference</th><th>dual</th><th>dual / reference</th></tr>\n");
    for row in timing_rows(results) {
        let _ = writeln!(
            s,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            row.figure,
            row.reference.map_or("—".into(), |r| format!("{r:.1} s")),
            seconds_range(&row.dual),
            ratio_range(&row.ratios())
        );
    }
    s.push_str("</table>\n</body></html>\n");
    s
}

/// Writes `index.md` and `index.html` into `out`.
pub fn write(out: &Path, results: &[FigureResult], context: &Context) -> Result<()> {
    for (name, text) in [
        ("index.md", markdown(results, context)),
        ("index.html", html(results, context)),
    ] {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(io_error(&path))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_and_ratios() {
        let row = TimingRow {
            figure: "fig16",
            reference: Some(10.0),
            dual: vec![11.0, 12.5],
        };
        assert_eq!(ratio_range(&row.ratios()), "1.10–1.25×");
        assert_eq!(seconds_range(&row.dual), "11.0–12.5 s");
        assert_eq!(seconds_range(&[]), "—");
        let no_reference = TimingRow {
            figure: "fig16",
            reference: None,
            dual: vec![1.0],
        };
        assert!(no_reference.ratios().is_empty());
    }

    #[test]
    fn html_is_escaped() {
        assert_eq!(escape("a < b & \"c\""), "a &lt; b &amp; &quot;c&quot;");
    }
}
