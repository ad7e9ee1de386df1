#!/usr/bin/env bash
# The committed scenes/hall/ files are what tools/make-hall writes: regenerating
# them into a scratch folder must give the same bytes; and their triangles are wound
# as their normals point (hall_winding_check.py).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$root/tools/make-hall" --out "$tmp" >/dev/null
status=0
for f in "$tmp"/*; do
  name=$(basename "$f")
  if ! cmp -s "$f" "$root/scenes/hall/$name"; then
    echo "hall_scenes_test: scenes/hall/$name differs from what tools/make-hall writes" >&2
    status=1
  fi
done
for f in "$root"/scenes/hall/*; do
  name=$(basename "$f")
  # hall_dense.*: written on demand by make-hall --dense (git-ignored, 60 MB).
  case "$name" in README.md | LICENSE.md | *.png.md | hall_dense.*) continue ;; esac
  [ -e "$tmp/$name" ] || { echo "hall_scenes_test: scenes/hall/$name is not written by tools/make-hall" >&2; status=1; }
done
"$root/.venv/bin/python" "$root/tests/tools/hall_winding_check.py" || status=1
[ $status -eq 0 ] && echo "hall_scenes_test: $(ls "$tmp" | wc -l) files as committed"
exit $status
