//! `mrshade stream`: raw RGB frames from stdin, composited one renderer frame each
//! ([`mrshade_render::stream`]), to stdout; nothing else goes to stdout. Three threads: the
//! reader, the GPU loop and the writer (`pipes`), and a fourth for `--poses` (`poses`).
//! docs/stream.md has the ffmpeg recipes.

mod pipes;
mod poses;

use super::{Log, load_session, open_gpu, quantile};
use crate::args::StreamArgs;
use anyhow::{Context, Result, bail};
use mrshade_gpu::{GpuContext, GpuOptions};
use mrshade_render::stream::{Stream, StreamFrame};
use mrshade_scene::sequence::{DEFAULT_FPS, MAX_FPS};
use mrshade_scene::session::{MAX_OUTPUT_SIDE, MIN_OUTPUT_SIDE};
use pipes::{End, Frame, Reader, Writer};
use poses::Poses;
use std::collections::HashSet;
use std::time::{Duration, Instant};

/// Shortest time between two warnings about late frames.
const LATE_WARNING_EVERY: Duration = Duration::from_secs(1);

/// Runs the stream until stdin ends.
pub fn stream(args: &StreamArgs, gpu: &GpuOptions, log: Log) -> Result<()> {
    let (width, height) = parse_size(&args.size)?;
    if args.session.width.is_some() || args.session.height.is_some() {
        bail!("--width/--height: mrshade stream takes the frame size as --size WxH");
    }
    if let Some(fps) = args.fps
        && !(fps > 0.0 && fps <= MAX_FPS)
    {
        bail!("--fps {fps}: must be above 0 and at most {MAX_FPS}");
    }
    if let Some(path) = &args.poses {
        poses::check_path(path)?;
    }
    let mut session_args = args.session.clone();
    (session_args.width, session_args.height, session_args.stretch_photo) = (Some(width), Some(height), args.stretch);
    let session = load_session(&session_args, log).map_err(|e| {
        // The one error of the session's that --size alone causes: say how to accept it.
        match !args.stretch && format!("{e:#}").contains("aspect ratio") {
            true => e.context(format!("--size {} (frames of another aspect ratio need --stretch)", args.size)),
            false => e,
        }
    })?;
    let fps = args.fps.or(session.sequence.as_ref().map(|s| s.fps)).unwrap_or(DEFAULT_FPS);
    let method = session.settings.method.name();
    let ctx = open_gpu(gpu, log)?;
    let mut stream = Stream::new(&ctx, session)?;
    for w in stream.warnings() {
        log.warn(w);
    }
    if stream.size() != (width, height) {
        bail!("the renderer's output is {:?}, not the --size {width}×{height} asked for", stream.size());
    }
    stream.settle(args.settle);
    log.info(format!(
        "streaming {width}×{height} RGB frames ({} bytes each) at {fps} frames/s from stdin to stdout (method {method}, \
         {})",
        stream.frame_bytes(),
        if args.drop_late { "late frames dropped" } else { "every frame kept" }
    ));
    let reader = Reader::start(std::io::stdin(), stream.frame_bytes(), args.drop_late);
    let writer = Writer::start(std::io::stdout());
    let poses = args.poses.clone().map(|path| Poses::start(path, (width, height), log));
    let mut run = Run::new(fps, log, args.drop_late);
    let rendered = run.frames(&ctx, &mut stream, &reader, &writer, poses);
    let latencies = match writer.finish() {
        Ok(latencies) => latencies,
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(crate::BROKEN_PIPE_EXIT),
        Err(e) => return Err(e).context("stdout"),
    };
    rendered?;
    let (read, dropped) = reader.counts();
    log.info(run.summary(read, dropped, latencies));
    match reader.end() {
        Some(End::Truncated { index, got }) => {
            bail!("stdin: truncated frame {index}: got {got} of {} bytes", stream.frame_bytes())
        }
        Some(End::Failed(e)) => Err(e).context("stdin"),
        Some(End::Clean) | None => Ok(()),
    }
}

/// `W×H` (`x`, `X` or `×`), each side within the output limits.
fn parse_size(text: &str) -> Result<(u32, u32)> {
    let bad = || format!("--size {text}: expected WIDTHxHEIGHT in pixels, e.g. 640x480");
    let (w, h) = text.split_once(['x', 'X', '×']).with_context(bad)?;
    let (w, h): (u32, u32) = (w.trim().parse().with_context(bad)?, h.trim().parse().with_context(bad)?);
    for (name, v) in [("width", w), ("height", h)] {
        if !(MIN_OUTPUT_SIDE..=MAX_OUTPUT_SIDE).contains(&v) {
            bail!("--size {text}: the {name} must be between {MIN_OUTPUT_SIDE} and {MAX_OUTPUT_SIDE} pixels, got {v}");
        }
    }
    Ok((w, h))
}

/// The GPU loop's state and measurements.
struct Run {
    fps: f32,
    log: Log,
    drop_late: bool,
    /// Frames that took longer than 1 / fps, in all and since the last warning.
    late: u64,
    late_unreported: u64,
    slowest_unreported_ms: f64,
    last_warning: Option<Instant>,
    /// Per frame: render time (milliseconds) and GPU time where timed.
    render_ms: Vec<f64>,
    gpu_ms: Vec<f64>,
    /// From the first frame's arrival.
    started: Option<Instant>,
    /// The library's warnings already shown.
    shown: HashSet<String>,
}

impl Run {
    fn new(fps: f32, log: Log, drop_late: bool) -> Self {
        Self {
            fps,
            log,
            drop_late,
            late: 0,
            late_unreported: 0,
            slowest_unreported_ms: 0.0,
            last_warning: None,
            render_ms: Vec::new(),
            gpu_ms: Vec::new(),
            started: None,
            shown: HashSet::new(),
        }
    }

    /// Renders frames until the input ends or the writer stops.
    fn frames(
        &mut self,
        ctx: &GpuContext,
        stream: &mut Stream,
        reader: &Reader,
        writer: &Writer,
        mut poses: Option<Poses>,
    ) -> Result<()> {
        let log = self.log;
        while let Some(frame) = reader.next() {
            self.started.get_or_insert(frame.read_at);
            let k = frame.index;
            let time = (k as f64 / self.fps as f64) as f32;
            let inputs = match &mut poses {
                Some(p) => {
                    p.advance(k, log);
                    StreamFrame {
                        world_from_camera: p.world_from_camera,
                        intrinsics: p.intrinsics,
                        inserts: &p.inserts,
                        ..StreamFrame::photo(&frame.rgb, time)
                    }
                }
                None => StreamFrame::photo(&frame.rgb, time),
            };
            let started = Instant::now();
            let out = stream.composite(ctx, &inputs).with_context(|| format!("frame {k}"))?;
            self.timed(started.elapsed().as_secs_f64() * 1e3, out.gpu_ms, reader);
            for w in out.warnings {
                if self.shown.insert(w.clone()) {
                    log.warn(format!("frame {k}: {w}"));
                }
            }
            if !writer.send(Frame { rgb: out.rgb, ..frame }) {
                break;
            }
        }
        Ok(())
    }

    /// Records one frame's times, and warns (at most once a second) when frames are late.
    fn timed(&mut self, ms: f64, gpu_ms: Option<f64>, reader: &Reader) {
        self.render_ms.push(ms);
        self.gpu_ms.extend(gpu_ms);
        let budget_ms = 1e3 / self.fps as f64;
        if ms <= budget_ms {
            return;
        }
        self.late += 1;
        self.late_unreported += 1;
        self.slowest_unreported_ms = self.slowest_unreported_ms.max(ms);
        if self.last_warning.is_some_and(|t| t.elapsed() < LATE_WARNING_EVERY) {
            return;
        }
        let what = if self.drop_late {
            format!("{} frame(s) dropped so far", reader.counts().1)
        } else {
            "every frame is kept, so the source waits (--drop-late drops frames instead)".into()
        };
        self.log.warn(format!(
            "{} frame(s) took longer than 1/{} s = {budget_ms:.1} ms to render (the slowest {:.1} ms); {what}",
            self.late_unreported, self.fps, self.slowest_unreported_ms
        ));
        (self.late_unreported, self.slowest_unreported_ms) = (0, 0.0);
        self.last_warning = Some(Instant::now());
    }

    /// The closing line: frames, throughput, latency.
    fn summary(&self, read: u64, dropped: u64, mut latencies: Vec<f64>) -> String {
        let seconds = self.started.map_or(0.0, |t| t.elapsed().as_secs_f64());
        let mut line = format!(
            "stream: {read} frames in, {} out, {dropped} dropped, {} late; {:.1} frames/s",
            latencies.len(),
            self.late,
            latencies.len() as f64 / seconds.max(1e-9)
        );
        let ms = |v: &mut Vec<f64>, name: &str| {
            if v.is_empty() {
                return String::new();
            }
            v.sort_by(f64::total_cmp);
            format!(
                "; {name} p50 {:.1} ms, p95 {:.1} ms, max {:.1} ms",
                quantile(v, 0.5),
                quantile(v, 0.95),
                v[v.len() - 1]
            )
        };
        line += &ms(&mut latencies, "latency");
        line += &ms(&mut self.render_ms.clone(), "render");
        line += &ms(&mut self.gpu_ms.clone(), "GPU");
        line
    }
}

#[cfg(test)]
mod tests {
    use super::parse_size;

    #[test]
    fn sizes_parse_strictly() {
        assert_eq!(parse_size("640x480").unwrap(), (640, 480));
        assert_eq!(parse_size("160X120").unwrap(), (160, 120));
        assert_eq!(parse_size("160×120").unwrap(), (160, 120));
        for bad in ["abc", "0x0", "640", "640x", "x480", "-1x5", "640x480x3", "8x8", "99999x480"] {
            let e = format!("{:#}", parse_size(bad).unwrap_err());
            assert!(e.starts_with(&format!("--size {bad}: ")), "{e}");
        }
    }
}
