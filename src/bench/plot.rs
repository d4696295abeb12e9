//! The bench's plot: relMSE against seconds, log–log, one panel per scene and one line per
//! integrator, with the thresholds of [`super::THRESHOLDS`] drawn across. A previous record
//! ("before") is drawn dashed beside the new one. Plain SVG, written by hand: a few lines and
//! labels need no plotting library.

use super::{Run, THRESHOLDS};
use std::fmt::Write;

const PANEL_W: f64 = 420.0;
const PANEL_H: f64 = 320.0;
const MARGIN: f64 = 56.0;
const COLOURS: [(&str, &str); 8] = [
    ("photon", "#1f77b4"),
    ("sppm", "#d62728"),
    ("ppm", "#2ca02c"),
    ("path", "#9467bd"),
    ("direct", "#8c564b"),
    ("vcm", "#ff7f0e"),
    ("bdpt", "#17becf"),
    ("lighttrace", "#bcbd22"),
];

fn colour(integrator: &str) -> &'static str {
    COLOURS
        .iter()
        .find(|(n, _)| *n == integrator)
        .map_or("#555555", |(_, c)| c)
}

/// Axis range in log10, widened to whole decades around the values.
fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.log10()), hi.max(v.log10()))
        });
    if lo > hi {
        return (-1.0, 1.0);
    }
    let (lo, hi) = (lo.floor(), hi.ceil());
    if lo == hi { (lo, lo + 1.0) } else { (lo, hi) }
}

/// The SVG of `runs` (and of `before`, dashed), titled `title`.
pub fn svg(title: &str, runs: &[Run], before: &[Run]) -> String {
    let mut scenes: Vec<&str> = Vec::new();
    for r in runs.iter().chain(before) {
        if r.rel_mse.is_some() && !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    let all = || runs.iter().chain(before).filter(|r| r.rel_mse.is_some());
    let (t0, t1) = decades(all().map(|r| r.seconds));
    let (e0, e1) = decades(all().filter_map(|r| r.rel_mse).chain(THRESHOLDS));
    let width = MARGIN + scenes.len().max(1) as f64 * (PANEL_W + MARGIN);
    let height = PANEL_H + 2.5 * MARGIN;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(
        s,
        r#"<rect width="100%" height="100%" fill="white"/><text x="{MARGIN}" y="20" font-size="14">{}</text>"#,
        escape(title)
    );
    for (i, scene) in scenes.iter().enumerate() {
        let x0 = MARGIN + i as f64 * (PANEL_W + MARGIN);
        let y0 = 1.5 * MARGIN;
        let px = |t: f64| x0 + (t.log10() - t0) / (t1 - t0) * PANEL_W;
        let py = |e: f64| y0 + (e1 - e.log10()) / (e1 - e0) * PANEL_H;
        let _ = writeln!(
            s,
            r##"<rect x="{x0}" y="{y0}" width="{PANEL_W}" height="{PANEL_H}" fill="none" stroke="#333"/><text x="{x0}" y="{}">{}: relMSE against seconds</text>"##,
            y0 - 8.0,
            escape(scene)
        );
        for d in t0 as i32..=t1 as i32 {
            let x = px(10f64.powi(d));
            let _ = writeln!(
                s,
                r##"<line x1="{x}" y1="{y0}" x2="{x}" y2="{}" stroke="#ddd"/><text x="{x}" y="{}" text-anchor="middle">{}</text>"##,
                y0 + PANEL_H,
                y0 + PANEL_H + 16.0,
                10f64.powi(d)
            );
        }
        for d in e0 as i32..=e1 as i32 {
            let y = py(10f64.powi(d));
            let _ = writeln!(
                s,
                r##"<line x1="{x0}" y1="{y}" x2="{}" y2="{y}" stroke="#ddd"/><text x="{}" y="{}" text-anchor="end">1e{d}</text>"##,
                x0 + PANEL_W,
                x0 - 4.0,
                y + 4.0
            );
        }
        for t in THRESHOLDS {
            let y = py(t);
            let _ = writeln!(
                s,
                r##"<line x1="{x0}" y1="{y}" x2="{}" y2="{y}" stroke="#999" stroke-dasharray="2,3"/><text x="{}" y="{}" fill="#777">{t}</text>"##,
                x0 + PANEL_W,
                x0 + PANEL_W - 40.0,
                y - 3.0
            );
        }
        // The legend sits in the lower left, where error-against-time curves never go.
        let entries = [before, runs]
            .iter()
            .map(|set| {
                let mut names: Vec<&str> = set
                    .iter()
                    .filter(|r| r.scene == *scene)
                    .map(|r| r.integrator.as_str())
                    .collect();
                names.sort_unstable();
                names.dedup();
                names.len()
            })
            .sum::<usize>();
        let mut legend = 0;
        for (set, dashed) in [(before, true), (runs, false)] {
            let mut integrators: Vec<&str> = Vec::new();
            for r in set.iter().filter(|r| r.scene == *scene) {
                if !integrators.contains(&r.integrator.as_str()) {
                    integrators.push(&r.integrator);
                }
            }
            for integrator in integrators {
                let mut points: Vec<(f64, f64)> = set
                    .iter()
                    .filter(|r| r.scene == *scene && r.integrator == integrator)
                    .filter_map(|r| Some((r.seconds, r.rel_mse?)))
                    .filter(|(t, e)| *t > 0.0 && *e > 0.0)
                    .collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                let path: Vec<String> = points
                    .iter()
                    .map(|&(t, e)| format!("{:.1},{:.1}", px(t), py(e)))
                    .collect();
                let c = colour(integrator);
                let dash = if dashed {
                    r#" stroke-dasharray="6,4""#
                } else {
                    ""
                };
                let _ = writeln!(
                    s,
                    r#"<polyline points="{}" fill="none" stroke="{c}" stroke-width="2"{dash}/>"#,
                    path.join(" ")
                );
                for p in &path {
                    let (x, y) = p.split_once(',').unwrap_or(("0", "0"));
                    let _ = writeln!(s, r#"<circle cx="{x}" cy="{y}" r="3" fill="{c}"/>"#);
                }
                let label = if dashed {
                    format!("{integrator} (before)")
                } else {
                    integrator.to_string()
                };
                let ly = y0 + PANEL_H - 8.0 - 14.0 * (entries - 1 - legend) as f64;
                let _ = writeln!(
                    s,
                    r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{c}" stroke-width="2"{dash}/><text x="{}" y="{ly}">{}</text>"#,
                    x0 + 8.0,
                    ly - 4.0,
                    x0 + 30.0,
                    ly - 4.0,
                    x0 + 34.0,
                    escape(&label)
                );
                legend += 1;
            }
        }
    }
    s.push_str("</svg>\n");
    s
}

fn escape(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::test_run as run;

    /// The plot has a panel per scene, a line per integrator (dashed for the record before),
    /// and points placed by log time: a later run sits further right.
    #[test]
    fn the_plot_draws_each_run_where_it_belongs() {
        let runs = [
            run("cornell", "ppm", 1.0, 0.01),
            run("cornell", "ppm", 10.0, 0.001),
            run("seed", "path", 1.0, 0.1),
        ];
        let before = [run("cornell", "ppm", 10.0, 0.003)];
        let s = svg("t <1>", &runs, &before);
        assert!(s.starts_with("<svg") && s.ends_with("</svg>\n"));
        assert!(s.contains("cornell: relMSE") && s.contains("seed: relMSE"));
        assert!(s.contains("t &lt;1&gt;"));
        assert_eq!(s.matches("<polyline").count(), 3);
        assert_eq!(s.matches("stroke-dasharray=\"6,4\"").count(), 2);
        let xs: Vec<f64> = s
            .lines()
            .filter(|l| l.contains("<polyline") && l.contains("#2ca02c") && !l.contains("6,4"))
            .flat_map(|l| {
                let pts = l.split('"').nth(1).unwrap_or("").to_string();
                pts.split(' ')
                    .map(|p| {
                        p.split(',')
                            .next()
                            .unwrap_or("0")
                            .parse::<f64>()
                            .unwrap_or(0.0)
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        assert_eq!(xs.len(), 2);
        assert!((xs[1] - xs[0] - PANEL_W).abs() < 0.2, "{xs:?}");
    }
}
