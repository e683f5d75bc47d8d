//! The session file's TOML: its tables, strict (`deny_unknown_fields`), and the `--set`
//! overrides applied to it before it is read.

use super::SessionOverrides;
use super::output::OutputFile;
use crate::sequence::{DEFAULT_FPS, DEFAULT_SAMPLES};
use anyhow::{Context, Result};
use mrshade_core::settings::{
    CausticsSettings, CompositeSettings, DirSettings, DlpvSettings, DvctSettings, IblSettings, Limits, Method,
    ReferenceSettings, ShadowSettings, SpecularSettings,
};
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SessionFile {
    pub(super) scene: String,
    pub(super) background: Option<String>,
    #[serde(default = "one")]
    pub(super) exposure: f32,
    pub(super) camera: Option<toml::Value>,
    #[serde(default)]
    pub(super) method: Method,
    pub(super) environment: Option<EnvironmentFile>,
    #[serde(default)]
    pub(super) output: OutputFile,
    #[serde(default)]
    pub(super) composite: CompositeSettings,
    #[serde(default)]
    pub(super) shadows: ShadowSettings,
    #[serde(default)]
    pub(super) dir: DirSettings,
    #[serde(default)]
    pub(super) dvct: DvctSettings,
    #[serde(default)]
    pub(super) dlpv: DlpvSettings,
    #[serde(default)]
    pub(super) ibl: IblSettings,
    #[serde(default)]
    pub(super) specular: SpecularSettings,
    #[serde(default)]
    pub(super) caustics: CausticsSettings,
    #[serde(default)]
    pub(super) reference: ReferenceSettings,
    #[serde(default)]
    pub(super) limits: Limits,
    pub(super) sequence: Option<SequenceFile>,
    #[serde(default, rename = "insert")]
    pub(super) inserts: Vec<super::insert::InsertFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SequenceFile {
    pub(super) transforms: Option<String>,
    pub(super) frames: Option<u32>,
    #[serde(default = "default_fps")]
    pub(super) fps: f32,
    #[serde(default = "default_samples")]
    pub(super) samples: u32,
}

fn default_samples() -> u32 {
    DEFAULT_SAMPLES
}

fn default_fps() -> f32 {
    DEFAULT_FPS
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct EnvironmentFile {
    pub(super) image: String,
    #[serde(default)]
    pub(super) rotation_deg: f32,
    #[serde(default = "one")]
    pub(super) intensity: f32,
}

fn one() -> f32 {
    1.0
}

/// Parses the TOML after applying `--set` overrides to its table.
pub(super) fn parse(text: &str, overrides: &SessionOverrides) -> Result<SessionFile> {
    if overrides.set.is_empty() {
        return toml::from_str(text).map_err(|e| toml_error(text, &e));
    }
    let mut table: toml::Table = toml::from_str(text).map_err(|e| toml_error(text, &e))?;
    for pair in &overrides.set {
        apply_set(&mut table, pair)?;
    }
    let merged = toml::to_string(&table)?;
    toml::from_str(&merged).map_err(|e| toml_error(&merged, &e).context("with the --set overrides"))
}

/// A TOML error as one line: where, the offending line's text, and what is wrong.
fn toml_error(text: &str, e: &toml::de::Error) -> anyhow::Error {
    let message = e.message().trim().replace('\n', " ");
    let Some(span) = e.span() else { return anyhow::anyhow!("{message}") };
    let start = span.start.min(text.len());
    let line = text[..start].matches('\n').count() + 1;
    let source = text.lines().nth(line - 1).unwrap_or("").trim();
    let source = mrshade_core::text::printable(source);
    anyhow::anyhow!("line {line} (`{source}`): {}", mrshade_core::text::printable(&message))
}

/// Applies one `dotted.key=value` override.
fn apply_set(table: &mut toml::Table, pair: &str) -> Result<()> {
    let (key, value) = pair.split_once('=').with_context(|| format!("--set {pair}: expected KEY=VALUE"))?;
    let value: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {value}")) {
        Ok(mut t) => t.remove("v").context("unreachable")?,
        Err(_) => toml::Value::String(value.to_string()),
    };
    let parts: Vec<&str> = key.trim().split('.').collect();
    let mut node = table;
    for part in &parts[..parts.len() - 1] {
        let entry = node.entry(part.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        node = entry.as_table_mut().with_context(|| format!("--set {pair}: `{part}` is not a table"))?;
    }
    node.insert(parts[parts.len() - 1].to_string(), value);
    Ok(())
}
