//! `mrshade adapters` and `mrshade info`.

use super::{Log, load_session};
use crate::args::InfoArgs;
use anyhow::Result;
use mrshade_core::text::printable;

/// Lists the adapters.
pub fn adapters() -> Result<()> {
    let adapters = mrshade_gpu::context::list_adapters();
    if adapters.is_empty() {
        anyhow::bail!("{}", mrshade_gpu::NO_ADAPTER_HELP);
    }
    for a in adapters {
        println!("{} ({:?}, {:?}, driver {} {})", a.name, a.backend, a.device_type, a.driver, a.driver_info);
    }
    Ok(())
}

/// Prints a session's contents.
pub fn info(args: &InfoArgs, log: Log) -> Result<()> {
    let s = load_session(&args.session, log)?;
    let camera = &s.scene.cameras[s.camera];
    println!("session    {}", printable(&s.origin));
    println!("output     {}×{} (supersample {})", s.output.width, s.output.height, s.output.supersample);
    println!("camera     {} (yfov {:.1}°)", printable(&camera.node_name), camera.yfov.to_degrees());
    if let Some(seq) = &s.sequence {
        let first = &seq.frames[0];
        let k = first.intrinsics;
        println!(
            "sequence   {} frames at {} fps, {} samples per frame{}; frame {}: fl {:.1}×{:.1} px, centre ({:.1}, {:.1}) of {}×{}",
            seq.frames.len(),
            seq.fps,
            seq.samples,
            if seq.from_transforms { ", posed by transforms.json" } else { ", one photo" },
            printable(&first.name),
            k.fl_x,
            k.fl_y,
            k.cx,
            k.cy,
            k.width,
            k.height
        );
    }
    if s.scene.is_animated() {
        let names: Vec<_> = s.scene.animations.iter().map(|a| printable(&a.name).into_owned()).collect();
        let (from, to) = s.scene.time_range().unwrap_or((0.0, 0.0));
        println!("animations {} ({from:.2}–{to:.2} s)", names.join(", "));
    }
    println!("exposure   {}", s.exposure);
    println!("method     {}", s.settings.method.name());
    println!("composite  {}", s.settings.composite.mode.name());
    if let Some(env) = &s.environment {
        println!(
            "probe      {}×{}, peak {:.1}, rotation {}°, intensity {}",
            env.image.width,
            env.image.height,
            env.image.max_value(),
            env.rotation_deg,
            env.intensity
        );
    }
    for i in &s.scene.instances {
        let p = &s.scene.primitives[i.primitive];
        let material = printable(&s.scene.materials[p.material].name);
        println!(
            "object     {:<8} {} ({} triangles, {material})",
            format!("{:?}", i.realness).to_lowercase(),
            printable(&i.node_name),
            p.indices.len() / 3
        );
    }
    for l in &s.scene.lights {
        println!("light      {:<8} {} {:?}", format!("{:?}", l.realness).to_lowercase(), printable(&l.name), l.kind);
    }
    Ok(())
}
