#!/usr/bin/env bash
# glTF 2.0 conformance: inserts every .gltf/.glb of a folder (default: assimp's test models,
# Debian package `assimp-testmodels`) into a benchmark scene's photo, 12 cm tall on the desk,
# renders it, and prints a Markdown table: rendered (with the loader's warnings) or refused
# (with its one-line error, which must name the file and the field). Optional: the models are
# not part of this repository.
#
#   scripts/gltf-conformance.sh [MODELS_DIR] [SCENE_DIR] [-- extra mrshade render flags]
#   e.g. scripts/gltf-conformance.sh /usr/share/assimp/models/glTF2 assets/benchmark/desk-spot-real -- --method dir
#
# Needs a release build (cargo build --release), or MRSHADE=path/to/mrshade. Renders go to a
# temporary folder, printed at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
models=${1:-/usr/share/assimp/models/glTF2}
scene=${2:-assets/benchmark/desk-spot-real}
shift 2 || shift $# || true
[ "${1:-}" = "--" ] && shift
mrshade=${MRSHADE:-./target/release/mrshade}
[ -d "$models" ] || { echo "error: no models at $models (apt-get install assimp-testmodels)" >&2; exit 1; }
[ -x "$mrshade" ] || { echo "error: $mrshade not found (cargo build --release, or set MRSHADE)" >&2; exit 1; }
[ "$#" -gt 0 ] || set -- --width 320 --height 240
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
out=$(mktemp -d)
models=$(cd "$models" && pwd)
rendered=0 refused=0 total=0
echo "| model | result | s | what mrshade said |"
echo "|---|---|---|---|"
while IFS= read -r model; do
  total=$((total + 1))
  rel=${model#"$models"/}
  name=$(echo "$rel" | tr '/' '_')
  work="$out/${name%.*}"
  mkdir -p "$work"
  cp "$scene"/* "$work/"
  printf '\n[[insert]]\nmodel = "%s"\ntranslation = [0.05, 0.0, 0.2]\nfit = 0.12\nrotation_deg = [0, 30, 0]\n' \
    "$model" >> "$work/session.toml"
  start=$(date +%s%N)
  if "$mrshade" render "$work/session.toml" -o "$out/${name%.*}.png" --allow-read "$(dirname "$model")" "$@" \
      2> "$work/stderr.txt" > /dev/null; then
    result=rendered; rendered=$((rendered + 1))
    said=$(grep -i "warning" "$work/stderr.txt" | sed 's/^mrshade: //' | tr '\n' ' ' | cut -c1-300 || true)
  else
    result=refused; refused=$((refused + 1))
    said=$(tail -n 1 "$work/stderr.txt" | cut -c1-300)
  fi
  secs=$(( ($(date +%s%N) - start) / 1000000 ))
  said=${said//|/\\|}
  said=${said//$models\//}
  echo "| $rel | $result | $(printf '%d.%02d' $((secs / 1000)) $((secs % 1000 / 10))) | ${said:-} |"
done < <(find "$models" -type f \( -name '*.gltf' -o -name '*.glb' \) | sort)
echo
echo "$total files: $rendered rendered, $refused refused. Images in $out"
