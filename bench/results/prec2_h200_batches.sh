#!/bin/bash
# bench/results/prec2_h200_batches.sh: the payload script of branch prec2 as run on the H200 (run.sh in
# bench/out/gpuq/prec2, with bin/*.gz and corpus/vox/eph_monu1.vox, ogt_chr_knight.vox); PART=1|2|3: batches 1, 5, 6;
# budgets 80, 60 and 18 s. Logs: prec2_h200_b1.txt, prec2_h200_b2.txt, prec2_h200_b3.txt.
# issue 18, branch prec2: the walk non-contracted in every kernel whose results are compared between the layouts
# or between the separate passes and frame.comp (cmake/shaders.cmake VX_WALK_PRECISE_KERNELS: + direct, ao, photon,
# gb_offset_point). bin/: test_new = test_compact_passes of prec2 (its kernels); test_diag = the same test source
# with main's 527d0fd kernels (every SPIR-V main's); passes_bench_new / _main: prec2's passes_bench.c (+ the row
# "=gbuffer,direct,ao") over prec2's / main's kernels; (batch 1 only: passes_bench_all, prec2's with trace.comp in
# the list too: its single-shader row, the cost of the non-contracted walk in the primary-ray benchmark's kernel;
# test_render_gpu_main, main's; test_diag); test_passes_new / _main: test_passes over prec2's / main's kernels.
# PART (env, default 3) picks the steps; BUDGET (s): the limit given in prec2.ready less 2-5.
HERE=$(dirname "$(readlink -f "$0")")
T=/tmp/${NAME:-prec2}
rm -rf $T; mkdir -p $T
for f in bin/*.gz; do gunzip -c $f > $T/$(basename $f .gz); chmod +x $T/$(basename $f .gz); done
cp -r corpus $T/
cd $T
PART=${PART:-3} # parts 1 and 2 ran in batches 1 and 5 (logs bench/results/prec2_h200_b1.txt, _b2.txt)
echo "== machine: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1); $(nproc) CPUs; $(date -u +%T); part $PART"
t0=$(date +%s)
BUDGET=${BUDGET:-$(case $PART in 1) echo 80;; 2) echo 60;; *) echo 18;; esac)}
# SB and run LIMIT ARGS... (a step within the budget, its rc and time): cones_h200_batches.sh's, which the payload
# held as its own lines; taken from there (this file lies beside it in bench/results)
eval "$(sed -n '/^SB=""; command -v stdbuf/p; /^run() {/,/^}/p' "$HERE/cones_h200_batches.sh")"
export VX_CORPUS_DIR=$T/corpus
PB="--runs 9 --size 1920x1080 corpus/vox/eph_monu1.vox"
bench() { # ROUNDS
    for r in $(seq $1); do
      for b in passes_bench_main passes_bench_new; do
        echo "-- $b round $r"; run 14 ./$b $PB 2>&1 | grep -v "shadow map check"
      done
    done
}
part1() { # batch 1 (bin/ also held test_spirv_precise, test_diag, passes_bench_all, test_render_gpu, _main)
    ./test_spirv_precise 2>&1 | tail -1
    echo "== test_compact_passes room frames, prec2 (test_new)"
    VX_TEST_ONLY=room_frames run 34 ./test_new 2>&1 | grep -v "^\[ run"
    echo "== test_compact_passes room frames, main's kernels (test_diag)"
    VX_TEST_ONLY=room_frames run 22 ./test_diag 2>&1 | grep -v "^\[ run"
    echo "== passes_bench $PB: main's kernels (passes_bench_main), prec2's (passes_bench_new), in turn"
    bench 1 # batch 1: for b in passes_bench_main passes_bench_new passes_bench_all
    echo "== test_compact_passes generated frames, prec2, as time allows"
    VX_TEST_ONLY=generated_frames run 20 ./test_new 2>&1 | grep -v "^\[ run"
    echo "== end $(( $(date +%s) - t0 )) s"
}
part2() { # batch 5 (bin/: test_new, test_passes_new, _main, passes_bench_new, _main)
    echo "== test_compact_passes room and generated GI frames (gi=photons, then gi=cones), prec2 (test_new)"
    VX_TEST_ONLY=room_gi_frames,generated_gi_frames run 22 ./test_new 2>&1 | grep -v "^\[ run"
    for b in test_passes_new test_passes_main; do
      echo "== test_passes default_equals_color (trace.comp against the passes) and merged_equals_separate: $b"
      VX_TEST_ONLY=default_equals_color,merged_equals_separate run 13 ./$b 2>&1 | grep -v "^\[ run"
    done
    echo "== passes_bench $PB: main's kernels (passes_bench_main), prec2's (passes_bench_new), in turn"
    bench 1
    echo "== end $(( $(date +%s) - t0 )) s"
}
part3() { # batch 6 (bin/: test_new)
    echo "== test_compact_passes generated GI frames (gi=photons, then gi=cones), prec2 (test_new)"
    VX_TEST_ONLY=generated_gi_frames run 18 ./test_new 2>&1 | grep -v "^\[ run"
    echo "== end $(( $(date +%s) - t0 )) s"
}
part$PART
