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
