//! The grand comparison's chart (Franke Fig. 5.19): per scene, the error (FLIP over the
//! changed region) against the GPU time the still cost, one point per method and setting, a
//! method's settings (`--budget-ms`) joined by a line. Inline SVG, drawn by hand: a few dozen
//! points need no plotting library.

use crate::report::{Row, escape};
use std::fmt::Write;

const WIDTH: f64 = 560.0;
const HEIGHT: f64 = 320.0;
const LEFT: f64 = 60.0;
const RIGHT: f64 = 130.0;
const TOP: f64 = 16.0;
const BOTTOM: f64 = 44.0;
/// Colors of the methods, in order of first appearance.
const PALETTE: [&str; 8] = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"];

/// The charts of every scene with timed rows (a note where no row has GPU times).
pub(crate) fn error_against_gpu_time(rows: &[Row]) -> String {
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if r.gpu_ms.is_some() && !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    if scenes.is_empty() {
        return "<p>No GPU times (no real-time method ran, or the adapter has no timestamp queries): no chart of \
                error against GPU time.</p>\n"
            .into();
    }
    let mut s = String::from(
        "<h2>Error against GPU time</h2>\n<p>FLIP over the changed region against the GPU milliseconds the \
         still cost (all its frames, timestamp queries), one point per method and setting; lower left is \
         better.</p>\n",
    );
    for scene in scenes {
        let points: Vec<&Row> = rows.iter().filter(|r| r.scene == scene && r.gpu_ms.is_some()).collect();
        s.push_str(&scene_chart(scene, &points));
    }
    s
}

/// Powers of ten and their 2× and 5× between `lo` and `hi`.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut ticks = Vec::new();
    let mut decade = 10f64.powf(lo.log10().floor());
    while decade <= hi {
        for m in [1.0, 2.0, 5.0] {
            let t = decade * m;
            if t >= lo && t <= hi {
                ticks.push(t);
            }
        }
        decade *= 10.0;
    }
    ticks
}

fn scene_chart(scene: &str, points: &[&Row]) -> String {
    let times: Vec<f64> = points.iter().filter_map(|r| r.gpu_ms).collect();
    let (mut lo, mut hi) = times.iter().fold((f64::MAX, f64::MIN), |(l, h), &t| (l.min(t), h.max(t)));
    lo = (lo / 1.5).max(1e-6);
    hi *= 1.5;
    let top = points.iter().map(|r| r.flip_region).fold(0.0, f64::max).max(1e-3) * 1.1;
    let (plot_w, plot_h) = (WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM);
    let x = |t: f64| LEFT + (t.log10() - lo.log10()) / (hi.log10() - lo.log10()) * plot_w;
    let y = |f: f64| TOP + (1.0 - f / top) * plot_h;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<figure><svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{HEIGHT}\" \
         font-family=\"sans-serif\" font-size=\"11\" role=\"img\"><title>{}: FLIP region against GPU ms</title>",
        escape(scene)
    );
    let _ = writeln!(
        s,
        "<rect x=\"{LEFT}\" y=\"{TOP}\" width=\"{plot_w}\" height=\"{plot_h}\" fill=\"none\" stroke=\"#888\"/>"
    );
    for t in log_ticks(lo, hi) {
        let px = x(t);
        let _ = writeln!(
            s,
            "<line x1=\"{px:.1}\" y1=\"{TOP}\" x2=\"{px:.1}\" y2=\"{:.1}\" stroke=\"#eee\"/><text x=\"{px:.1}\" y=\"{:.1}\" \
             text-anchor=\"middle\">{t}</text>",
            TOP + plot_h,
            TOP + plot_h + 14.0
        );
    }
    for k in 0..=4 {
        let f = top * k as f64 / 4.0;
        let py = y(f);
        let _ = writeln!(
            s,
            "<line x1=\"{LEFT}\" y1=\"{py:.1}\" x2=\"{:.1}\" y2=\"{py:.1}\" stroke=\"#eee\"/><text x=\"{:.1}\" y=\"{:.1}\" \
             text-anchor=\"end\">{f:.3}</text>",
            LEFT + plot_w,
            LEFT - 4.0,
            py + 4.0
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">GPU ms per still (log)</text>\
         <text transform=\"translate(14 {:.1}) rotate(-90)\" text-anchor=\"middle\">FLIP region</text>",
        LEFT + plot_w / 2.0,
        HEIGHT - 6.0,
        TOP + plot_h / 2.0
    );
    let mut methods: Vec<&str> = Vec::new();
    for r in points {
        if !methods.contains(&r.method.as_str()) {
            methods.push(&r.method);
        }
    }
    for (i, method) in methods.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        let mut series: Vec<&&Row> = points.iter().filter(|r| r.method == *method).collect();
        series.sort_by(|a, b| a.gpu_ms.unwrap_or(0.0).total_cmp(&b.gpu_ms.unwrap_or(0.0)));
        if series.len() > 1 {
            let path: Vec<String> =
                series.iter().map(|r| format!("{:.1},{:.1}", x(r.gpu_ms.unwrap_or(lo)), y(r.flip_region))).collect();
            let _ = writeln!(s, "<polyline points=\"{}\" fill=\"none\" stroke=\"{color}\"/>", path.join(" "));
        }
        for r in &series {
            let t = r.gpu_ms.unwrap_or(lo);
            let _ = writeln!(
                s,
                "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"4\" fill=\"{color}\"><title>{} ({}): FLIP region {:.4}, {:.3} GPU ms</title></circle>",
                x(t),
                y(r.flip_region),
                escape(method),
                escape(&r.setting),
                r.flip_region,
                t
            );
        }
        let ly = TOP + 12.0 + 16.0 * i as f64;
        let lx = LEFT + plot_w + 12.0;
        let _ = writeln!(
            s,
            "<circle cx=\"{lx:.1}\" cy=\"{:.1}\" r=\"4\" fill=\"{color}\"/><text x=\"{:.1}\" y=\"{ly:.1}\">{}</text>",
            ly - 4.0,
            lx + 8.0,
            escape(method)
        );
    }
    let _ = writeln!(s, "</svg><figcaption>{}</figcaption></figure>", escape(scene));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_cover_the_range_in_1_2_5_steps() {
        assert_eq!(log_ticks(0.3, 25.0), vec![0.5, 1.0, 2.0, 5.0, 10.0, 20.0]);
    }
}
