//! `mrshade reference`: the CPU differential path tracer.

use super::{Log, load_session};
use crate::args::ReferenceArgs;
use crate::output;
use anyhow::Result;
use mrshade_core::HdrImage;
use mrshade_reference::ReferenceImage;
use mrshade_scene::Session;
use std::path::Path;
use std::time::Instant;

/// Renders a session with the reference path tracer.
pub fn reference(args: &ReferenceArgs, log: Log) -> Result<()> {
    output::check_extension(&args.output)?;
    let mut session_args = args.session.clone();
    session_args.set.extend(args.spp.map(|n| format!("reference.spp={n}")));
    session_args.set.extend(args.seed.map(|n| format!("reference.seed={n}")));
    let session = load_session(&session_args, log)?;
    let (image, seconds) = render_reference(&session, log)?;
    output::write_image(&args.output, &image.composite)?;
    log.info(format!("wrote {} ({seconds:.1} s)", args.output.display()));
    if let Some(dir) = &args.aov_dir {
        write_aovs(dir, &session, &image)?;
        log.info(format!("wrote 5 AOVs to {}", dir.display()));
    }
    Ok(())
}

/// Renders with a progress bar; returns the image and the seconds it took.
pub fn render_reference(session: &Session, log: Log) -> Result<(ReferenceImage, f64)> {
    let s = session.settings.reference;
    log.info(format!(
        "path tracing {}×{} at {} spp, up to {} bounces, on {} threads",
        session.output.width,
        session.output.height,
        s.spp,
        s.max_bounces,
        rayon::current_num_threads()
    ));
    for w in mrshade_reference::warnings(&session.scene) {
        log.warn(w);
    }
    let bar = log.progress(session.output.height as u64, "{bar:40} {pos}/{len} rows {elapsed} (eta {eta})")?;
    let started = Instant::now();
    let image = mrshade_reference::render(session, &|done, _| bar.set_position(done as u64));
    bar.finish_and_clear();
    // Never a silent black image: NaN is written as black.
    if let Some((count, (x, y))) = image.composite.non_finite() {
        anyhow::bail!(
            "the path-traced composite holds {count} NaN or infinite pixel(s), the first at ({x}, {y}) (a bug in \
             mrshade, please report it with the session)"
        );
    }
    Ok((image, started.elapsed().as_secs_f64()))
}

fn write_aovs(dir: &Path, session: &Session, image: &ReferenceImage) -> Result<()> {
    output::write_image(&dir.join("l_rv.exr"), &image.l_rv)?;
    output::write_image(&dir.join("l_r.exr"), &image.l_r)?;
    output::write_image(&dir.join("alpha.exr"), &image.alpha)?;
    let mask = HdrImage {
        width: image.composite.width,
        height: image.composite.height,
        pixels: image.coverage.iter().map(|&c| [c; 3]).collect(),
    };
    output::write_image(&dir.join("virtual_mask.png"), &mask)?;
    let both = output::side_by_side(&session.background, &image.composite);
    output::write_image(&dir.join("side_by_side.png"), &both)
}
