#!/usr/bin/env python3
"""Makes the scene `mrshade bench` measures the specular stage on (issue: a glass object, a
mirror object and a spot light): the benchmark's desk-glass with desk-mirror's mirror sphere
and a real spot light added, written as OUT/scene.gltf + scene.bin + session.toml.

usage: specular-bench-scene.py SCENES_DIR OUT [--planar]   (SCENES_DIR: the team's benchmark data)
  --planar: also a flat virtual mirror (30 × 20 cm) standing behind the bunny, facing the
  camera, for `specular.intersection = "planar"`.
"""
import json, shutil, struct, sys
from pathlib import Path

scenes, out = Path(sys.argv[1]), Path(sys.argv[2])
out.mkdir(parents=True, exist_ok=True)
glass = json.loads((scenes / "desk-glass/scene.gltf").read_text())
mirror = json.loads((scenes / "desk-mirror/scene.gltf").read_text())
glass_bin = (scenes / "desk-glass" / glass["buffers"][0]["uri"]).read_bytes()
mirror_bin = (scenes / "desk-mirror" / mirror["buffers"][0]["uri"]).read_bytes()
glass_bin += b"\0" * (-len(glass_bin) % 4)

# The mirror sphere's mesh, its accessors, buffer views and material, appended.
node = next(n for n in mirror["nodes"] if n.get("name") == "mirror-sphere")
mesh = json.loads(json.dumps(mirror["meshes"][node["mesh"]]))
view_base, accessor_base = len(glass["bufferViews"]), len(glass["accessors"])
used = sorted({a for p in mesh["primitives"] for a in [*p["attributes"].values(), p["indices"]]})
accessor_of = {}
for a in used:
    acc = dict(mirror["accessors"][a])
    view = dict(mirror["bufferViews"][acc["bufferView"]])
    view["byteOffset"] = view.get("byteOffset", 0) + len(glass_bin)
    glass["bufferViews"].append(view)
    acc["bufferView"] = len(glass["bufferViews"]) - 1
    glass["accessors"].append(acc)
    accessor_of[a] = len(glass["accessors"]) - 1
for p in mesh["primitives"]:
    p["attributes"] = {k: accessor_of[v] for k, v in p["attributes"].items()}
    p["indices"] = accessor_of[p["indices"]]
    glass["materials"].append(mirror["materials"][p["material"]])
    p["material"] = len(glass["materials"]) - 1
glass["meshes"].append(mesh)
sphere = dict(node, mesh=len(glass["meshes"]) - 1, translation=[0.2, 0.08, 0.08])
glass["nodes"].append(sphere)
# A real spot light above the desk, shining down on the glass and the mirror.
glass["extensions"]["KHR_lights_punctual"]["lights"] = [
    {"type": "spot", "color": [1, 0.95, 0.85], "intensity": 4.0, "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}}
]
glass["nodes"].append({"name": "lamp", "translation": [0.1, 0.6, 0.1], "rotation": [-0.7071068, 0, 0, 0.7071068],
                       "extensions": {"KHR_lights_punctual": {"light": 0}}, "extras": {"real": True}})
root = glass["scenes"][glass.get("scene", 0)]["nodes"]
root += [len(glass["nodes"]) - 2, len(glass["nodes"]) - 1]
extra = b""
if "--planar" in sys.argv[3:]:
    # Positions, normals (+z) and two triangles of a 30 × 20 cm quad, appended after both bins.
    base = len(glass_bin) + len(mirror_bin)
    base_pad = -base % 4
    quad = [(-0.15, 0.0, 0.0), (0.15, 0.0, 0.0), (0.15, 0.2, 0.0), (-0.15, 0.2, 0.0)]
    positions = b"".join(struct.pack("<3f", *p) for p in quad)
    normals = struct.pack("<3f", 0, 0, 1) * 4
    indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    extra = b"\0" * base_pad + positions + normals + indices
    start = base + base_pad
    views = [(start, len(positions)), (start + 48, len(normals)), (start + 96, len(indices))]
    first_view = len(glass["bufferViews"])
    glass["bufferViews"] += [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views]
    first_accessor = len(glass["accessors"])
    glass["accessors"] += [
        {"bufferView": first_view, "componentType": 5126, "count": 4, "type": "VEC3",
         "min": [-0.15, 0.0, 0.0], "max": [0.15, 0.2, 0.0]},
        {"bufferView": first_view + 1, "componentType": 5126, "count": 4, "type": "VEC3"},
        {"bufferView": first_view + 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
    ]
    glass["materials"].append({"name": "flat-mirror", "pbrMetallicRoughness": {
        "baseColorFactor": [0.95, 0.95, 0.95, 1], "metallicFactor": 1.0, "roughnessFactor": 0.0}})
    glass["meshes"].append({"name": "flat-mirror", "primitives": [{"attributes": {
        "POSITION": first_accessor, "NORMAL": first_accessor + 1}, "indices": first_accessor + 2,
        "material": len(glass["materials"]) - 1}]})
    glass["nodes"].append({"name": "flat-mirror", "mesh": len(glass["meshes"]) - 1,
                           "translation": [-0.05, 0.0, -0.25], "extras": {"real": False}})
    root.append(len(glass["nodes"]) - 1)
glass["buffers"][0] = {"uri": "scene.bin", "byteLength": len(glass_bin) + len(mirror_bin) + len(extra)}
(out / "scene.bin").write_bytes(glass_bin + mirror_bin + extra)
(out / "scene.gltf").write_text(json.dumps(glass))
for f in ["background.png", "environment.exr"]:
    shutil.copy(scenes / "desk-glass" / f, out / f)
(out / "session.toml").write_text((scenes / "desk-glass/session.toml").read_text())
print(f"wrote {out}")
