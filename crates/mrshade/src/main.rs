//! `mrshade`: insert virtual objects into a photo with reciprocal shading.
//!
//! Every failure exits non-zero with one line on stderr naming its cause.

mod args;
mod cmd;
mod demo_assets;
mod output;

use clap::Parser;

fn main() {
    let cli = args::Cli::parse();
    if let Err(e) = cmd::run(cli) {
        // One line, whatever the messages in the chain hold.
        eprintln!("error: {}", format!("{e:#}").replace('\n', " "));
        std::process::exit(1);
    }
}
