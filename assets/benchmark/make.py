#!/usr/bin/env python3
"""Makes the small copies of the benchmark scenes that the golden tests render.

usage: make.py SCENES_DIR   (the team's benchmark data, e.g. ../shared/data/scenes)

For each scene: scene.gltf + scene.bin packed into one GLB (unchanged), the photo and the
path-traced answer box-filtered to 160x120 PNG, the probe box-filtered to 128x64 half-float
EXR (its mean radiance is kept; peaks are averaged with their neighbours), and the session.
"""
import json, struct, sys
from pathlib import Path

import numpy as np
import OpenEXR
from PIL import Image

SCENES = ["cornell", "desk-bunny", "desk-glass", "desk-mirror", "desk-spot-real", "desk-spot-virtual"]
SIZE = (160, 120)
PROBE = (128, 64)


def pack_glb(gltf_path: Path, out: Path):
    doc = json.loads(gltf_path.read_text())
    (buffer,) = doc["buffers"]
    data = (gltf_path.parent / buffer.pop("uri")).read_bytes()
    data += b"\0" * (-len(data) % 4)
    buffer["byteLength"] = len(data)
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(data), 0x004E4942) + data
    out.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(c):
    c = np.clip(c, 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1 / 2.4) - 0.055)


def box(a, size):
    """Box filter of an (h, w, c) array down to size (w, h), an integer factor."""
    h, w, c = a.shape
    fy, fx = h // size[1], w // size[0]
    return a.reshape(size[1], fy, size[0], fx, c).mean(axis=(1, 3))


def downscale_png(src: Path, out: Path):
    # Filtered in linear light, as the camera would have integrated it.
    a = srgb_to_linear(np.asarray(Image.open(src).convert("RGB"), dtype=np.float64) / 255.0)
    b = linear_to_srgb(box(a, SIZE))
    Image.fromarray(np.round(b * 255.0).astype(np.uint8)).save(out, optimize=True)


def downscale_exr(src: Path, out: Path):
    f = OpenEXR.File(str(src))
    rgb = np.asarray(f.parts[0].channels["RGB"].pixels, dtype=np.float64)
    small = box(rgb, PROBE).astype(np.float16)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    OpenEXR.File(header, {"RGB": small}).write(str(out))


def main():
    src_root = Path(sys.argv[1])
    for name in SCENES:
        src, dst = src_root / name, Path(__file__).parent / name
        dst.mkdir(exist_ok=True)
        pack_glb(src / "scene.gltf", dst / "scene.glb")
        downscale_png(src / "background.png", dst / "background.png")
        downscale_png(src / "ground_truth.png", dst / "ground_truth.png")
        downscale_exr(src / "environment.exr", dst / "environment.exr")
        session = (src / "session.toml").read_text().replace('"scene.gltf"', '"scene.glb"')
        (dst / "session.toml").write_text(session)
        print(name, sum(p.stat().st_size for p in dst.iterdir()) // 1024, "KiB")


if __name__ == "__main__":
    main()
