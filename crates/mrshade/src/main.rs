//! `mrshade`: insert virtual objects into a photo with reciprocal shading.
//!
//! Every failure exits non-zero with one line on stderr naming its cause.

mod args;
mod cmd;
mod demo_assets;
mod output;

use clap::Parser;

/// Exit status when the reader of our standard output has closed it (`mrshade info | head`):
/// the status of a Unix tool stopped by SIGPIPE (which Rust ignores), with nothing printed.
pub const BROKEN_PIPE_EXIT: i32 = 141;

fn main() {
    // A panic is a bug in mrshade; still, it is reported as one line, like any error.
    std::panic::set_hook(Box::new(|info| {
        let message = mrshade_core::text::panic_message(info);
        // `mrshade info | head`: the reader closed the pipe; stop as a Unix tool does on
        // SIGPIPE (which Rust ignores, so that println! panics instead), without a report.
        if message.contains("failed printing to stdout") && message.contains("Broken pipe") {
            std::process::exit(BROKEN_PIPE_EXIT);
        }
        eprintln!("error: internal error (a bug in mrshade, please report it): {}", one_line(&message));
    }));
    let cli = args::Cli::parse();
    if let Err(e) = cmd::run(cli) {
        eprintln!("error: {}", one_line(&format!("{e:#}")));
        std::process::exit(1);
    }
}

/// One line, whatever the messages in the chain hold: newlines become spaces, and every other
/// control character is escaped (names and paths come from files).
fn one_line(message: &str) -> String {
    mrshade_core::text::printable(&message.replace('\n', " ")).into_owned()
}
