#!/usr/bin/env python3
"""Makes the scene `mrshade bench` measures the specular stage on (issue: a glass object, a
mirror object and a spot light): the benchmark's desk-glass with desk-mirror's mirror sphere
and a real spot light added, written as OUT/scene.gltf + scene.bin + session.toml.

usage: specular-bench-scene.py SCENES_DIR OUT   (SCENES_DIR: the team's benchmark data)
"""
import json, shutil, sys
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
glass["buffers"][0] = {"uri": "scene.bin", "byteLength": len(glass_bin) + len(mirror_bin)}
(out / "scene.bin").write_bytes(glass_bin + mirror_bin)
(out / "scene.gltf").write_text(json.dumps(glass))
for f in ["background.png", "environment.exr"]:
    shutil.copy(scenes / "desk-glass" / f, out / f)
(out / "session.toml").write_text((scenes / "desk-glass/session.toml").read_text())
print(f"wrote {out}")
