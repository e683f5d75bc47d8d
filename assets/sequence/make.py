#!/usr/bin/env python3
"""Makes the small copy of the team's posed sequence `desk-orbit` that the tests render.

usage: make.py SEQUENCES_DIR   (the team's sequence data, e.g. ../shared/data/sequences)

Every other frame of the 24 (fps halved, so each frame keeps its time), photos and answers
box-filtered 4x4 in linear light to 80x60, intrinsics scaled with them, the probe as for the
benchmark copies (128x64 half-float), scene.gltf + scene.bin packed into one GLB (unchanged).
"""
import json, sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent.parent / "benchmark"))
import make as bench  # noqa: E402  (the benchmark copies' helpers: pack_glb, box filters)

SIZE = (80, 60)
STEP = 2


def main():
    src = Path(sys.argv[1]) / "desk-orbit"
    dst = Path(__file__).parent / "desk-orbit-mini"
    for sub in ("frames", "ground_truth"):
        (dst / sub).mkdir(parents=True, exist_ok=True)
    bench.SIZE = SIZE
    bench.pack_glb(src / "scene.gltf", dst / "scene.glb")
    bench.downscale_exr(src / "environment.exr", dst / "environment.exr")
    transforms = json.loads((src / "transforms.json").read_text())
    scale = SIZE[0] / transforms["w"]
    for key in ("fl_x", "fl_y", "cx", "cy"):
        transforms[key] *= scale
    transforms["w"], transforms["h"] = SIZE
    transforms["frames"] = transforms["frames"][::STEP]
    for frame in transforms["frames"]:
        name = Path(frame["file_path"]).name
        bench.downscale_png(src / "frames" / name, dst / "frames" / name)
        bench.downscale_png(src / "ground_truth" / name, dst / "ground_truth" / name)
    (dst / "transforms.json").write_text(json.dumps(transforms, indent=1))
    session = (src / "session.toml").read_text().replace('"scene.gltf"', '"scene.glb"')
    session = session.replace("fps = 30", f"fps = {30 // STEP}")
    (dst / "session.toml").write_text(session)
    print(dst.name, sum(p.stat().st_size for p in dst.rglob("*") if p.is_file()) // 1024, "KiB")


if __name__ == "__main__":
    main()
