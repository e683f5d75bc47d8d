//! Running one case through what users run: `info` (the session and every loader),
//! `reference` (the path tracer, tiny: it builds a BVH over whatever loaded), `compare`
//! (the photo against itself through FLIP) and, given a GPU, `render` (24 pixels wide, the
//! `direct` or `dir` method by the case's parity). Outcomes: the input loaded, or it was refused with
//! a message; anything else (a panic, a NaN image, a message of several lines) is a failure.
//! Hangs, crashes and memory blow-ups are caught one level up, by the driver.

use crate::case::Case;
use mrshade_gpu::GpuContext;
use mrshade_render::Renderer;
use mrshade_scene::budget::Budget;
use mrshade_scene::{Session, SessionOverrides};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::Mutex;

/// What a case did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// It loaded and rendered.
    Loaded,
    /// It was refused with this one-line message.
    Refused(String),
}

/// What went wrong, in one line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    /// "panic", "non-finite image", "message".
    pub kind: &'static str,
    /// Details.
    pub message: String,
}

static PANIC_MESSAGE: Mutex<String> = Mutex::new(String::new());

/// Records panic messages instead of printing them; call once per process.
pub fn capture_panics() {
    std::panic::set_hook(Box::new(|info| {
        if let Ok(mut m) = PANIC_MESSAGE.lock() {
            *m = mrshade_core::text::panic_message(info);
        }
    }));
}

/// Writes `case` into `dir` and runs it (on `gpu` too, if given).
pub fn run(case: &Case, dir: &Path, gpu: Option<&GpuContext>) -> Result<Outcome, Failure> {
    case.write(dir).map_err(|e| Failure { kind: "harness", message: format!("cannot write the case: {e}") })?;
    let session_path = dir.join("session.toml");
    guarded(|| {
        let outcome = match Session::load(&session_path, &SessionOverrides::default()) {
            Err(e) => return check_message(e),
            Ok(_) => Outcome::Loaded,
        };
        reference(&session_path)?;
        compare(dir)?;
        if let Some(ctx) = gpu {
            render(ctx, &session_path, if case.number.is_multiple_of(2) { "direct" } else { "dir" })?;
        }
        Ok(outcome)
    })
}

/// `f`, with a panic turned into a failure.
fn guarded(f: impl FnOnce() -> Result<Outcome, Failure>) -> Result<Outcome, Failure> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|_| {
        let message = PANIC_MESSAGE.lock().map(|m| m.clone()).unwrap_or_default();
        Err(Failure { kind: "panic", message })
    })
}

/// A refusal must say something, on one line once the CLI joins the chain.
fn check_message(e: anyhow::Error) -> Result<Outcome, Failure> {
    let message = format!("{e:#}");
    if message.trim().is_empty() {
        return Err(Failure { kind: "message", message: "an empty error message".into() });
    }
    Ok(Outcome::Refused(message))
}

/// The path tracer at 24 pixels wide, one path per pixel: every loaded scene goes through the
/// BVH build and a few hundred paths, and must give finite pixels.
fn reference(session_path: &Path) -> Result<(), Failure> {
    let overrides = SessionOverrides {
        width: Some(24),
        set: vec!["reference.spp=1".into(), "reference.max_bounces=3".into()],
        ..Default::default()
    };
    let Ok(session) = Session::load(session_path, &overrides) else { return Ok(()) };
    let image = mrshade_reference::render(&session, &|_, _| {});
    match image.composite.non_finite() {
        Some((count, at)) => {
            Err(Failure { kind: "non-finite image", message: format!("{count} pixels, the first at {at:?}") })
        }
        None => Ok(()),
    }
}

/// The real-time renderer, 24 pixels wide, two frames, with small maps (a CPU driver
/// rasterises a hostile scene's overdraw slowly; the fuzzer hunts crashes and NaN, not
/// speed): a refusal must name its cause (a device limit, a budget), never "a bug in
/// mrshade"; a rendered image must be finite.
fn render(ctx: &GpuContext, session_path: &Path, method: &str) -> Result<(), Failure> {
    let small = ["output.frames=2", "shadows.resolution=256", "dir.rsm_resolution=16", "dir.vpl_count=16"];
    let overrides = SessionOverrides {
        width: Some(24),
        method: mrshade_core::settings::Method::from_name(method).ok(),
        set: small.iter().map(|s| s.to_string()).chain(["dir.ism_resolution=16".into()]).collect(),
        ..Default::default()
    };
    let Ok(session) = Session::load(session_path, &overrides) else { return Ok(()) };
    let bug = |e: anyhow::Error| {
        let message = format!("{e:#}");
        if message.contains("bug in mrshade") { Err(Failure { kind: "GPU", message }) } else { Ok(()) }
    };
    let mut renderer = match Renderer::new(ctx, &session) {
        Ok(r) => r,
        Err(e) => return bug(e),
    };
    match renderer.render_still(ctx, session.output.frames, |_| {}) {
        Ok(_) => Ok(()),
        Err(e) => Err(Failure { kind: "GPU", message: format!("{method}: {e:#}") }),
    }
}

/// `compare`'s path: the photo decoded under its budget, scored against itself.
fn compare(dir: &Path) -> Result<(), Failure> {
    let budget = Budget::images(mrshade_eval::metrics::DEFAULT_MAX_PIXELS, "--max-pixels");
    for name in ["background.png", "background.jpg"] {
        let Ok(bytes) = std::fs::read(dir.join(name)) else { continue };
        let Ok(img) = mrshade_scene::images::decode_rgb8(&bytes, &budget) else { continue };
        let rgb8 = mrshade_eval::metrics::Rgb8 { width: img.width(), height: img.height(), rgb: img.into_raw() };
        if let Ok(c) = mrshade_eval::metrics::compare(&rgb8, &rgb8)
            && c.scores(None).is_ok_and(|s| !s.flip.is_finite())
        {
            return Err(Failure { kind: "non-finite image", message: "FLIP of an image against itself".into() });
        }
    }
    Ok(())
}
