#!/usr/bin/env bash
# Renders every benchmark scene and scores it against its path-traced answer with the
# reference scorer (FLIP over the changed region and the whole frame, PSNR), printing a
# Markdown table. Optional: it reads the team's data outside this repository.
#
#   scripts/score-benchmarks.sh [SCENES_DIR] [-- extra mrshade render flags]
#   e.g. scripts/score-benchmarks.sh ../shared/data/scenes -- --supersample 2
#
# Needs: a release build (cargo build --release), python3 with flip-evaluator, pillow, numpy.
set -euo pipefail
cd "$(dirname "$0")/.."
scenes=${1:-../shared/data/scenes}
shift || true
[ "${1:-}" = "--" ] && shift
scorer=${SCORER:-$scenes/../../tools/score.py}
[ -f "$scorer" ] || { echo "error: scorer not found at $scorer (set SCORER=path/to/score.py)" >&2; exit 1; }
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
out=$(mktemp -d)
echo "| scene | region FLIP | frame FLIP | frame PSNR (dB) | render s |"
echo "|---|---|---|---|---|"
for dir in "$scenes"/*/; do
  name=$(basename "$dir")
  [ -f "$dir/session.toml" ] || continue
  start=$(date +%s%N)
  ./target/release/mrshade render "$dir/session.toml" -q -o "$out/$name.png" "$@"
  secs=$(( ($(date +%s%N) - start) / 1000000 ))
  python3 "$scorer" "$dir" "$out/$name.png" --json |
    python3 -c "import json,sys; r=json.load(sys.stdin); print('| $name | %.3f | %.3f | %.1f | %.2f |' % (r['flip_region'], r['flip_frame'], r['psnr_frame'], $secs / 1000))"
done
echo
echo "Images in $out"
