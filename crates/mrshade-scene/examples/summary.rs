//! Prints what a session holds: `cargo run -p mrshade-scene --example summary -- SESSION.toml`.
fn main() -> anyhow::Result<()> {
    let path = std::env::args().nth(1).expect("usage: summary SESSION.toml");
    let s = mrshade_scene::Session::load(path.as_ref(), &Default::default())?;
    println!("{}: {}×{} exposure {}", s.origin, s.output.width, s.output.height, s.exposure);
    for i in &s.scene.instances {
        let p = &s.scene.primitives[i.primitive];
        println!(
            "  {:?} {} ({} tris, material {})",
            i.realness,
            i.node_name,
            p.indices.len() / 3,
            s.scene.materials[p.material].name
        );
    }
    for l in &s.scene.lights {
        println!("  light {:?} {} {:?} I={} at {}", l.realness, l.name, l.kind, l.intensity, l.position());
    }
    for w in &s.warnings {
        println!("  warning: {w}");
    }
    if let Some(env) = &s.environment {
        println!("  probe {}×{} max {}", env.image.width, env.image.height, env.image.max_value());
    }
    Ok(())
}
