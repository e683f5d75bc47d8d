//! The subcommands.

mod bench;
mod compare;
mod eval;
mod info;
mod reference;
mod render;
mod sequence;
mod stream;

use crate::args::{Cli, Command, SessionArgs};
use anyhow::Result;
use mrshade_core::settings::Method;
use mrshade_core::text::printable;
use mrshade_gpu::{GpuContext, GpuOptions};
use mrshade_scene::{Session, SessionOverrides};

/// Progress of frames.
const STILL_BAR: &str = "{bar:40} {pos}/{len} frames {elapsed}";

/// Progress and warnings on stderr, unless `--quiet`.
#[derive(Clone, Copy)]
pub struct Log {
    quiet: bool,
}

impl Log {
    /// A progress line.
    pub fn info(&self, msg: impl std::fmt::Display) {
        if !self.quiet {
            eprintln!("mrshade: {}", printable(&msg.to_string()));
        }
    }

    /// Whether progress is shown.
    pub fn shows_progress(&self) -> bool {
        !self.quiet
    }

    /// A progress bar of `len` steps drawn with `template` (indicatif's), hidden under
    /// `--quiet`.
    pub fn progress(&self, len: u64, template: &str) -> Result<indicatif::ProgressBar> {
        let bar =
            if self.shows_progress() { indicatif::ProgressBar::new(len) } else { indicatif::ProgressBar::hidden() };
        bar.set_style(indicatif::ProgressStyle::with_template(template)?);
        Ok(bar)
    }

    /// A warning line.
    pub fn warn(&self, msg: impl std::fmt::Display) {
        if !self.quiet {
            eprintln!("warning: {}", printable(&msg.to_string()));
        }
    }
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    let log = Log { quiet: cli.quiet };
    let gpu = GpuOptions { adapter: cli.adapter };
    match cli.command {
        Command::Render(args) => render::render(&args, &gpu, log),
        Command::Demo(args) => render::demo(&args, &gpu, log),
        Command::Bench(args) => bench::bench(&args, &gpu, log),
        Command::Adapters => info::adapters(),
        Command::Info(args) => info::info(&args, log),
        Command::Compare(args) => compare::compare(&args),
        Command::Reference(args) => reference::reference(&args, log),
        Command::Eval(args) => eval::eval(&args, &gpu, log),
        Command::Stream(args) => stream::stream(&args, &gpu, log),
    }
}

/// The command-line changes of `args` as session overrides.
pub fn overrides(args: &SessionArgs) -> Result<SessionOverrides> {
    let mut set = args.set.clone();
    if let Some(mode) = &args.composite {
        set.push(format!("composite.mode=\"{mode}\""));
    }
    if let Some(n) = args.supersample {
        set.push(format!("output.supersample={n}"));
    }
    let method = args.method.as_deref().map(Method::from_name).transpose().map_err(anyhow::Error::msg)?;
    Ok(SessionOverrides {
        width: args.width,
        height: args.height,
        method,
        set,
        stretch_photo: args.stretch_photo,
        allow_read: args.allow_read.clone(),
    })
}

/// Loads a session from disk, printing its warnings.
pub fn load_session(args: &SessionArgs, log: Log) -> Result<Session> {
    log.info(format!("loading {}", args.session.display()));
    let session = Session::load(&args.session, &overrides(args)?)?;
    for w in &session.warnings {
        log.warn(w);
    }
    Ok(session)
}

/// The `q` quantile (0 to 1) of `sorted` (ascending, not empty): the nearest sample's value.
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() as f64 - 1.0) * q).round() as usize]
}

/// Opens the GPU, printing which adapter was chosen.
pub fn open_gpu(options: &GpuOptions, log: Log) -> Result<GpuContext> {
    let ctx = GpuContext::new(options)?;
    log.info(format!("adapter: {}", ctx.describe()));
    Ok(ctx)
}
