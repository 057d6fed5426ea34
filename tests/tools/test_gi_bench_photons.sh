#!/bin/sh
# tests/tools/test_gi_bench_photons.sh BIN_DIR - gi_bench goes on past a
# method that fails: on the helmet (docs/PERFORMANCE.md section 7) photons-fg
# hit lavapipe's loop limit and gi_bench stopped there, so bench/gi_table
# lost the scene's later methods and every later scene. Here the photon
# methods fail on purpose (--photon-radius -1, rejected by
# vx_photon_gi_create) on the small thin-wall scene made by gi_bench: each
# must be reported in its place, the cone rows after them written, and the
# exit status 3 (some method failed), not 1.
set -u
BIN=$1
. "$(dirname "$0")/../common/expect.sh"
expect_status 3 "gi_bench: photon methods fail, exit 3" "$BIN/gi_bench" --ref-spp 2 --runs 1 --threads 1 \
    --methods photons,photons-fg,cones-iso --max-spp photons=1 --max-spp photons-fg=1 --photon-radius -1 \
    --camera 32,20,12,32,46,6 --up 0,0,1 thin-wall 24x16
for m in photons photons-fg; do
    grep -q "^thin-wall: $m - failed at 1 spp (its rows from there left out): photons: .*radius -1" "$T/out" &&
        ok "$m: its failure in the table's text" || bad "$m: no failure line in: $(cat "$T/out")"
    grep -q "thin-wall: $m - 1 spp: photons: " "$T/err" && ok "$m: its failure on stderr" || bad "$m: stderr $(cat "$T/err")"
done
grep -q "^| thin-wall | cones-iso | - | - | 1 |" "$T/out" && ok "cones-iso's row after the failures" ||
    bad "no cones-iso row in: $(cat "$T/out")"
grep -q "^| thin-wall | reference | seed 999 vs 1000 |" "$T/out" && ok "the reference's row" || bad "no reference row"
grep -q "^thin-wall: reference full: the worst pixel holds" "$T/out" && ok "the reference's worst-pixel share" ||
    bad "no worst-pixel share"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
