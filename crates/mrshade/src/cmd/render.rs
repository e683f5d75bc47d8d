//! `mrshade render` and `mrshade demo`.

use super::{Log, load_session, open_gpu};
use crate::args::{DemoArgs, RenderArgs};
use crate::{demo_assets, output};
use anyhow::{Context, Result, bail};
use mrshade_gpu::{GpuContext, GpuOptions};
use mrshade_render::{Composite, Renderer};
use mrshade_scene::{Session, SessionOverrides};
use std::path::Path;
use std::time::Instant;

/// Renders a session file.
pub fn render(args: &RenderArgs, gpu: &GpuOptions, log: Log) -> Result<()> {
    let session = load_session(&args.session, log)?;
    if session.sequence.is_some() {
        let ctx = open_gpu(gpu, log)?;
        return super::sequence::render_sequence(&session, args, &ctx, log);
    }
    for (flag, given) in
        [("--frame", args.frame.is_some()), ("--frames", args.frames.is_some()), ("--video", args.video.is_some())]
    {
        if given {
            bail!(
                "{flag}: {} is a still session (one photo); {flag} is for sequence sessions ([sequence] in the session)",
                session.origin
            );
        }
    }
    let out = args.output.as_deref().context("-o OUT is required")?;
    output::check_extension(out)?;
    render_session(&session, out, args.aov_dir.as_deref(), gpu, log)
}

/// Renders the embedded demo session.
pub fn demo(args: &DemoArgs, gpu: &GpuOptions, log: Log) -> Result<()> {
    output::check_extension(&args.output)?;
    log.info("loading the built-in demo session (desk-spot-real: real desk lamp, virtual torus and cube)");
    let overrides = SessionOverrides { width: args.width, height: args.height, ..Default::default() };
    let session = Session::load_from(&demo_assets::source(), demo_assets::SESSION, &overrides)?;
    for w in &session.warnings {
        log.warn(w);
    }
    render_session(&session, &args.output, args.aov_dir.as_deref(), gpu, log)
}

fn render_session(session: &Session, out: &Path, aov_dir: Option<&Path>, gpu: &GpuOptions, log: Log) -> Result<()> {
    let ctx = open_gpu(gpu, log)?;
    let started = Instant::now();
    let mut renderer = Renderer::for_still(&ctx, session)?;
    for w in &renderer.warnings {
        log.warn(w);
    }
    let (w, h) = renderer.output_size();
    log.info(format!(
        "rendering {w}×{h} (method {}, {} composite, supersample {}, {} frame{})",
        session.settings.method.name(),
        session.settings.composite.mode.name(),
        session.output.supersample,
        session.output.frames,
        if session.output.frames == 1 { "" } else { "s" }
    ));
    let composite = render_still(&mut renderer, &ctx, session.output.frames, log)?;
    output::write_image(out, &composite.image)?;
    log.info(format!("wrote {} ({:.2} s)", out.display(), started.elapsed().as_secs_f64()));
    if let Some(dir) = aov_dir {
        let aovs = renderer.read_aovs(&ctx)?;
        output::write_aovs(dir, &aovs, &session.background, &composite.image)?;
        log.info(format!("wrote {} AOVs to {}", aovs.len() + 1, dir.display()));
    }
    Ok(())
}

/// A still of `frames` frames, with a progress bar.
pub fn render_still(renderer: &mut Renderer, ctx: &GpuContext, frames: u32, log: Log) -> Result<Composite> {
    let bar = log.progress(frames as u64, crate::cmd::STILL_BAR)?;
    if frames == 1 {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let composite = renderer.render_still(ctx, frames, |i| bar.set_position(i as u64))?;
    bar.finish_and_clear();
    Ok(composite)
}
