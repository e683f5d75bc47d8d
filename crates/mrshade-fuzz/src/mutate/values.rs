//! The values that make loaders decide: boundaries of integer types, magnitudes that overflow
//! single precision, zero and negative sizes, hostile paths and text.

use arbitrary::Unstructured;

/// Numbers worth trying anywhere a number is read.
pub const NUMBERS: &[f64] = &[
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    2.0,
    3.0,
    4.0,
    255.0,
    256.0,
    65535.0,
    65536.0,
    2147483647.0,
    2147483648.0,
    4294967295.0,
    4294967296.0,
    4294967300.0,
    9007199254740992.0,
    1e-45,
    1e-30,
    1e6,
    1e10,
    1e18,
    1e19,
    1e30,
    -1e30,
    3e38,
    3.4028235e38,
    1e39,
    -1e39,
    1e300,
    std::f64::consts::PI,
    3.5,
    100000.0,
];

/// Strings worth trying anywhere a path, a name or an enum is read.
pub const STRINGS: &[&str] = &[
    "",
    ".",
    "..",
    "/",
    "/etc/passwd",
    "../../../../etc/passwd",
    "/dev/zero",
    "/dev/stdin",
    "scene.bin",
    "environment.exr",
    "background.png",
    "session.toml",
    "data:application/octet-stream;base64,AAAAAAAAAAA=",
    "data:application/octet-stream;base64,!!!",
    "data:,",
    "https://example.com/x.bin",
    "file:///etc/passwd",
    "a%2e%2e/b",
    "x\r\u{1b}[31mred\u{1b}[0m\nnext",
    "\u{202e}evil",
    "POSITION",
    "NORMAL",
    "TEXCOORD_0",
    "KHR_lights_punctual",
    "KHR_draco_mesh_compression",
    "VEC3",
    "SCALAR",
    "MAT4",
    "LINEAR",
    "CUBICSPLINE",
    "perspective",
    "orthographic",
    "spot",
    "image/png",
    "image/jpeg",
    "2.0",
    "1.0",
    "2.1",
    "dir",
    "direct",
    "alpha",
    "additive",
    "weighted",
    "flux",
];

/// A number from [`NUMBERS`], or near an existing value (`around`: plausible, so that the case
/// goes on past the range checks), or a small integer.
pub fn number(u: &mut Unstructured, around: Option<f64>) -> f64 {
    match (u.int_in_range(0..=9u8).unwrap_or(0), around) {
        (0..=3, _) => NUMBERS[u.choose_index(NUMBERS.len()).unwrap_or(0)],
        (4..=5, Some(v)) => {
            let factors = [-1.0, 0.0, 1e-10, 1e10, 1e30, 2.0, 0.5];
            v * factors[u.choose_index(factors.len()).unwrap_or(0)] + [0.0, 1.0, -1.0][u.choose_index(3).unwrap_or(0)]
        }
        (6..=7, Some(v)) => v * (0.5 + u.int_in_range(0..=100u8).unwrap_or(50) as f64 / 100.0),
        _ => u.int_in_range(-2..=40i32).unwrap_or(0) as f64,
    }
}

/// A string from [`STRINGS`].
pub fn string(u: &mut Unstructured) -> &'static str {
    STRINGS[u.choose_index(STRINGS.len()).unwrap_or(0)]
}
