//! `mrshade eval`: render benchmark datasets with each method, score against the answers the
//! way CALIBRATION.md does (FLIP heat-map mean over the frame and the changed region, PSNR),
//! time, and report (Markdown, JSON, HTML with images). Sequence datasets (posed image
//! sequences, one answer per frame) are played as footage and scored frame by frame
//! (`eval_sequence.rs`).

#[path = "eval_sequence.rs"]
mod sequence;

use super::compare::load as load_rgb8;
use super::reference::render_reference;
use super::{Log, open_gpu};
use crate::args::EvalArgs;
use anyhow::{Context, Result, bail};
use mrshade_core::HdrImage;
use mrshade_core::region::changed_region;
use mrshade_core::settings::Method;
use mrshade_eval::metrics::{Rgb8, compare};
use mrshade_eval::report::{Report, Row, RowImages};
use mrshade_gpu::{GpuContext, GpuOptions};
use mrshade_render::Renderer;
use mrshade_scene::{Session, SessionOverrides};
use std::path::Path;
use std::time::Instant;

/// Runs every method on every dataset and reports.
pub fn eval(args: &EvalArgs, gpu: &GpuOptions, log: Log) -> Result<()> {
    let mut methods: Vec<&str> = Vec::new();
    for m in &args.method {
        // `all`: every real-time method of the renderer's list, then the reference.
        let named: Vec<&str> = match m.as_str() {
            "all" => Method::ALL.iter().map(|m| m.name()).chain(["reference"]).collect(),
            m => vec![m],
        };
        for m in named {
            if !methods.contains(&m) {
                methods.push(m);
            }
        }
    }
    // Check every dataset before hours of rendering.
    let mut plans = Vec::with_capacity(args.datasets.len());
    for dir in &args.datasets {
        let plan = check(dir, &methods, args)?;
        if plan.is_some() && !args.budget_ms.is_empty() {
            bail!("dataset {}: --budget-ms is for still datasets; a sequence is scored frame by frame", dir.display());
        }
        plans.push(plan);
    }
    let ctx = if methods.iter().any(|m| *m != "reference") { Some(open_gpu(gpu, log)?) } else { None };
    let (mut rows, mut sequences) = (Vec::new(), Vec::new());
    for (i, (dir, plan)) in args.datasets.iter().zip(&plans).enumerate() {
        let scene = dir.file_name().map_or_else(|| dir.display().to_string(), |n| n.to_string_lossy().into_owned());
        // Folder names reach the terminal and the report.
        let scene = mrshade_core::text::printable(&scene).into_owned();
        if let Some(plan) = plan {
            if !args.budget_ms.is_empty() {
                bail!(
                    "dataset {}: --budget-ms is for still datasets; a sequence is scored frame by frame",
                    dir.display()
                );
            }
            log.info(format!("[{}/{}] {scene}: {}", i + 1, args.datasets.len(), methods.join(", ")));
            sequences.push(sequence::eval_sequence(dir, &scene, plan, &methods, args, ctx.as_ref(), log)?);
            continue;
        }
        let answer = load_rgb8(&dir.join("ground_truth.png"), args.max_pixels)?;
        let photo = load_rgb8(&dir.join("background.png"), args.max_pixels)?;
        if (photo.width, photo.height) != (answer.width, answer.height) {
            bail!("dataset {}: background.png and ground_truth.png differ in size", dir.display());
        }
        let region = changed_region(&answer.rgb, &photo.rgb, answer.width, answer.height);
        if let Some(out) = &args.report {
            copy_photo_and_answer(out, &scene, dir)?;
        }
        for method in &methods {
            log.info(format!("[{}/{}] {scene}: {method}", i + 1, args.datasets.len()));
            let session = load(dir, method, args, answer.width, answer.height)?;
            for run in runs(&session, method, &args.budget_ms, ctx.as_ref(), log)? {
                let result = to_rgb8(&run.image);
                let comparison = compare(&answer, &result).map_err(anyhow::Error::msg)?;
                let frame = comparison.scores(None).map_err(anyhow::Error::msg)?;
                let in_region = comparison.scores(Some(&region)).map_err(anyhow::Error::msg)?;
                let name = match run.budget_ms {
                    Some(b) => format!("{method}@{b}ms"),
                    None => method.to_string(),
                };
                let images = match &args.report {
                    Some(out) => write_images(out, &scene, &name, &result, &comparison.heatmap)?,
                    None => RowImages::default(),
                };
                let gpu_ms = (!run.gpu_ms.is_empty()).then(|| run.gpu_ms.iter().sum::<f64>());
                let row = Row {
                    scene: scene.clone(),
                    method: method.to_string(),
                    setting: setting(&session, method, &run),
                    gpu_ms,
                    gpu_ms_frame: gpu_ms.map(|total| total / run.gpu_ms.len() as f64),
                    budget_ms: run.budget_ms,
                    flip_region: in_region.flip_heatmap_mean,
                    flip_frame: frame.flip_heatmap_mean,
                    flip_error_region: in_region.flip,
                    psnr_frame: frame.psnr.is_finite().then_some(frame.psnr),
                    ssim_frame: frame.ssim,
                    region_fraction: region.iter().filter(|&&m| m).count() as f64 / region.len() as f64,
                    seconds: run.seconds,
                    device: run.device,
                    images,
                };
                let gpu = row.gpu_ms.map_or(String::new(), |ms| format!(", {ms:.2} GPU ms"));
                log.info(format!(
                    "{scene} {name}: FLIP region {:.4}, frame {:.4}, PSNR {:.2} dB ({:.1} s{gpu})",
                    row.flip_region, row.flip_frame, frame.psnr, row.seconds
                ));
                rows.push(row);
            }
        }
    }
    let report = Report { command: command_line(), version: env!("CARGO_PKG_VERSION").into(), rows, sequences };
    println!("{}", report.markdown());
    if let Some(out) = &args.report {
        write(&out.join("report.md"), report.markdown().as_bytes())?;
        write(&out.join("report.json"), report.json().as_bytes())?;
        write(&out.join("index.html"), report.html().as_bytes())?;
        log.info(format!("wrote report.md, report.json and index.html to {}", out.display()));
    }
    Ok(())
}

/// Checks a dataset's files: a still's photo and answer, or a sequence's frames (its plan).
fn check(dir: &Path, methods: &[&str], args: &EvalArgs) -> Result<Option<sequence::Plan>> {
    let layout = "a dataset folder holds session.toml, background.png and ground_truth.png, or session.toml with \
                  [sequence] transforms and ground_truth/NAME.png per frame";
    if !dir.join("session.toml").is_file() {
        bail!("dataset {}: no session.toml ({layout})", dir.display());
    }
    if sequence::declares_sequence(dir, args)
        && let Some(plan) = sequence::check(dir, methods, args)?
    {
        return Ok(Some(plan));
    }
    for file in ["background.png", "ground_truth.png"] {
        if !dir.join(file).is_file() {
            bail!("dataset {}: no {file} ({layout})", dir.display());
        }
    }
    Ok(None)
}

/// The session of `dir` for `method`, rendered at `width × height` (the answer's size).
fn load(dir: &Path, method: &str, args: &EvalArgs, width: u32, height: u32) -> Result<Session> {
    let mut set = args.set.clone();
    set.extend(args.spp.map(|n| format!("reference.spp={n}")));
    let real_time =
        (method != "reference").then(|| Method::from_name(method)).transpose().map_err(anyhow::Error::msg)?;
    // Rendered at the answer's size, whatever the session says.
    let overrides = SessionOverrides {
        width: Some(width),
        height: Some(height),
        method: real_time,
        set,
        stretch_photo: false,
        allow_read: args.allow_read.clone(),
    };
    Session::load(&dir.join("session.toml"), &overrides)
}

fn setting(session: &Session, method: &str, run: &Run) -> String {
    if method == "reference" {
        return format!("{} spp", session.settings.reference.spp);
    }
    let frames = run.frames;
    let plural = if frames == 1 { "" } else { "s" };
    match run.budget_ms {
        Some(b) => format!("{frames} frame{plural} in {b} GPU ms"),
        None => format!("{frames} frame{plural}"),
    }
}

/// One rendered still of a method.
struct Run {
    image: HdrImage,
    /// Wall-clock seconds of the render.
    seconds: f64,
    /// Where it ran.
    device: String,
    /// GPU milliseconds of every frame (empty for the reference or without timestamps).
    gpu_ms: Vec<f64>,
    /// Frames rendered.
    frames: u32,
    /// The GPU budget it was given, if any.
    budget_ms: Option<f64>,
}

/// The stills of `method`: one at the session's frames, or one per budget, each with as
/// many frames as the session's own still spends within it (at least one).
fn runs(session: &Session, method: &str, budgets: &[f64], ctx: Option<&GpuContext>, log: Log) -> Result<Vec<Run>> {
    if method == "reference" {
        let (image, seconds) = render_reference(session, log)?;
        let device = format!("CPU, {} threads", rayon::current_num_threads());
        let frames = 1;
        return Ok(vec![Run { image: image.composite, seconds, device, gpu_ms: Vec::new(), frames, budget_ms: None }]);
    }
    let ctx = ctx.context("no GPU context")?;
    let still = |frames: u32, budget_ms: Option<f64>| -> Result<Run> {
        let started = Instant::now();
        let mut renderer = Renderer::for_still(ctx, session)?;
        let bar = log.progress(frames as u64, crate::cmd::STILL_BAR)?;
        let (composite, gpu_ms) = renderer.render_still_timed(ctx, frames, |i| bar.set_position(i as u64))?;
        bar.finish_and_clear();
        let seconds = started.elapsed().as_secs_f64();
        Ok(Run { image: composite.image, seconds, device: ctx.info.name.clone(), gpu_ms, frames, budget_ms })
    };
    let full = still(session.output.frames, None)?;
    if budgets.is_empty() {
        return Ok(vec![full]);
    }
    if full.gpu_ms.len() != full.frames as usize {
        bail!("--budget-ms needs GPU timestamp queries, which adapter {} does not offer", ctx.info.name);
    }
    budgets
        .iter()
        .map(|&budget| {
            let mut spent = 0.0;
            let fit = full.gpu_ms.iter().take_while(|ms| {
                spent += **ms;
                spent <= budget
            });
            still((fit.count() as u32).max(1), Some(budget))
        })
        .collect()
}

fn to_rgb8(image: &HdrImage) -> Rgb8 {
    Rgb8 { width: image.width, height: image.height, rgb: image.to_srgb8() }
}

/// Copies the dataset's photo and answer to `out/scene/`, once per scene.
fn copy_photo_and_answer(out: &Path, scene: &str, dir: &Path) -> Result<()> {
    let folder = out.join(scene);
    std::fs::create_dir_all(&folder).with_context(|| format!("cannot create {}", folder.display()))?;
    for (from, to) in [("background.png", "photo.png"), ("ground_truth.png", "answer.png")] {
        std::fs::copy(dir.join(from), folder.join(to)).with_context(|| format!("cannot copy {from}"))?;
    }
    Ok(())
}

/// Writes one row's result and heat map under `out/scene/`, beside the photo and answer.
fn write_images(out: &Path, scene: &str, method: &str, result: &Rgb8, heatmap: &Rgb8) -> Result<RowImages> {
    let folder = out.join(scene);
    let save = |name: &str, img: &Rgb8| {
        let path = folder.join(name);
        image::save_buffer(&path, &img.rgb, img.width, img.height, image::ExtendedColorType::Rgb8)
            .with_context(|| format!("cannot write {}", path.display()))
    };
    save(&format!("{method}.png"), result)?;
    save(&format!("{method}_flip.png"), heatmap)?;
    Ok(RowImages {
        photo: format!("{scene}/photo.png"),
        result: format!("{scene}/{method}.png"),
        answer: format!("{scene}/answer.png"),
        heatmap: format!("{scene}/{method}_flip.png"),
    })
}

fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes).with_context(|| format!("cannot write {}", path.display()))
}

/// The command as typed (arguments quoted where they hold spaces).
fn command_line() -> String {
    let args: Vec<String> =
        std::env::args().skip(1).map(|a| if a.contains(' ') { format!("'{a}'") } else { a }).collect();
    format!("mrshade {}", args.join(" "))
}
