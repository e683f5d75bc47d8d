//! The `direct` method: no indirect light. Direct light (`crate::passes::direct`) alone fills
//! `L_rv` and `L_r`: punctual lights with real-only and virtual-only shadow maps (Knecht
//! Eq. 5.1–5.5) and the probe's unshadowed light.

use super::{FrameChange, IndirectLight, LightTransport, MethodInputs};
use crate::limits::Fit;
use crate::raster::Rasterizer;
use anyhow::Result;
use mrshade_core::settings::RenderSettings;
use mrshade_gpu::timing::Recorder;

/// Nothing to build, prepare or record.
struct Direct;

pub(super) fn build(_: &MethodInputs) -> Box<dyn LightTransport> {
    Box::new(Direct)
}

pub(super) fn fit(_: &mut RenderSettings, _: &mut Fit) -> Result<()> {
    Ok(())
}

pub(super) fn estimate(_: &RenderSettings, _: u64, _: u64) -> Vec<(&'static str, u64)> {
    Vec::new()
}

impl LightTransport for Direct {
    fn prepare(&mut self, _: &wgpu::Queue, _: &FrameChange) {}
    fn record(&mut self, _: &mut Recorder, _: &Rasterizer) {}
    fn indirect(&self) -> Option<&IndirectLight> {
        None
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
