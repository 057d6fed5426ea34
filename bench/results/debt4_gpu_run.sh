#!/bin/bash
# debt4 (issues 18 and 21 debt): entry_tau precise in every kernel (render/shaders/trace_common.glsl) and the
# bake's compact beam walk from render/shaders/beam_walk.glsl (probes/shaders/probe_beam.comp).
# A = main 396b0f0's test_render_gpu, B = branch debt4's test binaries (build-gpu: no OIIO, OpenVDB, glTF, MPI);
# the deep tests in turn B A B A, then B's compact bakes (probe_beam), the passes (frame, gbuffer) and the rest
# of test_render_gpu (no corpus here).
T=/tmp/debt4; rm -rf $T; mkdir -p $T/a $T/b
for f in a/*.gz b/*.gz; do gzip -dc $f > $T/${f%.gz}; done; chmod +x $T/a/* $T/b/*
echo "== machine: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1); $(nproc) CPUs; $(date -u)"
s0=$(date +%s); LIMIT=${LIMIT:-56}; n=0
runt() { # tag test VX_TEST_ONLY
  local l=$(( LIMIT - ($(date +%s) - s0) )); [ $l -gt 3 ] || { echo "== $1 $2: no time left"; return; }
  n=$((n + 1)); local log=$T/$n.$1.$2.log s=$(date +%s)
  (cd $T && VX_TEST_ONLY=$3 timeout $l $T/$1/$2 > $log 2>&1); local rc=$?
  echo "== $1 $2 ${3:+($3) }rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed, .* failed' $log | tail -1)"
  grep -o "^device: [^[]*" $log | head -1
  grep -o "deep octrees, strict rule: [a-z0-9 ,]*\|deep float, depth [0-9]*: close-ups [^;]*; [^)]*), far view [0-9]* of [0-9]* ([0-9.]*%)" $log
  grep -o "stack levels: depth [0-9]* view [0-9]* .*mismatched" $log | awk '{m += $(NF-1); v++} END {if (v) print "stack levels: " v " views, " m " mismatched pixels"}'
  grep -o "probe bake ([^)]*): [a-zA-Z ]*; compact without its beam: [A-Z a-z]*" $log | sort | uniq -c
  [ $rc != 0 ] && { grep -o "CHECK failed: .\{0,200\}" $log | head -12; tail -3 $log; }
}
D=test_deep_octrees,test_deep_float,test_stack_levels
runt b test_render_gpu $D
runt a test_render_gpu $D
runt b test_render_gpu $D
runt a test_render_gpu $D
runt b test_compact_passes _bakes
runt b test_passes
runt b test_render_gpu test_empty,test_axis,test_diagonal,test_ray_origins,test_eye,test_grazing,test_transforms,test_precise,test_many,test_far,test_instanced,test_frames,test_modes,test_screen,test_path,test_deep_without
echo "== end $(( $(date +%s) - s0 )) s"
