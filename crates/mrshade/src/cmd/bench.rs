//! `mrshade bench`: GPU milliseconds per pass and per frame from timestamp queries, for a
//! still camera or a sequence played frame by frame (new photo, pose and transforms each).

use super::{Log, load_session, open_gpu};
use crate::args::BenchArgs;
use anyhow::{Context, Result, bail};
use mrshade_gpu::GpuOptions;
use mrshade_gpu::timing::{flatten, profiler};
use mrshade_render::footage::FrameData;
use mrshade_render::{FrameInputs, Renderer};
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Serialize)]
struct Stats {
    mean_ms: f64,
    p95_ms: f64,
    min_ms: f64,
    max_ms: f64,
}

impl Stats {
    fn of(samples: &[f64]) -> Self {
        let mut s = samples.to_vec();
        s.sort_by(f64::total_cmp);
        let pick = |q: f64| super::quantile(&s, q);
        Stats {
            mean_ms: s.iter().sum::<f64>() / s.len() as f64,
            p95_ms: pick(0.95),
            min_ms: s[0],
            max_ms: s[s.len() - 1],
        }
    }
}

#[derive(Serialize)]
struct Report {
    session: String,
    method: String,
    adapter: String,
    backend: String,
    device_type: String,
    driver: String,
    width: u32,
    height: u32,
    supersample: u32,
    frames: u32,
    warmup: u32,
    /// From the first pass's start to the last pass's end, on the GPU's clock.
    frame: Stats,
    /// Per pass label (several passes with one label, e.g. shadow layers, are summed per frame).
    passes: BTreeMap<String, Stats>,
    /// Per pass label: GPU time between the end of everything recorded before it and its start
    /// (barriers, buffer clears and copies between passes, the GPU draining and refilling).
    gaps_before: BTreeMap<String, Stats>,
    /// Pass labels in frame order.
    pass_order: Vec<String>,
    /// Frames of the sequence played (0: a still camera).
    sequence_frames: u32,
    /// Bytes of photo uploaded per frame (a texture write before the frame's passes).
    upload_bytes: u64,
    /// CPU time per frame to upload the inputs and record and submit the commands.
    cpu_submit: Stats,
    /// Frames per second end to end (CPU, upload, GPU, waiting for each frame), warm-up included.
    wall_fps: f64,
}

/// Runs the benchmark.
pub fn bench(args: &BenchArgs, gpu: &GpuOptions, log: Log) -> Result<()> {
    if args.frames == 0 {
        bail!("--frames must be at least 1");
    }
    // Speed is measured at the requested size whatever the photo's aspect ratio.
    let mut session_args = args.session.clone();
    session_args.stretch_photo = true;
    let session = load_session(&session_args, log)?;
    let ctx = open_gpu(gpu, log)?;
    if !ctx.timestamps {
        bail!("adapter {} does not support timestamp queries, which bench needs", ctx.info.name);
    }
    let mut renderer = Renderer::new(&ctx, &session)?;
    renderer.serial_passes = args.serial;
    for w in &renderer.warnings {
        log.warn(w);
    }
    let mut profiler = profiler(&ctx, true)?;
    let (w, h) = renderer.output_size();
    // A sequence plays: a new photo, camera pose and animated transforms every frame (loaded
    // and resized before timing, looping over the sequence's frames).
    let footage: Vec<FrameData> = match &session.sequence {
        Some(seq) => {
            log.info(format!("loading the sequence's {} frames", seq.frames.len()));
            (0..seq.frames.len()).map(|k| FrameData::load(&session, k)).collect::<Result<_>>()?
        }
        None => Vec::new(),
    };
    let still = FrameInputs::camera(renderer.session_camera());
    // --moving: the first virtual instance and its rest transform; every instance's transform.
    let mut placed: Vec<glam::Mat4> = session.scene.instances.iter().map(|i| i.world_from_object).collect();
    let moving = if args.moving {
        let k = session.scene.instances.iter().position(|i| i.realness == mrshade_core::flags::Realness::Virtual);
        Some(k.map(|k| (k, placed[k])).ok_or_else(|| anyhow::anyhow!("--moving: the scene has no virtual object"))?)
    } else {
        None
    };
    log.info(format!(
        "bench {w}×{h}, {} warm-up + {} measured frames{}",
        args.warmup,
        args.frames,
        if footage.is_empty() { String::new() } else { format!(", playing {} sequence frames", footage.len()) }
    ));

    let total = (args.warmup + args.frames) as u64;
    let bar = log.progress(total, crate::cmd::STILL_BAR)?;
    let mut frames: Vec<Vec<(String, f64, f64)>> = Vec::new();
    let mut submit_ms = Vec::new();
    let mut previous = None;
    let mut processed = 0;
    let started = std::time::Instant::now();
    for i in 0..total {
        let mut inputs = if footage.is_empty() { still } else { footage[i as usize % footage.len()].inputs() };
        if let Some((k, rest)) = moving {
            // Back and forth by 0.01 rad about the object's own vertical axis.
            let turn = if i % 2 == 0 { 0.01 } else { -0.01 };
            placed[k] = rest * glam::Mat4::from_rotation_y(turn);
            inputs.instances = Some(&placed);
        }
        let submit = std::time::Instant::now();
        let submitted = renderer.render(&ctx, &mut profiler, &inputs)?;
        if i >= args.warmup as u64 {
            submit_ms.push(submit.elapsed().as_secs_f64() * 1e3);
        }
        profiler.end_frame().map_err(|e| anyhow::anyhow!("profiler: {e}"))?;
        // One frame in flight, as a live renderer runs: the next frame's inputs are uploaded
        // and its commands recorded while the GPU draws this one.
        if let Some(before) = previous.replace(submitted) {
            ctx.wait_for(before)?;
        }
        while let Some(results) = profiler.process_finished_frame(ctx.queue.get_timestamp_period()) {
            if processed >= args.warmup {
                frames.push(flatten(&results));
            }
            processed += 1;
        }
        bar.inc(1);
    }
    ctx.wait_idle()?;
    while let Some(results) = profiler.process_finished_frame(ctx.queue.get_timestamp_period()) {
        if processed >= args.warmup {
            frames.push(flatten(&results));
        }
        processed += 1;
    }
    bar.finish_and_clear();
    let wall_fps = total as f64 / started.elapsed().as_secs_f64();
    if frames.is_empty() {
        bail!("no timestamp results came back from the GPU");
    }

    let mut pass_order: Vec<String> = Vec::new();
    let mut per_pass: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let mut per_gap: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let mut frame_ms = Vec::new();
    for f in &frames {
        let mut gaps: BTreeMap<&str, f64> = BTreeMap::new();
        let mut ordered: Vec<&(String, f64, f64)> = f.iter().collect();
        ordered.sort_by(|a, b| a.1.total_cmp(&b.1));
        let mut busy_until = ordered.first().map_or(0.0, |p| p.1);
        for (label, s, e) in ordered {
            *gaps.entry(label).or_default() += (s - busy_until).max(0.0) * 1e3;
            busy_until = busy_until.max(*e);
        }
        for (label, ms) in gaps {
            per_gap.entry(label.to_string()).or_default().push(ms);
        }
        frame_ms.extend(mrshade_gpu::timing::frame_ms(f));
        let mut sums: BTreeMap<&str, f64> = BTreeMap::new();
        for (label, s, e) in f {
            if !pass_order.contains(label) {
                pass_order.push(label.clone());
            }
            *sums.entry(label).or_default() += (e - s) * 1e3;
        }
        for (label, ms) in sums {
            per_pass.entry(label.to_string()).or_default().push(ms);
        }
    }
    let report = Report {
        session: session.origin.clone(),
        method: session.settings.method.name().into(),
        adapter: ctx.info.name.clone(),
        backend: format!("{:?}", ctx.info.backend),
        device_type: format!("{:?}", ctx.info.device_type),
        driver: format!("{} {}", ctx.info.driver, ctx.info.driver_info),
        width: w,
        height: h,
        supersample: session.output.supersample,
        frames: frames.len() as u32,
        warmup: args.warmup,
        frame: Stats::of(&frame_ms),
        passes: per_pass.iter().map(|(k, v)| (k.clone(), Stats::of(v))).collect(),
        gaps_before: per_gap.iter().map(|(k, v)| (k.clone(), Stats::of(v))).collect(),
        pass_order,
        sequence_frames: footage.len() as u32,
        upload_bytes: if footage.is_empty() { 0 } else { renderer.photo_upload_bytes() },
        cpu_submit: Stats::of(&submit_ms),
        wall_fps,
    };
    print_report(&report);
    if let Some(path) = &args.json {
        std::fs::write(path, serde_json::to_string_pretty(&report)?)
            .with_context(|| format!("cannot write {}", path.display()))?;
        log.info(format!("wrote {}", path.display()));
    }
    Ok(())
}

fn print_report(r: &Report) {
    println!("{} on {} ({}), {}×{}, {} frames", r.method, r.adapter, r.backend, r.width, r.height, r.frames);
    println!("{:<12} {:>10} {:>10} {:>10}", "pass", "mean ms", "p95 ms", "gap ms");
    for label in &r.pass_order {
        let s = &r.passes[label];
        let gap = r.gaps_before.get(label).map_or(0.0, |g| g.mean_ms);
        println!("{label:<12} {:>10.3} {:>10.3} {gap:>10.3}", s.mean_ms, s.p95_ms);
    }
    println!("{:<12} {:>10.3} {:>10.3}", "frame", r.frame.mean_ms, r.frame.p95_ms);
    if r.sequence_frames > 0 {
        println!(
            "played {} sequence frames: {:.1} MiB photo upload per frame, CPU upload + submit {:.3} ms, {:.0} frames/s \
             end to end",
            r.sequence_frames,
            r.upload_bytes as f64 / (1 << 20) as f64,
            r.cpu_submit.mean_ms,
            r.wall_fps
        );
    }
}
