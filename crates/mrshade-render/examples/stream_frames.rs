//! The stream library on its own: a few synthetic frames composited one at a time, as
//! `mrshade stream` does with frames from a pipe, the last written as a PNG.
//!
//! ```sh
//! cargo run --release -p mrshade-render --example stream_frames -- [SESSION] [OUT.png]
//! ```
//! The session defaults to `assets/sequence/desk-orbit-mini` (80×60), the output to
//! `stream_frames.png`. Each frame is the session's photo, a little brighter than the last,
//! seen from a camera turned a little further about the vertical axis (as a tracker would
//! report it), at 15 frames per second.

use anyhow::{Context, Result};
use glam::Mat4;
use mrshade_gpu::{GpuContext, GpuOptions};
use mrshade_render::stream::{Stream, StreamFrame};
use mrshade_scene::{Session, SessionOverrides};
use std::path::PathBuf;

/// Frames composited.
const FRAMES: u32 = 4;
/// Frames per second of the synthetic source.
const FPS: f32 = 15.0;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let session_path = args.next().map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/sequence/desk-orbit-mini/session.toml"))
    });
    let out = args.next().map_or_else(|| PathBuf::from("stream_frames.png"), PathBuf::from);

    let session = Session::load(&session_path, &SessionOverrides::default())?;
    let photo = session.background.to_srgb8();
    let camera = session.view_at(0).world_from_camera;
    let ctx = GpuContext::new(&GpuOptions::default())?;
    eprintln!("adapter: {}", ctx.describe());
    let mut stream = Stream::new(&ctx, session)?;
    let (width, height) = stream.size();

    let mut last = Vec::new();
    for k in 0..FRAMES {
        // A synthetic frame: the photo, brighter by 5 % a frame.
        let gain = 1.0 + 0.05 * k as f32;
        let rgb: Vec<u8> = photo.iter().map(|&c| (c as f32 * gain).min(255.0) as u8).collect();
        // The camera turned by half a degree a frame about its own vertical axis.
        let turned = camera * Mat4::from_rotation_y((0.5 * k as f32).to_radians());
        let frame = StreamFrame { world_from_camera: Some(turned), ..StreamFrame::photo(&rgb, k as f32 / FPS) };
        let started = std::time::Instant::now();
        let composited = stream.composite(&ctx, &frame)?;
        eprintln!(
            "frame {k}: {:.1} ms{}",
            started.elapsed().as_secs_f64() * 1e3,
            composited.gpu_ms.map(|ms| format!(" ({ms:.1} ms on the GPU)")).unwrap_or_default()
        );
        last = composited.rgb;
    }
    let png = mrshade_scene::images::encode_png_rgb8(width, height, last)?;
    std::fs::write(&out, png).with_context(|| format!("cannot write {}", out.display()))?;
    eprintln!("wrote {} ({width}×{height})", out.display());
    Ok(())
}
