#!/usr/bin/env bash
# End caps of `--scheme adaptive` (CPU `AdaptiveSurface`, the GPU's construction) beside OpenSubdiv's
# patches, both against the exact limit, at the same points: a K x K grid of each of tessera's end
# caps' own (s, t) at isolation L. One line per (mesh, L): RMS / max distance (fraction of the control
# mesh's bbox diagonal) and RMS / max normal angle (rad), OpenSubdiv then tessera.
#   tools/osd_eval/endcaps.sh OSD_EVAL TESSERA_EXAMPLES_DIR K "L1 L2 ..." MESH.obj... [-- EXTRA FLAGS]
# e.g. tools/osd_eval/endcaps.sh /tmp/osd_eval target/release/examples 9 "1 2 3 4 5" catmark_cube.obj
# EXTRA FLAGS go to adaptive_grid (`single-crease`, `smooth`); `single-crease` also to osd_eval.
set -euo pipefail
osd=$1 ex=$2 k=$3 levels=$4
shift 4
meshes=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do meshes+=("$1"); shift; done
[ $# -gt 0 ] && shift
flags=("$@")
osd_flag=""
for f in "${flags[@]}"; do [ "$f" = single-crease ] && osd_flag=single-crease; done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
here=$(dirname "$0")
for m in "${meshes[@]}"; do
    diag=$(awk '$1=="v"{for(i=2;i<=4;i++){if(!(i in lo)||$i<lo[i])lo[i]=$i;if(!(i in hi)||$i>hi[i])hi[i]=$i}}
        END{print sqrt((hi[2]-lo[2])^2+(hi[3]-lo[3])^2+(hi[4]-lo[4])^2)}' "$m")
    for l in $levels; do
        "$ex/adaptive_grid" "$m" "$l" "endcaps:$k" "${flags[@]}" > "$tmp/t.txt"
        "$ex/adaptive_grid" "$m" "$l" "endcaps:$k" "${flags[@]}" exact > "$tmp/e.txt"
        "$osd" "$m" "$l" - $osd_flag < "$tmp/t.txt" > "$tmp/o.txt" 2>/dev/null
        o=$(python3 "$here/compare.py" "$tmp/e.txt" "$tmp/o.txt" "$diag")
        t=$(python3 "$here/compare.py" "$tmp/e.txt" "$tmp/t.txt" "$diag")
        echo "$(basename "$m" .obj) L$l osd: $o"
        echo "$(basename "$m" .obj) L$l tessera: $t"
    done
done
