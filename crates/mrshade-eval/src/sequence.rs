//! The sequence part of the evaluation report: per frame scores of each method on a posed
//! image sequence, their summary (means, the worst frame, frames that beat the untouched
//! photo), the sequence-versus-stills quality bar, and the Markdown and HTML that show them
//! (an inline SVG plot of FLIP per frame and a frame slider, no script library).

use crate::report::escape;
use serde::Serialize;
use std::fmt::Write;

/// First frame (index in the sequence) of the `flip_region_from4` mean: a temporal method's
/// history is still short over the first frames of a sequence.
pub const FROM_FRAME: usize = 4;

/// The quality bar: a method played as a sequence may have at most this times the mean region
/// FLIP (over frames [`FROM_FRAME`]..) of the same frames rendered as converged stills.
pub const STILLS_RATIO_BAR: f64 = 1.3;

/// The method name of the untouched photo, scored as if it were a result.
pub const PHOTO: &str = "photo";

/// The scores of one frame.
#[derive(Clone, Debug, Serialize)]
pub struct FrameScores {
    /// The frame's name (its image's stem, e.g. `0007`).
    pub name: String,
    /// FLIP over the changed region (heat-map mean); null when the answer does not differ
    /// from the photo anywhere in this frame (nothing to score).
    pub flip_region: Option<f64>,
    /// FLIP over the frame (heat-map mean).
    pub flip_frame: f64,
    /// PSNR of the frame, dB (null for an exact match).
    pub psnr_frame: Option<f64>,
    /// The result image, relative to the report's folder (empty without a report).
    pub result: String,
    /// FLIP's heat map of the result, relative to the report's folder (empty without a report).
    pub heatmap: String,
}

/// What one method's frames add up to.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Summary {
    /// Mean region FLIP over the frames that have a region.
    pub flip_region: Option<f64>,
    /// Mean frame FLIP.
    pub flip_frame: f64,
    /// Mean PSNR over the frames of finite PSNR.
    pub psnr_frame: Option<f64>,
    /// Mean region FLIP over frames [`FROM_FRAME`].. (null for a shorter sequence).
    pub flip_region_from4: Option<f64>,
    /// The frame of the largest region FLIP.
    pub worst_frame: Option<String>,
    /// That frame's region FLIP.
    pub worst_flip_region: Option<f64>,
    /// Frames whose region FLIP is lower than the photo's own (null for the photo).
    pub beats_photo: Option<usize>,
}

/// One method on one sequence.
#[derive(Clone, Debug, Serialize)]
pub struct MethodRun {
    /// The method's name (`dir`, `dir-stills`, `reference`, or [`PHOTO`]).
    pub method: String,
    /// What it ran with.
    pub setting: String,
    /// Wall-clock seconds of rendering, all frames (loading and scoring excluded).
    pub seconds: f64,
    /// Where it ran.
    pub device: String,
    /// What the frames add up to.
    pub summary: Summary,
    /// One entry per frame, in sequence order.
    pub frames: Vec<FrameScores>,
}

impl MethodRun {
    /// A run and its summary; `photo`: the photo's own scores of the same frames, for
    /// counting the frames it beats (`None` for the photo itself).
    pub fn new(
        method: String,
        setting: String,
        seconds: f64,
        device: String,
        frames: Vec<FrameScores>,
        photo: Option<&[FrameScores]>,
    ) -> Self {
        let summary = summarise(&frames, photo);
        Self { method, setting, seconds, device, summary, frames }
    }
}

fn mean(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| sum / n as f64)
}

fn summarise(frames: &[FrameScores], photo: Option<&[FrameScores]>) -> Summary {
    let worst = frames.iter().filter_map(|f| f.flip_region.map(|v| (f, v))).max_by(|a, b| a.1.total_cmp(&b.1));
    let beats_photo = photo.map(|photo| {
        frames
            .iter()
            .zip(photo)
            .filter(|(f, p)| matches!((f.flip_region, p.flip_region), (Some(a), Some(b)) if a < b))
            .count()
    });
    Summary {
        flip_region: mean(frames.iter().filter_map(|f| f.flip_region)),
        flip_frame: mean(frames.iter().map(|f| f.flip_frame)).unwrap_or(0.0),
        psnr_frame: mean(frames.iter().filter_map(|f| f.psnr_frame)),
        flip_region_from4: mean(frames.iter().skip(FROM_FRAME).filter_map(|f| f.flip_region)),
        worst_frame: worst.map(|(f, _)| f.name.clone()),
        worst_flip_region: worst.map(|(_, v)| v),
        beats_photo,
    }
}

/// The quality bar of one method: played as a sequence against rendered as stills.
#[derive(Clone, Debug, Serialize)]
pub struct QualityBar {
    /// The method (its stills are `<method>-stills`).
    pub method: String,
    /// Mean region FLIP over frames [`FROM_FRAME`].. of the sequence run.
    pub sequence: f64,
    /// The same of the stills.
    pub stills: f64,
    /// `sequence / stills`.
    pub ratio: f64,
    /// The largest ratio that passes, [`STILLS_RATIO_BAR`].
    pub bar: f64,
    /// Whether `ratio ≤ bar`.
    pub met: bool,
}

impl QualityBar {
    /// One line for the log and the Markdown.
    pub fn line(&self, sequence: &str, frames: usize) -> String {
        format!(
            "{sequence} {}: mean FLIP region over frames {FROM_FRAME}..{}: sequence {:.4}, stills {:.4}, ratio {:.3} \
             (bar ≤ {}: {})",
            self.method,
            frames.saturating_sub(1),
            self.sequence,
            self.stills,
            self.ratio,
            self.bar,
            if self.met { "met" } else { "NOT met" }
        )
    }
}

/// Every method on one sequence.
#[derive(Clone, Debug, Serialize)]
pub struct SequenceReport {
    /// The dataset folder's name; also the folder of its images in the report.
    pub name: String,
    /// The frames' names, in order.
    pub frames: Vec<String>,
    /// The untouched photo's own scores (inserting nothing).
    pub photo: MethodRun,
    /// One run per method (stills as `<method>-stills`).
    pub runs: Vec<MethodRun>,
    /// Sequence against stills, for each method run both ways.
    pub quality_bars: Vec<QualityBar>,
}

impl SequenceReport {
    /// The report of one sequence, with its quality bars.
    pub fn new(name: String, photo: MethodRun, runs: Vec<MethodRun>) -> Self {
        let frames = photo.frames.iter().map(|f| f.name.clone()).collect();
        let quality_bars = runs
            .iter()
            .filter_map(|run| {
                let stills = runs.iter().find(|r| r.method == format!("{}-stills", run.method))?;
                let (sequence, stills) = (run.summary.flip_region_from4?, stills.summary.flip_region_from4?);
                let ratio = if stills > 0.0 { sequence / stills } else { f64::INFINITY };
                Some(QualityBar {
                    method: run.method.clone(),
                    sequence,
                    stills,
                    ratio,
                    bar: STILLS_RATIO_BAR,
                    met: ratio <= STILLS_RATIO_BAR,
                })
            })
            .collect();
        Self { name, frames, photo, runs, quality_bars }
    }

    fn rows(&self) -> impl Iterator<Item = &MethodRun> {
        std::iter::once(&self.photo).chain(&self.runs)
    }
}

fn number(v: Option<f64>, digits: usize) -> String {
    v.map_or("—".into(), |v| format!("{v:.digits$}"))
}

fn worst(s: &Summary) -> String {
    match (&s.worst_frame, s.worst_flip_region) {
        (Some(name), Some(v)) => format!("{name} ({v:.4})"),
        _ => "—".into(),
    }
}

fn beats(s: &Summary, frames: usize) -> String {
    s.beats_photo.map_or("—".into(), |n| format!("{n}/{frames}"))
}

/// The Markdown of the sequences: one summary row per (sequence, method), then the bars.
pub fn markdown(sequences: &[SequenceReport]) -> String {
    let mut s = String::from(
        "Sequences: means over all frames; \"frames 4..\" leaves out the first frames, over which a temporal \
         method's history builds up; \"beats photo\": frames whose region FLIP is below the untouched photo's. \
         PSNR: mean over the frames.\n\n",
    );
    s.push_str(
        "| sequence | method | setting | FLIP region | FLIP frame | PSNR frame (dB) | FLIP region, frames 4.. | \
         worst frame (FLIP region) | beats photo | time (s) |\n",
    );
    s.push_str("|---|---|---|---|---|---|---|---|---|---|\n");
    for q in sequences {
        for r in q.rows() {
            let m = &r.summary;
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.4} | {} | {} | {} | {} | {:.1} |",
                q.name,
                r.method,
                r.setting,
                number(m.flip_region, 4),
                m.flip_frame,
                number(m.psnr_frame, 1),
                number(m.flip_region_from4, 4),
                worst(m),
                beats(m, q.frames.len()),
                r.seconds
            );
        }
    }
    let bars: Vec<String> =
        sequences.iter().flat_map(|q| q.quality_bars.iter().map(|b| b.line(&q.name, q.frames.len()))).collect();
    if !bars.is_empty() {
        s.push('\n');
        for line in bars {
            let _ = writeln!(s, "- {line}");
        }
    }
    s
}

/// Line colours of the plot, photo first.
const COLOURS: [&str; 6] = ["#888", "#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"];

/// The HTML of the sequences: a summary table, then per sequence a plot of region FLIP per
/// frame and a frame slider over photo | result | answer | heat map.
pub fn html(sequences: &[SequenceReport]) -> String {
    let mut s = String::from(
        "<h2>Sequences</h2>\n<table><tr><th>sequence</th><th>method</th><th>setting</th><th>FLIP region</th>\
         <th>FLIP frame</th><th>PSNR</th><th>FLIP region, frames 4..</th><th>worst frame</th><th>beats photo</th>\
         <th>time (s)</th></tr>\n",
    );
    for q in sequences {
        for r in q.rows() {
            let m = &r.summary;
            let _ = writeln!(
                s,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.4}</td><td>{}</td><td>{}</td><td>{}</td>\
                 <td>{}</td><td>{:.1}</td></tr>",
                escape(&q.name),
                escape(&r.method),
                escape(&r.setting),
                number(m.flip_region, 4),
                m.flip_frame,
                number(m.psnr_frame, 1),
                number(m.flip_region_from4, 4),
                escape(&worst(m)),
                beats(m, q.frames.len()),
                r.seconds
            );
        }
    }
    s.push_str("</table>\n");
    for q in sequences {
        for b in &q.quality_bars {
            let _ = writeln!(s, "<p>{}</p>", escape(&b.line(&q.name, q.frames.len())));
        }
    }
    for (i, q) in sequences.iter().enumerate() {
        section(&mut s, i, q);
    }
    s.push_str(SCRIPT);
    s
}

/// One sequence: the plot, the slider, the four images, and the data the script reads.
fn section(s: &mut String, index: usize, q: &SequenceReport) {
    let _ = writeln!(s, "<section class=\"sequence\" id=\"seq{index}\"><h3>{}</h3>", escape(&q.name));
    plot(s, q);
    let options: String = q
        .rows()
        .enumerate()
        .map(|(i, r)| {
            let selected = if i == 1 { " selected" } else { "" };
            format!("<option{selected}>{}</option>", escape(&r.method))
        })
        .collect();
    let _ = writeln!(
        s,
        "<p><label>method <select class=\"method\">{options}</select></label> \
         <label>frame <input class=\"frame\" type=\"range\" min=\"0\" max=\"{}\" value=\"0\"></label> \
         <span class=\"label\"></span></p>",
        q.frames.len().saturating_sub(1)
    );
    for caption in ["photo", "result", "answer", "FLIP heat map"] {
        let _ = writeln!(s, "<figure><img alt=\"{caption}\"><figcaption>{caption}</figcaption></figure>");
    }
    // What the script needs: folder, frame names, and per method its region FLIP per frame.
    let flip: std::collections::BTreeMap<&str, Vec<Option<f64>>> =
        q.rows().map(|r| (r.method.as_str(), r.frames.iter().map(|f| f.flip_region).collect())).collect();
    let data = serde_json::json!({ "folder": q.name, "frames": q.frames, "flip": flip });
    // `</` would end the script element early.
    let json = data.to_string().replace("</", "<\\/");
    let _ = writeln!(s, "<script type=\"application/json\">{json}</script></section>");
}

/// Plot size, in SVG user units.
const W: f64 = 720.0;
const H: f64 = 260.0;
/// Margins: the y axis's labels, the x axis's, above, and the legend.
const LEFT: f64 = 50.0;
const BOTTOM: f64 = 36.0;
const TOP: f64 = 10.0;
const RIGHT: f64 = 130.0;

/// Region FLIP per frame, one polyline per method and one for the photo, with a legend, the
/// start of the frames-4.. window dashed, and a cursor at the slider's frame.
fn plot(s: &mut String, q: &SequenceReport) {
    let n = q.frames.len();
    let top = q.rows().flat_map(|r| r.frames.iter().filter_map(|f| f.flip_region)).fold(0.0f64, f64::max);
    let top = if top > 0.0 { nice_ceiling(top) } else { 1.0 };
    let (pw, ph) = (W - LEFT - RIGHT, H - TOP - BOTTOM);
    let x = |k: usize| LEFT + if n > 1 { pw * k as f64 / (n - 1) as f64 } else { pw / 2.0 };
    let y = |v: f64| TOP + ph * (1.0 - v / top);
    let _ = writeln!(
        s,
        "<svg class=\"plot\" width=\"{W}\" height=\"{H}\" viewBox=\"0 0 {W} {H}\" font-size=\"11\">\
         <rect x=\"{LEFT}\" y=\"{TOP}\" width=\"{pw}\" height=\"{ph}\" fill=\"none\" stroke=\"#ccc\"/>"
    );
    for t in 0..=4 {
        let v = top * t as f64 / 4.0;
        let _ = write!(
            s,
            "<line x1=\"{LEFT}\" x2=\"{}\" y1=\"{yy:.1}\" y2=\"{yy:.1}\" stroke=\"#eee\"/>\
             <text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{v:.3}</text>",
            LEFT + pw,
            LEFT - 4.0,
            y(v) + 4.0,
            yy = y(v),
        );
    }
    let step = n.div_ceil(12).max(1);
    for k in (0..n).step_by(step) {
        let _ = write!(
            s,
            "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
            x(k),
            TOP + ph + 14.0,
            escape(&q.frames[k])
        );
    }
    if n > FROM_FRAME {
        let _ = write!(
            s,
            "<line x1=\"{xx:.1}\" x2=\"{xx:.1}\" y1=\"{TOP}\" y2=\"{}\" stroke=\"#999\" stroke-dasharray=\"4 3\"/>",
            TOP + ph,
            xx = x(FROM_FRAME)
        );
    }
    for (i, r) in q.rows().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let points: Vec<String> = r
            .frames
            .iter()
            .enumerate()
            .filter_map(|(k, f)| f.flip_region.map(|v| format!("{:.1},{:.1}", x(k), y(v))))
            .collect();
        let dash = if r.method == PHOTO { " stroke-dasharray=\"2 2\"" } else { "" };
        let _ = write!(
            s,
            "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\"{dash} points=\"{}\"/>\
             <line x1=\"{lx}\" x2=\"{}\" y1=\"{ly}\" y2=\"{ly}\" stroke=\"{colour}\" stroke-width=\"2\"{dash}/>\
             <text x=\"{}\" y=\"{}\">{}</text>",
            points.join(" "),
            W - RIGHT + 34.0,
            W - RIGHT + 38.0,
            TOP + 14.0 + 16.0 * i as f64 + 4.0,
            escape(&r.method),
            lx = W - RIGHT + 14.0,
            ly = TOP + 14.0 + 16.0 * i as f64,
        );
    }
    let _ = writeln!(
        s,
        "<line class=\"cursor\" x1=\"{xx:.1}\" x2=\"{xx:.1}\" y1=\"{TOP}\" y2=\"{}\" stroke=\"#000\"/>\
         <text x=\"{}\" y=\"{}\" text-anchor=\"middle\">frame (FLIP over the changed region, lower is better)</text></svg>",
        TOP + ph,
        LEFT + pw / 2.0,
        H - 4.0,
        xx = x(0)
    );
}

/// The smallest of 1, 2, 2.5, 3, 4, 5, 6, 8 × 10^k at or above `v` (a round top for the axis).
fn nice_ceiling(v: f64) -> f64 {
    // Dividing by 10^-e rather than multiplying by 10^e keeps 0.6 exact for the labels.
    let e = v.log10().floor() as i32;
    let scale = |m: f64| if e >= 0 { m * 10f64.powi(e) } else { m / 10f64.powi(-e) };
    [1.0, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0].into_iter().map(scale).find(|&c| c >= v * (1.0 - 1e-12)).unwrap_or(v)
}

/// Per section: the slider and the select swap the four images and move the plot's cursor.
/// Image paths follow the report's layout: `folder/method/name.png` and `name_flip.png`,
/// `folder/photo/name.png`, `folder/answer/name.png`.
const SCRIPT: &str = r#"<script>
for (const sec of document.querySelectorAll("section.sequence")) {
  const d = JSON.parse(sec.querySelector("script[type='application/json']").textContent);
  const [slider, select, label] = ["input.frame", "select.method", "span.label"].map(q => sec.querySelector(q));
  const imgs = sec.querySelectorAll("figure img"), cursor = sec.querySelector("line.cursor");
  const plot = sec.querySelector("rect");
  const path = (m, name) => [d.folder, m, name].map(encodeURIComponent).join("/");
  const show = () => {
    const k = +slider.value, name = d.frames[k], m = select.value, v = d.flip[m][k];
    const src = [path("photo", name + ".png"), path(m, name + ".png"), path("answer", name + ".png"), path(m, name + "_flip.png")];
    imgs.forEach((img, i) => img.src = src[i]);
    label.textContent = `frame ${name} (${k + 1}/${d.frames.length}): ${m} FLIP region ${v == null ? "—" : v.toFixed(4)}, photo ${d.flip.photo[k] == null ? "—" : d.flip.photo[k].toFixed(4)}`;
    const x0 = +plot.getAttribute("x"), w = +plot.getAttribute("width"), n = d.frames.length;
    const x = n > 1 ? x0 + w * k / (n - 1) : x0 + w / 2;
    cursor.setAttribute("x1", x); cursor.setAttribute("x2", x);
  };
  slider.oninput = select.onchange = show;
  show();
}
</script>
"#;

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(values: &[Option<f64>]) -> Vec<FrameScores> {
        values
            .iter()
            .enumerate()
            .map(|(k, &v)| FrameScores {
                name: format!("{:04}", 2 * k),
                flip_region: v,
                flip_frame: v.unwrap_or(0.0) / 10.0,
                psnr_frame: if k == 0 { None } else { Some(30.0 + k as f64) },
                result: String::new(),
                heatmap: String::new(),
            })
            .collect()
    }

    fn report() -> SequenceReport {
        let photo = frames(&[Some(0.5); 6]);
        let run = |method: &str, values: &[Option<f64>]| {
            MethodRun::new(method.into(), "x".into(), 1.0, "cpu".into(), frames(values), Some(&photo))
        };
        let dir = run("dir", &[Some(0.9), Some(0.6), Some(0.2), Some(0.1), Some(0.12), None]);
        let stills = run("dir-stills", &[Some(0.1), Some(0.1), Some(0.1), Some(0.1), Some(0.1), Some(0.1)]);
        let photo = MethodRun::new(PHOTO.into(), "do nothing".into(), 0.0, String::new(), photo, None);
        SequenceReport::new("orbit<1>".into(), photo, vec![dir, stills])
    }

    #[test]
    fn the_summary_counts_what_the_issue_asks() {
        let r = report();
        let s = &r.runs[0].summary;
        assert!((s.flip_region.unwrap() - (0.9 + 0.6 + 0.2 + 0.1 + 0.12) / 5.0).abs() < 1e-12);
        // Frames 4.. are the fifth and sixth; the sixth has no region.
        assert!((s.flip_region_from4.unwrap() - 0.12).abs() < 1e-12);
        assert_eq!((s.worst_frame.as_deref(), s.worst_flip_region), (Some("0000"), Some(0.9)));
        assert_eq!(s.beats_photo, Some(3));
        // PSNR: the exact match of frame 0 is left out of the mean.
        assert!((s.psnr_frame.unwrap() - 33.0).abs() < 1e-12);
        assert_eq!(r.photo.summary.beats_photo, None);
        let bar = &r.quality_bars[0];
        assert_eq!(bar.method, "dir");
        assert!((bar.ratio - 1.2).abs() < 1e-9 && bar.met);
    }

    #[test]
    fn markdown_and_html_hold_the_rows_the_plot_and_the_slider() {
        let r = report();
        let md = markdown(std::slice::from_ref(&r));
        assert!(md.contains("| orbit<1> | dir | x | 0.3840 |"), "{md}");
        assert!(md.contains("| 0000 (0.9000) | 3/6 |") && md.contains("ratio 1.200 (bar ≤ 1.3: met)"), "{md}");
        let html = html(&[r]);
        assert!(html.contains("<svg") && html.matches("<polyline").count() == 3);
        assert!(html.contains("type=\"range\"") && html.contains("orbit&lt;1&gt;"));
        assert!(html.contains("\"folder\":\"orbit<1>\""), "JSON data for the script");
    }

    #[test]
    fn the_axis_top_is_round() {
        assert_eq!(nice_ceiling(0.37), 0.4);
        assert_eq!(nice_ceiling(0.5455), 0.6);
        assert_eq!(nice_ceiling(0.05), 0.05);
        assert_eq!(nice_ceiling(0.021), 0.025);
    }
}
