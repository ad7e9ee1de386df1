#!/usr/bin/env bash
# tools/bench-scale end to end on one small scale hall (10,000 triangles, one run):
# it makes the scene, runs rtgi and the path tracer, and writes results.json with
# sane figures, the table and the plot. Usage: bench_scale_test.sh VOXGI_BINARY
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$("$root/tools/bench-scale" --voxgi "$1" --triangles 10000 --runs 1 --size 32x32 --out "$tmp")
echo "$out"
grep -q "^| 10,[0-9][0-9][0-9] |" <<<"$out" || { echo "bench_scale_test: no table row" >&2; exit 1; }
[ -s "$tmp/scale.png" ] || { echo "bench_scale_test: no plot" >&2; exit 1; }
"$root/.venv/bin/python" - "$tmp/results.json" <<'PY'
import json, sys
rows = json.load(open(sys.argv[1]))["rows"]
assert len(rows) == 1, rows
for mode in ("rtgi", "pathtrace"):
    r = rows[0][mode]
    assert r["triangles"] >= 10000, r
    assert 10 < r["peak_rss_mb"] < 8000, r
    assert 0 < r["wall_s"] < 120 and r["startup_ms"] > 0 and r["frame_ms"] > 0, r
assert rows[0]["rtgi"]["bvh_ms"] > 0, rows[0]["rtgi"]
print("bench_scale_test: results as expected")
PY
