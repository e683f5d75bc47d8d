//! Command-line arguments.

use clap::{Args, Parser, Subcommand};
use mrshade_core::settings::Method;
use std::path::PathBuf;

/// Real-time mixed-reality rendering with reciprocal shading: inserts the virtual objects of a
/// glTF scene into a photo of the real one, with their shadows and light on the real
/// surfaces, by differential rendering.
#[derive(Parser, Debug)]
#[command(name = "mrshade", version, propagate_version = true)]
pub struct Cli {
    /// The command to run.
    #[command(subcommand)]
    pub command: Command,
    /// Use the GPU adapter whose name contains this text (see `mrshade adapters`).
    #[arg(long, global = true, value_name = "NAME")]
    pub adapter: Option<String>,
    /// Print nothing but errors.
    #[arg(short, long, global = true)]
    pub quiet: bool,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a session (TOML) to an image (.png: sRGB; .exr: linear; .jpg: sRGB).
    Render(RenderArgs),
    /// Render the built-in demo session (a desk lamp lights a real desk; a virtual torus and
    /// cube cast its shadows), with no other input.
    Demo(DemoArgs),
    /// Measure GPU time per pass and per frame with timestamp queries.
    Bench(BenchArgs),
    /// List the GPU adapters this machine offers.
    Adapters,
    /// Print what a session holds: objects, lights, flags, warnings.
    Info(InfoArgs),
    /// Score an image against a reference: FLIP, PSNR, RMSE, SSIM (over a mask if given).
    Compare(CompareArgs),
    /// Render a session with the CPU differential path tracer (unbiased, all cores): L_rv and
    /// L_r from the same paths, composited like the real-time methods. Minutes per image.
    Reference(ReferenceArgs),
    /// Composite a live stream: raw 8-bit RGB frames (ffmpeg's rawvideo rgb24) of --size W×H
    /// from stdin to stdout, one renderer frame each (real time), moved by the camera and
    /// insert poses of --poses (docs/stream.md: webcams, video files, MP4 out).
    Stream(StreamArgs),
    /// Render benchmark datasets with one or more methods, score each against its answer
    /// (FLIP over the frame and the changed region, PSNR, SSIM), time it, and write a report.
    Eval(EvalArgs),
}

/// How to load a session and what to change in it.
#[derive(Args, Debug, Clone)]
pub struct SessionArgs {
    /// The session file (TOML): scene, background, exposure, [environment], …
    #[arg(value_name = "SESSION")]
    pub session: PathBuf,
    /// Output width in pixels (default: the photo's; the height follows its aspect ratio).
    #[arg(long)]
    pub width: Option<u32>,
    /// Output height in pixels.
    #[arg(long)]
    pub height: Option<u32>,
    /// Light-transport method.
    #[arg(long, value_parser = method_names())]
    pub method: Option<String>,
    /// Compositing: `alpha` (α-scaled differential, default) or `additive` (Debevec).
    #[arg(long, value_parser = ["alpha", "additive"])]
    pub composite: Option<String>,
    /// Shading samples per pixel along each axis (1–4): anti-aliases the virtual edges.
    #[arg(long, value_name = "N")]
    pub supersample: Option<u32>,
    /// Override any session setting, e.g. `--set shadows.resolution=4096` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Also read files under this folder (repeatable). By default a session and its glTF
    /// files read only under their own folders.
    #[arg(long, value_name = "FOLDER")]
    pub allow_read: Vec<PathBuf>,
    /// Set by commands that may change the aspect ratio (bench); not a flag.
    #[arg(skip)]
    pub stretch_photo: bool,
}

fn method_names() -> Vec<&'static str> {
    Method::ALL.iter().map(|m| m.name()).collect()
}

/// What `eval --method` takes: every real-time method, the reference, and `all` of them.
fn eval_method_names() -> Vec<&'static str> {
    method_names().into_iter().chain(["reference", "all"]).collect()
}

/// `mrshade render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The session and its overrides.
    #[command(flatten)]
    pub session: SessionArgs,
    /// Output image: .png (sRGB), .exr (linear camera values) or .jpg. For a sequence
    /// session, a folder (written as OUT/NNNN.png, numbered as the input frames; see --format).
    #[arg(short, long, value_name = "OUT", required_unless_present = "video")]
    pub output: Option<PathBuf>,
    /// Also write the AOVs here: l_rv.exr, l_r.exr, alpha.exr, difference.exr and
    /// difference_signed.png, virtual_mask.png, normals.png, flags.png, side_by_side.png
    /// (for a sequence, one folder per frame: DIR/NNNN/).
    #[arg(long, value_name = "DIR")]
    pub aov_dir: Option<PathBuf>,
    /// Sequence: render frame K alone as a converged still (as for a photo) into OUT.
    #[arg(long, value_name = "K", conflicts_with_all = ["frames", "video"])]
    pub frame: Option<usize>,
    /// Sequence: render frames A..B (B excluded; A..=B includes it) only. Earlier frames
    /// are rendered first and not written, so that the range matches the whole run's frames:
    /// shard a long sequence across machines with it (README: GNU parallel, Slurm).
    #[arg(long, value_name = "A..B")]
    pub frames: Option<String>,
    /// Sequence: frames rendered (unwritten) before a --frames range starts.
    #[arg(long, value_name = "N", default_value_t = mrshade_render::footage::RANGE_WARMUP_FRAMES)]
    pub warmup: usize,
    /// Sequence: image format of the frames in the OUT folder.
    #[arg(long, value_name = "FORMAT", default_value = "png", value_parser = ["png", "exr", "jpg"])]
    pub format: String,
    /// Sequence: also encode the frames into this video with ffmpeg (H.264, at the session's
    /// fps), which must be installed.
    #[arg(long, value_name = "OUT.mp4")]
    pub video: Option<PathBuf>,
}

/// `mrshade demo`.
#[derive(Args, Debug)]
pub struct DemoArgs {
    /// Output image.
    #[arg(short, long, value_name = "OUT", default_value = "demo.png")]
    pub output: PathBuf,
    /// Also write the AOVs here (see `render --help`).
    #[arg(long, value_name = "DIR")]
    pub aov_dir: Option<PathBuf>,
    /// Output width (default 640).
    #[arg(long)]
    pub width: Option<u32>,
    /// Output height (default 480).
    #[arg(long)]
    pub height: Option<u32>,
}

/// `mrshade bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// The session and its overrides.
    #[command(flatten)]
    pub session: SessionArgs,
    /// Frames measured.
    #[arg(long, default_value_t = 300)]
    pub frames: u32,
    /// Frames rendered first and not measured (pipelines compile, caches fill).
    #[arg(long, default_value_t = 30)]
    pub warmup: u32,
    /// Turn the first virtual object a little every frame, so that what depends on where the
    /// objects are (shadow maps, impostors, ISM points) is drawn again each frame, as with a
    /// moving insert. By default a still scene keeps them.
    #[arg(long)]
    pub moving: bool,
    /// Record the specular rays and photons as passes of their own, for a time per pass
    /// (by default they run beside the method's shading, which is faster but times them
    /// together with it).
    #[arg(long)]
    pub serial: bool,
    /// Write the results as JSON here.
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,
}

/// `mrshade stream`.
#[derive(Args, Debug)]
#[command(mut_arg("width", |a| a.hide(true)), mut_arg("height", |a| a.hide(true)))]
pub struct StreamArgs {
    /// The session and its overrides (its output size is --size).
    #[command(flatten)]
    pub session: SessionArgs,
    /// Frame size in pixels, in and out: W×H×3 bytes a frame (e.g. 640x480). Its aspect ratio
    /// must be the session's (see --stretch).
    #[arg(long, value_name = "WxH", required = true)]
    pub size: String,
    /// Frames per second of the source: frame k is at k / F seconds for the scene's animations,
    /// and a frame that takes longer than 1/F to render is late (default: the session's
    /// [sequence] fps, else 30).
    #[arg(long, value_name = "F")]
    pub fps: Option<f32>,
    /// Camera and insert poses, one JSON object a line, from a file or a FIFO, read as they
    /// come (docs/stream.md); a bad line is skipped with a warning.
    #[arg(long, value_name = "FILE")]
    pub poses: Option<PathBuf>,
    /// For live sources: render the newest frame only, dropping (and counting) frames that
    /// arrive while one renders. By default every frame is rendered and the source waits.
    #[arg(long)]
    pub drop_late: bool,
    /// Render the first frame this many more times before writing it, so that a temporal
    /// method has converged (as a still's or footage's first frames do).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub settle: u32,
    /// Accept a --size of another aspect ratio than the session's photo and camera: the
    /// session's camera keeps its vertical field of view (a transforms session's is stretched);
    /// give the real intrinsics in --poses.
    #[arg(long)]
    pub stretch: bool,
}

/// `mrshade reference`.
#[derive(Args, Debug)]
pub struct ReferenceArgs {
    /// The session and its overrides (`--set reference.max_bounces=4`, …).
    #[command(flatten)]
    pub session: SessionArgs,
    /// Paths per pixel (default: the session's `[reference] spp`, 256).
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
    /// Seed of the sample sequence (default: the session's, 0).
    #[arg(long)]
    pub seed: Option<u32>,
    /// Output image: .png (sRGB), .exr (linear camera values) or .jpg.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Also write l_rv.exr, l_r.exr, alpha.exr, virtual_mask.png and side_by_side.png here.
    #[arg(long, value_name = "DIR")]
    pub aov_dir: Option<PathBuf>,
}

/// `mrshade eval`.
#[derive(Args, Debug)]
pub struct EvalArgs {
    /// Dataset folders, each with session.toml, background.png and ground_truth.png (the
    /// layout of the benchmark's scenes); or a sequence: session.toml with `[sequence]
    /// transforms`, the frames it lists and ground_truth/NAME.png per frame (NAME: the frame
    /// image's stem), played as footage and scored frame by frame.
    #[arg(value_name = "DATASET", required = true)]
    pub datasets: Vec<PathBuf>,
    /// Methods to run (repeatable or comma-separated): the real-time methods, and
    /// `reference` (the CPU path tracer), or `all`.
    #[arg(long, value_delimiter = ',', default_value = "dir", value_parser = eval_method_names())]
    pub method: Vec<String>,
    /// Paths per pixel of the reference method (default: the session's, 256).
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
    /// Override any session setting (repeatable), as `render --set`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Also read files under this folder (repeatable), as `render --allow-read`.
    #[arg(long, value_name = "FOLDER")]
    pub allow_read: Vec<PathBuf>,
    /// Largest image scored, in pixels (FLIP takes about 120 bytes per pixel).
    #[arg(long, value_name = "N", default_value_t = mrshade_eval::metrics::DEFAULT_MAX_PIXELS)]
    pub max_pixels: u64,
    /// Write report.md, report.json, index.html and the images here.
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// Sequences: also render every frame alone as a converged still (as `render --frame K`),
    /// reported as the method `METHOD-stills`, to compare footage with (real-time methods).
    #[arg(long)]
    pub stills: bool,
    /// Give every real-time method the same GPU time for a still (milliseconds, repeatable
    /// or comma-separated: one row per budget): as many frames as fit, measured by the
    /// timestamp queries, so temporal methods accumulate over them (Franke's equal-time
    /// comparison). Still datasets only; needs an adapter with timestamp queries.
    #[arg(long = "budget-ms", value_name = "MS", value_delimiter = ',', value_parser = positive_ms)]
    pub budget_ms: Vec<f64>,
}

fn positive_ms(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(ms) if ms.is_finite() && ms > 0.0 && ms <= 3.6e6 => Ok(ms),
        _ => Err(format!("a budget is a number of milliseconds above 0 and at most 3600000, got `{text}`")),
    }
}

/// `mrshade info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// The session and its overrides.
    #[command(flatten)]
    pub session: SessionArgs,
}

/// `mrshade compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    /// The reference image (PNG or JPEG, 8-bit sRGB), e.g. a path-traced answer.
    #[arg(value_name = "REFERENCE")]
    pub reference: PathBuf,
    /// The image to score, of the same size.
    #[arg(value_name = "TEST")]
    pub test: PathBuf,
    /// Score only where this image (same size) is not black, e.g. a changed-region mask.
    #[arg(long, value_name = "MASK.png")]
    pub mask: Option<PathBuf>,
    /// Write the FLIP error map here as a heat map (magma: black = equal, yellow = different).
    #[arg(long, value_name = "OUT.png")]
    pub heatmap: Option<PathBuf>,
    /// Print the scores as one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Largest image scored, in pixels: FLIP takes about 120 bytes per pixel, so the default
    /// 16 Mi pixels (4096 × 4096) take 2 GiB.
    #[arg(long, value_name = "N", default_value_t = mrshade_eval::metrics::DEFAULT_MAX_PIXELS)]
    pub max_pixels: u64,
}
