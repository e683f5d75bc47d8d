//! mrshade's fuzzing harness, on stable Rust (`cargo fuzz` needs nightly).
//!
//! A case is a number: it picks a committed session ([`corpus`]) and one to four
//! structure-aware mutations of its files ([`mutate`]: glTF JSON and GLB, session TOML, PNG
//! and EXR headers, bytes), driven by `arbitrary` from bytes the number seeds. The worker
//! runs each case through the loaders, the path tracer and the metrics ([`run`]); the parent
//! ([`driver`]) catches hangs, crashes and memory blow-ups, and writes every failing case to
//! a folder. `./dev fuzz SECONDS` runs it with a random first number; the test suite runs a
//! fixed range; every input it ever found is a regression test (`tests/`).

pub mod case;
pub mod corpus;
pub mod driver;
pub mod mutate;
pub mod run;

pub use case::Case;
