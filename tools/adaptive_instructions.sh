#!/usr/bin/env bash
# Instructions per `AdaptiveTables::new` (docs/measured.md's preprocessing table): cachegrind's user
# instructions of `examples/adaptive_preprocess MESH ISO 3` minus `... 1`, halved (two builds),
# one thread; deterministic, so binaries of two commits compare in one run whatever the load.
#   tools/adaptive_instructions.sh ISO MESH BINARY... [-- FLAG...]   (copies of
#   target/release/examples/adaptive_preprocess; FLAGs passed to each, e.g. `-- no-lattice`)
set -euo pipefail
iso=$1 mesh=$2
shift 2
bins=() flags=()
while (($#)); do
  if [[ $1 == -- ]]; then
    shift
    flags=("$@")
    break
  fi
  bins+=("$1")
  shift
done
for bin in "${bins[@]}"; do
  ir() {
    RAYON_NUM_THREADS=1 valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null \
      "$bin" "$mesh" "$iso" "$1" "${flags[@]}" 2>&1 >/dev/null | awk '/I *refs/ { gsub(",", "", $NF); print $NF }'
  }
  r1=$(ir 1)
  r3=$(ir 3)
  echo "$bin iso=$iso $(basename "$mesh") ${flags[*]}: $(( (r3 - r1) / 2 )) instructions per build"
done
