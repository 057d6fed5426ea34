#!/bin/bash
# lvp1 (issue 21, seventeenth sitting), batch 2 (limit 80 s): the branch's final form against main on the H200. trace.comp's float SPIR-V
# changes (TRACE_STACK_SELECTS: the walk's stack as selects where NODES_FILE, i.e. CPU devices), but its
# specialisation for GPUs is main's after optimisation. Expect B = A. test_render_gpu's test_stack_levels makes a
# second device with the file's node form: the ladder (NODES_FILE) then runs on the H200 too, against the GPU form.
# A = main 46eb6d3 (bench/out/base/bin), B = lvp1 (bench/out/lvp1, gz'd), alternated process by process.
# 1: eph_monu1, eph_menger, 1920x1080, 3 views, A B A B (ESVO included). 2: --generate --no-esvo (terrain1024
#    DEEP 1, terrain4096 DEEP 2), A B A B. 3: B's test_render_gpu.
R=bench/out/lvp1; A=bench/out/base/bin; T=/tmp/lvp1; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$A
for f in $R/*.gz; do gzip -dc $f > $T/$(basename $f .gz) && chmod +x $T/$(basename $f .gz); done
SIZE=1920x1080; WU=0.1; RUNS=10
s0=$(date +%s)
left() { echo $(( ${1} - ($(date +%s) - s0) )); }
echo "== lvp1 B $(cat $R/REV | tr '\n' ' ') on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
echo "== 1: eph_monu1, eph_menger, A B A B (with ESVO) $(date -u +%T)"
for round in 1 2; do
  for who in A B; do
    l=$(left 34); [ $l -gt 3 ] || break 2
    bin=$A/render_bench; [ $who = B ] && bin=$T/render_bench
    echo "-- round $round $who $(date -u +%T)"
    timeout $l $bin --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup $R/eph_monu1.vox $R/eph_menger.vox \
      2>&1 | grep -v '^shadow map' | cut -c1-170
  done
done
echo "== 2: terrains (--generate --no-esvo), A B A B $(date -u +%T)"
for round in 1 2; do
  for who in A B; do
    l=$(left 62); [ $l -gt 3 ] || break 2
    bin=$A/render_bench; [ $who = B ] && bin=$T/render_bench
    echo "-- round $round $who $(date -u +%T)"
    timeout $l $bin --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup \
      2>&1 | grep -E '^terr|far pointer' | cut -c1-200
  done
done
echo "== 3: B's test_render_gpu $(date -u +%T)"
l=$(left 78); if [ $l -gt 3 ]; then
  s=$(date +%s); (cd $T && timeout $l ./test_render_gpu > $T/trg.log 2>&1); rc=$?
  echo "== test_render_gpu rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/trg.log | tail -1)"
  grep -E '^stack levels' $T/trg.log
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/trg.log | head -30; tail -5 $T/trg.log; }
fi
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
