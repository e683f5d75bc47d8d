//! `mrshade render` and `mrshade demo`.

use super::{Log, load_session, open_gpu};
use crate::args::{DemoArgs, RenderArgs};
use crate::{demo_assets, output};
use anyhow::Result;
use mrshade_gpu::GpuOptions;
use mrshade_render::Renderer;
use mrshade_scene::{Session, SessionOverrides};
use std::path::Path;
use std::time::Instant;

/// Renders a session file.
pub fn render(args: &RenderArgs, gpu: &GpuOptions, log: Log) -> Result<()> {
    output::check_extension(&args.output)?;
    let session = load_session(&args.session, log)?;
    render_session(&session, &args.output, args.aov_dir.as_deref(), gpu, log)
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
    let mut renderer = Renderer::new(&ctx, session)?;
    let (w, h) = renderer.output_size();
    log.info(format!(
        "rendering {w}×{h} (method {}, {} composite, supersample {})",
        session.settings.method.name(),
        session.settings.composite.mode.name(),
        session.output.supersample
    ));
    renderer.render_once(&ctx)?;
    let composite = renderer.read_composite(&ctx)?;
    output::write_image(out, &composite.image)?;
    log.info(format!("wrote {} ({:.2} s)", out.display(), started.elapsed().as_secs_f64()));
    if let Some(dir) = aov_dir {
        let aovs = renderer.read_aovs(&ctx)?;
        output::write_aovs(dir, &aovs, &session.background, &composite.image)?;
        log.info(format!("wrote {} AOVs to {}", aovs.len() + 1, dir.display()));
    }
    Ok(())
}
