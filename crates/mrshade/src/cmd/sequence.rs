//! `mrshade render` of a sequence session: one composite per frame into a folder, a range of
//! frames (`--frames A..B`, for sharding), one frame as a converged still (`--frame K`), and a
//! video through ffmpeg (`--video`).

use super::Log;
use crate::args::RenderArgs;
use crate::output;
use anyhow::{Context, Result, bail};
use mrshade_gpu::GpuContext;
use mrshade_render::Renderer;
use mrshade_render::footage::{FrameData, playback_length};
use mrshade_scene::Session;
use std::io::Write;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

/// Progress of footage: frames and their rate.
const FOOTAGE_BAR: &str = "{bar:40} {pos}/{len} frames {per_sec} {elapsed}";

/// Renders the frames `args` asks for.
pub fn render_sequence(session: &Session, args: &RenderArgs, ctx: &GpuContext, log: Log) -> Result<()> {
    let count = session.frame_count();
    if let Some(k) = args.frame {
        return render_one(session, args, ctx, k, log);
    }
    let range = match &args.frames {
        Some(text) => parse_range(text, count)?,
        None => 0..count,
    };
    let folder = args.output.as_deref();
    if let Some(dir) = folder {
        check_folder(dir)?;
    }
    let mut video = args.video.as_deref().map(|path| Video::start(path, session)).transpose()?;
    let mut renderer = Renderer::new(ctx, session)?;
    for w in &renderer.warnings {
        log.warn(w);
    }
    let (w, h) = renderer.output_size();
    log.info(format!(
        "rendering frames {}..{} of {count} at {w}×{h} (method {}, footage at {} fps)",
        range.start,
        range.end,
        session.settings.method.name(),
        fps(session)
    ));
    let bar = log.progress(playback_length(&range, args.warmup) as u64, FOOTAGE_BAR)?;
    let started = std::time::Instant::now();
    renderer.play_with_warmup(
        ctx,
        session,
        range.clone(),
        args.warmup,
        |i| bar.set_position(i as u64),
        |renderer: &Renderer, data: &FrameData, composite| {
            if let Some(dir) = folder {
                output::write_image(&dir.join(format!("{}.{}", data.name, args.format)), &composite.image)?;
            }
            if let Some(video) = &mut video {
                video.push(&composite.image)?;
            }
            if let Some(aov_dir) = &args.aov_dir {
                let aovs = renderer.read_aovs(ctx)?;
                output::write_aovs(&aov_dir.join(&data.name), &aovs, &data.photo, &composite.image)?;
            }
            Ok(())
        },
    )?;
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    log.info(format!(
        "rendered {} frames in {seconds:.1} s ({:.1} frames/s){}",
        range.len(),
        range.len() as f64 / seconds.max(1e-9),
        folder.map(|d| format!(", wrote {}", d.display())).unwrap_or_default()
    ));
    if let Some(video) = video {
        let path = video.finish()?;
        log.info(format!("wrote {}", path.display()));
    }
    Ok(())
}

/// Frames per second of the footage.
fn fps(session: &Session) -> f32 {
    session.sequence.as_ref().map_or(mrshade_scene::sequence::DEFAULT_FPS, |s| s.fps)
}

/// Frame `k` alone, converged as a still.
fn render_one(session: &Session, args: &RenderArgs, ctx: &GpuContext, k: usize, log: Log) -> Result<()> {
    let count = session.frame_count();
    if k >= count {
        bail!("--frame {k}: the sequence has {count} frames (0..{count})");
    }
    let out = args.output.as_deref().context("--frame needs -o OUT (an image file)")?;
    output::check_extension(out)?;
    let data = FrameData::load(session, k)?;
    let mut renderer = Renderer::for_still(ctx, session)?;
    for w in &renderer.warnings {
        log.warn(w);
    }
    let frames = session.output.frames;
    let bar = log.progress(frames as u64, crate::cmd::STILL_BAR)?;
    let composite = renderer.render_still_of(ctx, frames, &data.inputs(), |i| bar.set_position(i as u64))?;
    bar.finish_and_clear();
    output::write_image(out, &composite.image)?;
    log.info(format!("wrote frame {} to {}", data.name, out.display()));
    if let Some(dir) = &args.aov_dir {
        let aovs = renderer.read_aovs(ctx)?;
        output::write_aovs(dir, &aovs, &data.photo, &composite.image)?;
    }
    Ok(())
}

/// `A..B` (B excluded), `A..=B` (included) or `A..` (to the end), within `0..count`.
pub fn parse_range(text: &str, count: usize) -> Result<Range<usize>> {
    let bad = || format!("--frames {text}: expected A..B (B excluded), A..=B or A.., e.g. 0..24");
    let (a, b, inclusive) = if let Some((a, b)) = text.split_once("..=") {
        (a, b, true)
    } else if let Some((a, b)) = text.split_once("..") {
        (a, b, false)
    } else {
        bail!(bad());
    };
    let a: usize = a.trim().parse().with_context(bad)?;
    let b = match b.trim() {
        "" if !inclusive => count,
        b => b.parse::<usize>().with_context(bad)? + inclusive as usize,
    };
    if a >= b {
        bail!("--frames {text}: the range is empty");
    }
    if b > count {
        bail!("--frames {text}: the sequence has {count} frames (0..{count})");
    }
    Ok(a..b)
}

/// A sequence writes into a folder, not onto an image file.
fn check_folder(dir: &Path) -> Result<()> {
    let image_name =
        dir.extension().is_some_and(|e| ["png", "exr", "jpg", "jpeg"].contains(&&*e.to_string_lossy().to_lowercase()));
    if dir.is_file() || image_name {
        bail!(
            "-o {}: a sequence session renders one image per frame into a folder (-o OUT_DIR/), or one frame with \
             --frame K -o OUT.png",
            dir.display()
        );
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))
}

/// Frames piped into ffmpeg as raw RGB.
struct Video {
    child: Child,
    stdin: Option<ChildStdin>,
    path: PathBuf,
}

impl Video {
    fn start(path: &Path, session: &Session) -> Result<Self> {
        let (w, h) = (session.output.width, session.output.height);
        let spawned = Command::new("ffmpeg")
            .args(["-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24"])
            .args(["-s", &format!("{w}x{h}"), "-r", &fps(session).to_string(), "-i", "-"])
            .args(["-c:v", "libx264", "-pix_fmt", "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .spawn();
        let mut child = match spawned {
            Ok(c) => c,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => bail!(
                "--video needs ffmpeg, which is not installed (Debian/Ubuntu: sudo apt install ffmpeg; Fedora: sudo \
                 dnf install ffmpeg; macOS: brew install ffmpeg); or render the frames with -o OUT_DIR/ and encode \
                 them yourself"
            ),
            Err(e) => return Err(e).context("cannot start ffmpeg"),
        };
        let stdin = child.stdin.take();
        Ok(Self { child, stdin, path: path.to_path_buf() })
    }

    fn push(&mut self, image: &mrshade_core::HdrImage) -> Result<()> {
        let stdin = self.stdin.as_mut().context("ffmpeg's input is closed")?;
        stdin.write_all(&image.to_srgb8()).context("ffmpeg stopped reading frames (see its message above)")
    }

    fn finish(mut self) -> Result<PathBuf> {
        drop(self.stdin.take());
        let status = self.child.wait().context("waiting for ffmpeg")?;
        if !status.success() {
            bail!("ffmpeg failed ({status}) writing {}", self.path.display());
        }
        Ok(self.path)
    }
}

#[cfg(test)]
mod tests {
    use super::parse_range;

    #[test]
    fn ranges_parse_strictly() {
        assert_eq!(parse_range("2..5", 10).unwrap(), 2..5);
        assert_eq!(parse_range("2..=5", 10).unwrap(), 2..6);
        assert_eq!(parse_range("7..", 10).unwrap(), 7..10);
        for bad in ["5", "a..3", "5..2", "3..3", "0..11", "-1..3", "2..="] {
            assert!(parse_range(bad, 10).is_err(), "{bad}");
        }
    }
}
