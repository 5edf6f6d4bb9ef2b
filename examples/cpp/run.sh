#!/usr/bin/env bash
# Builds the three programs of examples/cpp/ against an installed mwst and checks what they print
# against the installed command line (the same library):
#   delaunay_points  6 points, 2 inside the hull: 6 triangles of total area 6;
#   refine_polygon   data/Plate.poly (5 holes) at 25 degrees: smallest angle >= 25, and the weights
#                    of `mwst triangulate --method dr --min-angle 25 --json -`;
#   bundle_number    a DR mesh of data/Africa.poly written by `mwst triangulate`: the bundle number
#                    of `mwst bundle --json`.
#   usage: examples/cpp/run.sh PREFIX WORKDIR
#     PREFIX   where mwst is installed (cmake --install BUILD --prefix PREFIX); only it is searched
#     WORKDIR  scratch directory for the example builds and meshes (created)
set -euo pipefail
cd "$(dirname "$0")/../.."
prefix=$(readlink -f "$1")
work=$2
mkdir -p "$work"
work=$(readlink -f "$work")
mwst="$prefix/bin/mwst"
python=/usr/bin/python3

fail() {
  echo "examples/cpp: $*" >&2
  exit 1
}

for example in delaunay_points refine_polygon bundle_number; do
  # CMAKE_PREFIX_PATH is the install prefix alone: the build tree is never registered or searched.
  cmake -S "examples/cpp/$example" -B "$work/$example" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$work/$example.configure.log" 2>&1 ||
    { cat "$work/$example.configure.log" >&2; fail "$example: configure failed"; }
  cmake --build "$work/$example" >"$work/$example.build.log" 2>&1 ||
    { cat "$work/$example.build.log" >&2; fail "$example: build failed"; }
done

out=$("$work/delaunay_points/delaunay_points")
grep -qx '6 vertices, 6 triangles' <<<"$out" || fail "delaunay_points printed: $out"
grep -qx 'area 6' <<<"$out" || fail "delaunay_points printed: $out"
[ "$(grep -c '^triangle ' <<<"$out")" = 6 ] || fail "delaunay_points printed: $out"

out=$("$work/refine_polygon/refine_polygon" data/Plate.poly)
report=$("$mwst" triangulate data/Plate.poly -o "$work/plate" --method dr --min-angle 25 --quiet --json -)
expected=$($python -c '
import json, sys
r = json.load(sys.stdin)
print("%d holes, %d triangles, %d Steiner points, angles %.3f to %.3f degrees" % (5, r["triangles"], r["steiner"], r["min_angle"], r["max_angle"]))
print("weight %.6f = boundary %.6f + interior %.6f" % (r["weight_total"], r["weight_boundary"], r["weight_interior"]))
assert r["min_angle"] >= 25.0, r["min_angle"]
' <<<"$report") || fail "mwst triangulate data/Plate.poly: smallest angle below 25"
[ "$out" = "$expected" ] || fail "refine_polygon printed
$out
but mwst triangulate reports
$expected"

"$mwst" triangulate data/Africa.poly -o "$work/africa" --method dr --quiet
out=$("$work/bundle_number/bundle_number" "$work/africa")
expected=$("$mwst" bundle data/Africa.poly "$work/africa" --json |
  $python -c 'import json, sys; r = json.load(sys.stdin); print("%d triangles: bundle number %d" % (r["triangle_count"], r["bundle_number"]))')
[ "$(head -n 1 <<<"$out")" = "$expected" ] || fail "bundle_number printed '$out', mwst bundle says '$expected'"
grep -q '^witness: the disk centred' <<<"$out" || fail "bundle_number printed no witness: $out"

echo "examples/cpp: the three examples built against $prefix and printed what mwst prints"
