#!/bin/bash
# bench/results/cones_h200_batches.sh - the two device scripts of issue 18, branch cones, as run (each was the payload's
# run.sh; they shared everything but the budget and the body, kept here once): `bash cones_h200_batches.sh 1|2`.
# Logs: cones_h200_batch1.txt, cones_h200_batch2.txt.
#
# Batch 1:
# (as run, 2026-12-01 09:59 UTC, one fresh H200: bin/ held test_diag = test_compact_passes of 48f6232's test with
# every kernel main's 1695247 (the shader changes stashed; SPIR-V headers compared), test_fix = 48f6232 (CELL_HITS in
# the cones' kernels), gi_bench_base = gi_bench of main's sources, gi_bench_fix = 48f6232's; corpus/vox: eph_monu1.vox,
# ogt_chr_knight.vox. Log: cones_h200_batch1.txt)
# issue 18, branch cones: the layouts' differences in the cones pass (and the other GI and pass paths) on the
# device, with main's kernels (test_diag: the branch's diagnostic test, every kernel's SPIR-V main's) and the fix's
# (test_fix); then the cones pass's cost, main (gi_bench_base) against the fix (gi_bench_fix), in turn.
#
# Batch 2:
# (as run, 2026-12-01 10:22 UTC, one fresh H200: bin/ held test_A = test_compact_passes of 98255da (WALK_PRECISE),
# gi_bench_A = 98255da's gi_bench, gi_bench_base as batch 1's (main's sources); corpus/vox as batch 1.
# Log: cones_h200_batch2.txt)
# issue 18, branch cones, batch 2: the fix (WALK_PRECISE in gbuffer.comp, frame.comp and the cones' kernels:
# the walk not contracted) on the H200: test_compact_passes' frames (room, generated, corpus: G-buffer shows,
# passes, frame lights, cones, photons) in both layouts; then the cost, main (gi_bench_base) against the fix
# (gi_bench_A), gbuffer,direct,gi=cones at 1920x1080 on eph_monu1, processes in turn (A B A B).
T=/tmp/${NAME:-cones}
rm -rf $T; mkdir -p $T
for f in bin/*.gz; do gunzip -c $f > $T/$(basename $f .gz); chmod +x $T/$(basename $f .gz); done
cp -r corpus $T/ 2>/dev/null
cd $T
echo "== machine: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1); $(nproc) CPUs; $(date -u +%T)"
t0=$(date +%s)
BUDGET=${BUDGET:-$([ "$1" = 2 ] && echo 80 || echo 115)} # batch 1: 115 s, batch 2: 80 s
SB=""; command -v stdbuf > /dev/null && SB="stdbuf -oL -eL" # the tests' lines even where a timeout ends them
run() { # LIMIT ARGS...
    lim=$1; shift
    left=$(( BUDGET - ($(date +%s) - t0) ))
    [ $left -lt 4 ] && { echo "SKIPPED (time): $*"; return; }
    [ $lim -gt $left ] && lim=$left
    s=$(date +%s%N)
    timeout $lim $SB "$@"
    rc=$?; echo "rc $rc $(( ($(date +%s%N) - s) / 1000000 )) ms (at $(( $(date +%s) - t0 )) s)"
}
export VX_CORPUS_DIR=$T/corpus
batch1() {
    echo "== test_compact_passes (room), main's kernels (test_diag)"
    VX_TEST_ONLY=test_room run 55 ./test_diag 2>&1 | grep -v "^\[ run"
    echo "== test_compact_passes (room), the fix (test_fix)"
    VX_TEST_ONLY=test_room run 35 ./test_fix 2>&1 | grep -v "^\[ run"
    echo "== gi_bench --methods cones: A = main (gi_bench_base), B = the fix (gi_bench_fix), A B A B"
    G="--ref-spp 8 --runs 7 --warm 50 --methods cones,cones-half"
    for r in 1 2; do
      for b in gi_bench_base gi_bench_fix; do
        echo "-- $b round $r metal-room"; run 12 ./$b $G --name metal-room metal-room 1920x1080 2>&1 | grep -v "^#"
        echo "-- $b round $r monu1"; run 12 ./$b $G --name monu1 corpus/vox/eph_monu1.vox 1920x1080 2>&1 | grep -v "^#"
      done
    done
    echo "== test_compact_passes (generated, corpus), main's kernels then the fix, as time allows"
    VX_TEST_ONLY=test_generated,test_corpus run 30 ./test_diag 2>&1 | grep -v "^\[ run"
    VX_TEST_ONLY=test_generated,test_corpus run 30 ./test_fix 2>&1 | grep -v "^\[ run"
    echo "== end $(( $(date +%s) - t0 )) s"
}
batch2() {
    echo "== test_compact_passes room frames, the fix"
    VX_TEST_ONLY=room_frames run 32 ./test_A 2>&1 | grep -v "^\[ run"
    echo "== test_compact_passes generated frames, the fix"
    VX_TEST_ONLY=generated_frames run 16 ./test_A 2>&1 | grep -v "^\[ run"
    echo "== gi_bench --methods cones, eph_monu1 1920x1080: A = main (gi_bench_base), B = the fix (gi_bench_A)"
    G="--ref-spp 1 --runs 9 --warm 50 --methods cones"
    for r in 1 2; do
      for b in gi_bench_base gi_bench_A; do
        echo "-- $b round $r"; run 9 ./$b $G --name monu1 corpus/vox/eph_monu1.vox 1920x1080 2>&1 | grep -v "^| scene\|^|---\|| reference |"
      done
    done
    echo "== test_compact_passes corpus frames, the fix, as time allows"
    VX_TEST_ONLY=corpus_frames run 30 ./test_A 2>&1 | grep -v "^\[ run"
    echo "== end $(( $(date +%s) - t0 )) s"
}
batch$1
