//! `mrshade-fuzz`: run the harness (`run`), or be its worker (`worker`), or write a case's
//! files for a look (`show`).

use anyhow::{Context, Result, bail};
use cap::Cap;
use mrshade_fuzz::driver::{Config, fuzz, worker};
use std::time::Duration;

/// Counts every allocation; the worker caps them, so a blow-up is an abort the parent sees.
#[global_allocator]
static ALLOCATOR: Cap<std::alloc::System> = Cap::new(std::alloc::System, usize::MAX);

const USAGE: &str = "usage: mrshade-fuzz run [--seconds N | --count N] [--first N] [--failures DIR] [--memory-mib M] [--timeout-s T] [--gpu]
       mrshade-fuzz show N DIR";

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |name: &str| -> Result<Option<u64>> {
        args.iter()
            .position(|a| a == name)
            .map(|i| {
                args.get(i + 1)
                    .with_context(|| format!("{name} needs a value"))?
                    .parse::<u64>()
                    .with_context(|| format!("{name}: not a number"))
            })
            .transpose()
    };
    match args.first().map(String::as_str) {
        Some("worker") => {
            let mib = value("--memory-mib")?.unwrap_or(4096);
            ALLOCATOR.set_limit((mib << 20) as usize).map_err(|_| anyhow::anyhow!("cannot set the allocation cap"))?;
            Ok(worker(args.iter().any(|a| a == "--gpu"))?)
        }
        Some("show") => {
            let number: u64 = args.get(1).context(USAGE)?.parse().context("the case number")?;
            let dir = args.get(2).context(USAGE)?;
            let case = mrshade_fuzz::Case::generate(number);
            case.write(std::path::Path::new(dir))?;
            println!("{}", case.recipe.join("\n"));
            Ok(())
        }
        Some("run") => {
            let failures = args.iter().position(|a| a == "--failures").and_then(|i| args.get(i + 1)).map(Into::into);
            let config = Config {
                first: value("--first")?.unwrap_or(0),
                count: value("--count")?,
                duration: value("--seconds")?.map(Duration::from_secs),
                failures,
                memory_mib: value("--memory-mib")?.unwrap_or(4096),
                timeout: Duration::from_secs(value("--timeout-s")?.unwrap_or(30)),
                exe: std::env::current_exe()?,
                gpu: args.iter().any(|a| a == "--gpu"),
            };
            if config.count.is_none() && config.duration.is_none() {
                bail!("say how long: --seconds N or --count N\n{USAGE}");
            }
            let started = std::time::Instant::now();
            let summary = fuzz(&config, |s| {
                eprint!(
                    "\rmrshade-fuzz: {} cases, {} failures, {:.0} s",
                    s.tried,
                    s.failures.len(),
                    started.elapsed().as_secs_f64()
                );
            })?;
            eprintln!();
            println!(
                "mrshade-fuzz: {} cases from {} in {:.0} s ({} loaded, {} refused, slowest {:.1} s: case {}), {} failures",
                summary.tried,
                config.first,
                started.elapsed().as_secs_f64(),
                summary.loaded,
                summary.refused,
                summary.slowest.0,
                summary.slowest.1,
                summary.failures.len()
            );
            for (number, what) in &summary.failures {
                println!("case {number}: {what}");
            }
            if !summary.failures.is_empty() {
                std::process::exit(1);
            }
            Ok(())
        }
        _ => bail!("{USAGE}"),
    }
}
