//! `mrshade eval` of a sequence dataset: session.toml with `[sequence] transforms`, the frames
//! it lists, and `ground_truth/NAME.png` per frame. Each real-time method plays the whole
//! sequence once as footage (temporal reuse across frames, as live) and every frame is scored
//! against its answer as a still is; with `--stills`, every frame is also rendered alone as a
//! converged still (`METHOD-stills`), the bar the footage is held to. The untouched photo is
//! scored too: a method should beat inserting nothing.

use super::{Log, load, load_rgb8, render_reference, to_rgb8};
use crate::args::EvalArgs;
use anyhow::{Context, Result, bail};
use mrshade_core::region::changed_region;
use mrshade_eval::metrics::{Rgb8, compare};
use mrshade_eval::sequence::{FrameScores, MethodRun, PHOTO, SequenceReport};
use mrshade_gpu::GpuContext;
use mrshade_render::Renderer;
use mrshade_render::footage::FrameData;
use mrshade_scene::{Session, SessionOverrides};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Largest deviation of a frame's principal point from the image centre (as a share of the
/// image's size) and of its pixels from square that the path tracer's centred pinhole allows.
const CENTRED_TOLERANCE: f32 = 1e-3;

/// A sequence dataset, checked: its frames and the answers' size.
pub struct Plan {
    /// Per frame: its name and its photo, relative to the dataset folder.
    frames: Vec<(String, String)>,
    /// The answers' size, which every method renders at.
    width: u32,
    height: u32,
}

/// Whether `dir` may be a sequence dataset: its session.toml declares `[sequence]` (or
/// `--set` does). Still datasets are then left exactly as they were, unloaded until rendered.
pub fn declares_sequence(dir: &Path, args: &EvalArgs) -> bool {
    let text = std::fs::read_to_string(dir.join("session.toml")).unwrap_or_default();
    let in_file = text.lines().map(str::trim_start).any(|line| {
        line.starts_with("[sequence]")
            || line.strip_prefix("sequence").is_some_and(|rest| rest.trim_start().starts_with(['=', '.']))
    });
    in_file || args.set.iter().any(|s| s.trim_start().starts_with("sequence."))
}

/// Loads the session of `dir` and, when it is a `transforms` sequence, checks every frame up
/// front (before hours of rendering): its photo and its answer exist, all answers have one
/// size, and `reference` can render its cameras. `None`: a still dataset after all.
pub fn check(dir: &Path, methods: &[&str], args: &EvalArgs) -> Result<Option<Plan>> {
    let shown = dir.display();
    let overrides =
        SessionOverrides { set: args.set.clone(), allow_read: args.allow_read.clone(), ..Default::default() };
    let session = Session::load(&dir.join("session.toml"), &overrides).with_context(|| format!("dataset {shown}"))?;
    let Some(seq) = session.sequence.as_ref().filter(|s| s.from_transforms) else {
        return Ok(None);
    };
    let mut frames = Vec::with_capacity(seq.frames.len());
    let mut size = None;
    for frame in &seq.frames {
        let name = &frame.name;
        if !dir.join(&frame.file).is_file() {
            bail!("dataset {shown}: frame {name}: no photo {}", frame.file);
        }
        let answer = answer_path(dir, name);
        if !answer.is_file() {
            bail!(
                "dataset {shown}: frame {name}: no ground_truth/{name}.png (a sequence dataset holds one answer per \
                 frame, named like the frame's image)"
            );
        }
        let dims = image::image_dimensions(&answer)
            .with_context(|| format!("dataset {shown}: frame {name}: cannot read ground_truth/{name}.png"))?;
        match size {
            None => size = Some(dims),
            Some(first) if first != dims => bail!(
                "dataset {shown}: frame {name}: ground_truth/{name}.png is {}×{}, the first answer {}×{}",
                dims.0,
                dims.1,
                first.0,
                first.1
            ),
            Some(_) => {}
        }
        frames.push((name.clone(), frame.file.clone()));
    }
    if methods.contains(&"reference") {
        reference_fits(&session)
            .map_err(|why| anyhow::anyhow!("dataset {shown}: --method reference cannot render this sequence: {why}"))?;
    }
    let (width, height) = size.context("the sequence has no frame")?;
    Ok(Some(Plan { frames, width, height }))
}

/// The path tracer renders the session's own camera, a centred pinhole of square pixels, at
/// the rest pose: each frame's camera must be one, and nothing may move over time.
fn reference_fits(session: &Session) -> Result<(), String> {
    if session.scene.is_animated() {
        return Err("the scene is animated, and the path tracer renders its rest pose only".into());
    }
    for k in 0..session.frame_count() {
        let i = session.view_at(k).intrinsics;
        let off = |c: f32, side: u32| (c / side as f32 - 0.5).abs() > CENTRED_TOLERANCE;
        if off(i.cx, i.width) || off(i.cy, i.height) || (i.fl_x / i.fl_y - 1.0).abs() > CENTRED_TOLERANCE {
            return Err(format!(
                "frame {k}'s camera is off-centre or has non-square pixels (cx {}, cy {}, fl_x {}, fl_y {} for \
                 {}×{}), and the path tracer renders centred pinholes only",
                i.cx, i.cy, i.fl_x, i.fl_y, i.width, i.height
            ));
        }
    }
    Ok(())
}

fn answer_path(dir: &Path, name: &str) -> PathBuf {
    dir.join("ground_truth").join(format!("{name}.png"))
}

/// One frame's answer, photo (8-bit sRGB at the answer's size) and changed region.
struct Truth {
    answer: Rgb8,
    photo: Rgb8,
    region: Vec<bool>,
}

impl Truth {
    /// Reads frame `k`: the photo as its file's bytes when it is an 8-bit image of the
    /// answer's size (as the benchmark's scorer reads it), else as the renderer sees it.
    fn load(dir: &Path, plan: &Plan, session: &Session, k: usize, args: &EvalArgs) -> Result<Truth> {
        let (name, file) = &plan.frames[k];
        let answer = load_rgb8(&answer_path(dir, name), args.max_pixels)?;
        let eight_bit = [".png", ".jpg", ".jpeg"].iter().any(|e| file.to_lowercase().ends_with(e));
        let photo = match eight_bit.then(|| load_rgb8(&dir.join(file), args.max_pixels)).transpose()? {
            Some(p) if (p.width, p.height) == (answer.width, answer.height) => p,
            _ => to_rgb8(&session.photo_at(k)?),
        };
        let region = changed_region(&answer.rgb, &photo.rgb, answer.width, answer.height);
        Ok(Truth { answer, photo, region })
    }
}

/// Where a run's images go: `OUT/<sequence>/<method>/`, `None` without `--report`.
struct Images {
    folder: Option<PathBuf>,
    /// The folder relative to the report, for the report's paths.
    rel: String,
}

impl Images {
    fn new(args: &EvalArgs, scene: &str, method: &str) -> Result<Images> {
        let folder = args.report.as_ref().map(|out| out.join(scene).join(method));
        if let Some(f) = &folder {
            std::fs::create_dir_all(f).with_context(|| format!("cannot create {}", f.display()))?;
        }
        Ok(Images { folder, rel: format!("{scene}/{method}") })
    }

    /// Writes `img` as `name.png` (or `name_flip.png`); returns its path in the report.
    fn save(&self, file: &str, img: &Rgb8) -> Result<String> {
        let Some(folder) = &self.folder else { return Ok(String::new()) };
        let path = folder.join(file);
        image::save_buffer(&path, &img.rgb, img.width, img.height, image::ExtendedColorType::Rgb8)
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(format!("{}/{file}", self.rel))
    }
}

/// Scores `result` of frame `name` and writes it with its heat map.
fn score(truth: &Truth, result: &Rgb8, name: &str, images: &Images) -> Result<FrameScores> {
    let what = |e: String| anyhow::anyhow!("frame {name}: {e}");
    let comparison = compare(&truth.answer, result).map_err(what)?;
    let frame = comparison.scores(None).map_err(what)?;
    // A frame where the answer equals the photo (the virtual objects out of view) has no
    // region to score: null, left out of the means.
    let flip_region = match truth.region.contains(&true) {
        true => Some(comparison.scores(Some(&truth.region)).map_err(what)?.flip_heatmap_mean),
        false => None,
    };
    Ok(FrameScores {
        name: name.to_string(),
        flip_region,
        flip_frame: frame.flip_heatmap_mean,
        psnr_frame: frame.psnr.is_finite().then_some(frame.psnr),
        result: images.save(&format!("{name}.png"), result)?,
        heatmap: images.save(&format!("{name}_flip.png"), &comparison.heatmap)?,
    })
}

/// Runs every method on the sequence at `dir` and scores every frame.
pub fn eval_sequence(
    dir: &Path,
    scene: &str,
    plan: &Plan,
    methods: &[&str],
    args: &EvalArgs,
    ctx: Option<&GpuContext>,
    log: Log,
) -> Result<SequenceReport> {
    let n = plan.frames.len();
    // Answers, photos and regions are read again for each run rather than held: a long
    // sequence's would not fit in memory.
    let base = load(dir, "reference", args, plan.width, plan.height)?;
    let truth = |k: usize| Truth::load(dir, plan, &base, k, args);
    log.info(format!("{scene}: sequence of {n} frames at {}×{}", plan.width, plan.height));

    let (photos, answers) = (Images::new(args, scene, PHOTO)?, Images::new(args, scene, "answer")?);
    let mut scores = Vec::with_capacity(n);
    for (k, (name, _)) in plan.frames.iter().enumerate() {
        let t = truth(k)?;
        answers.save(&format!("{name}.png"), &t.answer)?;
        scores.push(score(&t, &t.photo, name, &photos)?);
    }
    let photo = MethodRun::new(PHOTO.into(), "do nothing".into(), 0.0, String::new(), scores, None);
    summary_line(scene, &photo, n, log);

    let mut runs = Vec::new();
    for method in methods {
        let session = load(dir, method, args, plan.width, plan.height)?;
        let run = |name: &str, setting: String, seconds: f64, device: String, frames| {
            MethodRun::new(name.into(), setting, seconds, device, frames, Some(&photo.frames))
        };
        if *method == "reference" {
            let (frames, seconds) = reference(&session, plan, scene, args, &truth, log)?;
            let setting = format!("{} spp per frame", session.settings.reference.spp);
            let device = format!("CPU, {} threads", rayon::current_num_threads());
            runs.push(run(method, setting, seconds, device, frames));
            summary_line(scene, &runs[runs.len() - 1], n, log);
            continue;
        }
        let ctx = ctx.context("no GPU context")?;
        let settle = session.output.frames / 2;
        log.info(format!("{scene}: {method}, played as footage (settling over {settle} frames first)"));
        let (frames, seconds) = play(ctx, &session, plan, scene, method, args, &truth, log)?;
        let samples = session.sequence.as_ref().map_or(1, |seq| seq.samples);
        let plural = |n: u32, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
        let setting = match settle {
            0 => format!("footage, {} per frame", plural(samples, "sample")),
            n => format!("footage, {} per frame, settles over {}", plural(samples, "sample"), plural(n, "frame")),
        };
        runs.push(run(method, setting, seconds, ctx.info.name.clone(), frames));
        summary_line(scene, &runs[runs.len() - 1], n, log);
        if args.stills {
            let per_still = session.output.frames;
            log.info(format!("{scene}: {method}, every frame as a still of {per_still} frames"));
            let name = format!("{method}-stills");
            let (frames, seconds) = stills(ctx, &session, plan, scene, &name, args, &truth, log)?;
            let setting = format!("{per_still} frame{} per still", if per_still == 1 { "" } else { "s" });
            runs.push(run(&name, setting, seconds, ctx.info.name.clone(), frames));
            summary_line(scene, &runs[runs.len() - 1], n, log);
        }
    }
    let report = SequenceReport::new(scene.to_string(), photo, runs);
    for bar in &report.quality_bars {
        log.info(bar.line(scene, n));
    }
    Ok(report)
}

/// Plays the whole sequence once; the frames' scores and the seconds spent rendering.
#[allow(clippy::too_many_arguments)]
fn play(
    ctx: &GpuContext,
    session: &Session,
    plan: &Plan,
    scene: &str,
    method: &str,
    args: &EvalArgs,
    truth: &dyn Fn(usize) -> Result<Truth>,
    log: Log,
) -> Result<(Vec<FrameScores>, f64)> {
    let images = Images::new(args, scene, method)?;
    let range = 0..plan.frames.len();
    let mut renderer = Renderer::new(ctx, session)?;
    for w in &renderer.warnings {
        log.warn(w);
    }
    // From frame 0 there is no warm-up: the frames played are the frames scored.
    let bar = log.progress(range.len() as u64, crate::cmd::STILL_BAR)?;
    let started = Instant::now();
    let mut scoring = Duration::ZERO;
    let mut frames = Vec::with_capacity(range.len());
    renderer.play(
        ctx,
        session,
        range,
        |i| bar.set_position(i as u64),
        |_, data: &FrameData, composite| {
            let t0 = Instant::now();
            let t = truth(data.index)?;
            frames.push(score(&t, &to_rgb8(&composite.image), &data.name, &images)?);
            scoring += t0.elapsed();
            Ok(())
        },
    )?;
    bar.finish_and_clear();
    Ok((frames, (started.elapsed() - scoring).as_secs_f64()))
}

/// Every frame alone as a converged still, each by a fresh renderer: no history carries over
/// from one frame to the next.
#[allow(clippy::too_many_arguments)]
fn stills(
    ctx: &GpuContext,
    session: &Session,
    plan: &Plan,
    scene: &str,
    name: &str,
    args: &EvalArgs,
    truth: &dyn Fn(usize) -> Result<Truth>,
    log: Log,
) -> Result<(Vec<FrameScores>, f64)> {
    let images = Images::new(args, scene, name)?;
    let per_still = session.output.frames;
    let bar = log.progress((plan.frames.len() * per_still as usize) as u64, crate::cmd::STILL_BAR)?;
    let mut seconds = 0.0;
    let mut frames = Vec::with_capacity(plan.frames.len());
    for k in 0..plan.frames.len() {
        let data = FrameData::load(session, k)?;
        let started = Instant::now();
        let mut renderer = Renderer::for_still(ctx, session)?;
        let done = k as u64 * per_still as u64;
        let composite =
            renderer.render_still_of(ctx, per_still, &data.inputs(), |i| bar.set_position(done + i as u64))?;
        seconds += started.elapsed().as_secs_f64();
        frames.push(score(&truth(k)?, &to_rgb8(&composite.image), &data.name, &images)?);
    }
    bar.finish_and_clear();
    Ok((frames, seconds))
}

/// Every frame with the CPU path tracer, its camera and photo put in the session's place
/// ([`reference_fits`] checked that they fit).
fn reference(
    session: &Session,
    plan: &Plan,
    scene: &str,
    args: &EvalArgs,
    truth: &dyn Fn(usize) -> Result<Truth>,
    log: Log,
) -> Result<(Vec<FrameScores>, f64)> {
    let images = Images::new(args, scene, "reference")?;
    let mut framed = session.clone();
    let (mut frames, mut seconds) = (Vec::with_capacity(plan.frames.len()), 0.0);
    for (k, (name, _)) in plan.frames.iter().enumerate() {
        log.info(format!("{scene}: reference, frame {name} ({}/{})", k + 1, plan.frames.len()));
        let view = session.view_at(k);
        let camera = &mut framed.scene.cameras[framed.camera];
        camera.world_from_camera = view.world_from_camera;
        camera.yfov = view.intrinsics.yfov();
        framed.background = session.photo_at(k)?;
        let (image, s) = render_reference(&framed, log)?;
        seconds += s;
        frames.push(score(&truth(k)?, &to_rgb8(&image.composite), name, &images)?);
    }
    Ok((frames, seconds))
}

/// The log's line of a run.
fn summary_line(scene: &str, run: &MethodRun, frames: usize, log: Log) {
    let s = &run.summary;
    let f = |v: Option<f64>| v.map_or("—".into(), |v| format!("{v:.4}"));
    let beats = s.beats_photo.map(|b| format!("; beats the photo on {b}/{frames} frames")).unwrap_or_default();
    log.info(format!(
        "{scene} {}: FLIP region {} (frames 4..: {}), frame {:.4}, PSNR {} dB; worst frame {} ({}){beats} ({:.1} s)",
        run.method,
        f(s.flip_region),
        f(s.flip_region_from4),
        s.flip_frame,
        s.psnr_frame.map_or("—".into(), |p| format!("{p:.2}")),
        s.worst_frame.as_deref().unwrap_or("—"),
        f(s.worst_flip_region),
        run.seconds
    ));
}
