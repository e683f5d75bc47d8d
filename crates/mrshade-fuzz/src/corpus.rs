//! The seeds: the committed sessions (six small benchmark scenes, the demo and a tiny posed
//! image sequence, `corpus/`), compiled in so that the harness needs nothing but itself.

/// One committed session: its file name and every file it reads.
pub struct Seed {
    /// Which session (for failure reports).
    pub name: &'static str,
    /// `(file name, bytes)`; `session.toml` names the others.
    pub files: &'static [(&'static str, &'static [u8])],
}

macro_rules! benchmark {
    ($name:literal) => {
        Seed {
            name: $name,
            files: &[
                ("session.toml", include_bytes!(concat!("../../../assets/benchmark/", $name, "/session.toml"))),
                ("scene.glb", include_bytes!(concat!("../../../assets/benchmark/", $name, "/scene.glb"))),
                ("background.png", include_bytes!(concat!("../../../assets/benchmark/", $name, "/background.png"))),
                ("environment.exr", include_bytes!(concat!("../../../assets/benchmark/", $name, "/environment.exr"))),
            ],
        }
    };
}

/// Every seed. The benchmark probes are ZIP-compressed EXR; the demo's is DWAB, whose chunks
/// carry counts of their own.
pub static SEEDS: &[Seed] = &[
    benchmark!("cornell"),
    benchmark!("desk-bunny"),
    benchmark!("desk-glass"),
    benchmark!("desk-mirror"),
    benchmark!("desk-spot-real"),
    benchmark!("desk-spot-virtual"),
    Seed {
        name: "demo",
        files: &[
            ("session.toml", include_bytes!("../../../assets/demo/session.toml")),
            ("scene.glb", include_bytes!("../../../assets/demo/scene.glb")),
            ("background.jpg", include_bytes!("../../../assets/demo/background.jpg")),
            ("environment.exr", include_bytes!("../../../assets/demo/environment.exr")),
        ],
    },
    // A posed image sequence: three frames of `shared/data/sequences/desk-orbit` at 32×24
    // (PNG, PNG named without its extension, JPEG) with intrinsics for 320×240, in the scene
    // and probe of desk-spot-real.
    Seed {
        name: "desk-orbit (sequence)",
        files: &[
            ("session.toml", include_bytes!("../corpus/desk-orbit/session.toml")),
            ("transforms.json", include_bytes!("../corpus/desk-orbit/transforms.json")),
            ("frame_0000.png", include_bytes!("../corpus/desk-orbit/frame_0000.png")),
            ("frame_0012.png", include_bytes!("../corpus/desk-orbit/frame_0012.png")),
            ("frame_0023.jpg", include_bytes!("../corpus/desk-orbit/frame_0023.jpg")),
            ("scene.glb", include_bytes!("../../../assets/benchmark/desk-spot-real/scene.glb")),
            ("environment.exr", include_bytes!("../../../assets/benchmark/desk-spot-real/environment.exr")),
        ],
    },
];
