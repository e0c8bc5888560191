#!/bin/sh
# Seeds the corpus from the OpenSubdiv shapes (files up to 32 KB) and the embedded meshes, then
# fuzzes the OBJ + tag parser and validation for FUZZ_SECONDS (default 600) on nightly.
set -e
cd "$(dirname "$0")/.."
OSD="${OSD:-../shared/meshes/osd}"
mkdir -p fuzz/corpus/obj_parse
for f in "$OSD"/*.obj assets/*.obj; do
    [ "$(stat -c %s "$f")" -le 32768 ] && cp "$f" fuzz/corpus/obj_parse/
done
cargo +nightly fuzz run obj_parse fuzz/corpus/obj_parse -- \
    -max_total_time="${FUZZ_SECONDS:-600}" -max_len=32768 -timeout=10 -rss_limit_mb=2048 \
    -malloc_limit_mb=512 -print_final_stats=1
