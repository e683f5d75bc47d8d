//! The parent and its worker. The worker (this program, `worker`) runs cases one by one, under
//! an allocation cap, and answers one line per case. The parent hands out case numbers, and
//! counts the worker's silence past the time limit as a hang and its death (an abort on the
//! allocation cap, a segfault) as a crash; either way it writes the case to the failures
//! folder and starts a new worker.

use crate::case::Case;
use crate::run::{Outcome, run};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::time::{Duration, Instant};

/// How to fuzz.
#[derive(Clone, Debug)]
pub struct Config {
    /// The first case number.
    pub first: u64,
    /// Stop after this many cases…
    pub count: Option<u64>,
    /// …or after this long.
    pub duration: Option<Duration>,
    /// Where failing cases are written (`case-N/` with `failure.txt`).
    pub failures: Option<PathBuf>,
    /// The worker's allocation cap, in MiB.
    pub memory_mib: u64,
    /// Longest a case may take.
    pub timeout: Duration,
    /// This program (for the worker).
    pub exe: PathBuf,
    /// Render every case that loads on the GPU too (slow on a CPU driver).
    pub gpu: bool,
}

/// What a run found.
#[derive(Debug, Default)]
pub struct Summary {
    /// Cases tried.
    pub tried: u64,
    /// Cases that loaded.
    pub loaded: u64,
    /// Cases refused with a message.
    pub refused: u64,
    /// `(case number, what went wrong)`.
    pub failures: Vec<(u64, String)>,
    /// Longest case, in seconds, and its number.
    pub slowest: (f64, u64),
}

struct Worker {
    child: Child,
    stdin: ChildStdin,
    lines: Receiver<String>,
    stderr: PathBuf,
}

impl Worker {
    fn start(config: &Config, stderr: &Path) -> std::io::Result<Worker> {
        let mut command = Command::new(&config.exe);
        command.args(["worker", "--memory-mib", &config.memory_mib.to_string()]);
        if config.gpu {
            command.arg("--gpu");
        }
        let mut child =
            command.stdin(Stdio::piped()).stdout(Stdio::piped()).stderr(std::fs::File::create(stderr)?).spawn()?;
        let stdin = child.stdin.take().expect("piped");
        let stdout = child.stdout.take().expect("piped");
        let (tx, lines) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        Ok(Worker { child, stdin, lines, stderr: stderr.to_path_buf() })
    }

    /// The worker's last words, for a crash report.
    fn last_words(&mut self) -> String {
        let status = self.child.wait().map(|s| s.to_string()).unwrap_or_default();
        let err = std::fs::read_to_string(&self.stderr).unwrap_or_default();
        let last = err.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("").to_string();
        format!("{status}; {last}")
    }
}

/// Runs cases from `config.first` on, until the count or the time is reached.
pub fn fuzz(config: &Config, mut progress: impl FnMut(&Summary)) -> std::io::Result<Summary> {
    let scratch = tempfile::tempdir()?;
    let stderr = scratch.path().join("worker.stderr");
    let mut worker = Worker::start(config, &stderr)?;
    let mut summary = Summary::default();
    let started = Instant::now();
    let mut number = config.first;
    loop {
        if config.count.is_some_and(|c| summary.tried >= c) || config.duration.is_some_and(|d| started.elapsed() >= d) {
            break;
        }
        writeln!(worker.stdin, "{number}")?;
        let case_started = Instant::now();
        let failure = match worker.lines.recv_timeout(config.timeout) {
            Ok(line) => match line.split_once(' ') {
                Some(("loaded", _)) => {
                    summary.loaded += 1;
                    None
                }
                Some(("refused", _)) => {
                    summary.refused += 1;
                    None
                }
                _ => Some(line),
            },
            Err(RecvTimeoutError::Timeout) => {
                let _ = worker.child.kill();
                let _ = worker.child.wait();
                Some(format!("hang: no answer within {} s", config.timeout.as_secs()))
            }
            Err(RecvTimeoutError::Disconnected) => Some(format!("crash: {}", worker.last_words())),
        };
        let seconds = case_started.elapsed().as_secs_f64();
        if seconds > summary.slowest.0 {
            summary.slowest = (seconds, number);
        }
        summary.tried += 1;
        if let Some(what) = failure {
            if let Some(dir) = &config.failures {
                let case_dir = dir.join(format!("case-{number}"));
                // A case the generator itself cannot make is the harness's failure; say so.
                match std::panic::catch_unwind(|| Case::generate(number)) {
                    Ok(case) => case.write(&case_dir)?,
                    Err(_) => std::fs::create_dir_all(&case_dir)?,
                }
                std::fs::write(case_dir.join("failure.txt"), format!("{what}\n"))?;
            }
            summary.failures.push((number, what));
            if !worker_alive(&mut worker) {
                worker = Worker::start(config, &stderr)?;
            }
        }
        number = number.wrapping_add(1);
        if summary.tried.is_multiple_of(100) {
            progress(&summary);
        }
    }
    drop(worker.stdin);
    let _ = worker.child.wait();
    Ok(summary)
}

fn worker_alive(worker: &mut Worker) -> bool {
    matches!(worker.child.try_wait(), Ok(None))
}

/// The worker's loop: a case number per line in, one line out per case.
pub fn worker(gpu: bool) -> std::io::Result<()> {
    let ctx = if gpu {
        Some(mrshade_gpu::GpuContext::new(&Default::default()).map_err(|e| std::io::Error::other(format!("{e:#}")))?)
    } else {
        None
    };
    crate::run::capture_panics();
    let scratch = tempfile::tempdir()?;
    let stdout = std::io::stdout();
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        let Ok(number) = line.trim().parse::<u64>() else { continue };
        let dir = scratch.path().join(number.to_string());
        let answer = match run(&Case::generate(number), &dir, ctx.as_ref()) {
            Ok(Outcome::Loaded) => "loaded -".to_string(),
            Ok(Outcome::Refused(message)) => {
                format!("refused {}", mrshade_core::text::printable(&message.replace('\n', " ")))
            }
            Err(f) => format!("{}: {}", f.kind, mrshade_core::text::printable(&f.message.replace('\n', " "))),
        };
        let _ = std::fs::remove_dir_all(&dir);
        let mut out = stdout.lock();
        writeln!(out, "{answer}")?;
        out.flush()?;
    }
    Ok(())
}
