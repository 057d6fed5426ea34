#!/bin/bash
# lvp2 (issue 21, eighteenth sitting), batch 2 (limit 100 s; a4ced5b: test_deep_octrees also bounds the forced float variant at 2% of the pixels): the stack's ladder in the rebased walk (DEEP 2) on
# CPU devices again, now over every index a model of up to 21 levels pushes (S_MAX - 20 up; fbb131c's S_MAX - 15 up
# dropped the pushes of the forced float variant's 17-21-level models). The H200 check of the file's form: the
# branch's test_render_gpu with VX_GPU_NODE_FORM=file (the ladder on a GPU; test_deep_octrees forces the float
# variant on 17-21 levels, test_stack_levels now 7-21 levels against the GPU form's device) and in the default form.
# The GPU form's SPIR-V is main's (bench/results/lvp2_spv_gpuform.sh: 30 specialised kernels the same).
R=bench/out/lvp2; A=bench/out/base/bin; T=/tmp/lvp2; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$A
for f in $R/*.gz; do gzip -dc $f > $T/$(basename $f .gz) && chmod +x $T/$(basename $f .gz); done
export VX_CORPUS_DIR=$PWD/$R/corpus
s0=$(date +%s)
left() { echo $(( ${1} - ($(date +%s) - s0) )); }
echo "== lvp2 $(cat $R/REV | tr '\n' ' ') on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
runt() { # form limit
  local l=$(left $2); [ $l -gt 4 ] || { echo "== test_render_gpu ($1 form): no time left"; return; }
  local fe=X=0; [ $1 = file ] && fe=VX_GPU_NODE_FORM=file
  local s=$(date +%s); (cd $T && env $fe timeout $l ./test_render_gpu > $T/trg.$1.log 2>&1); local rc=$?
  echo "== test_render_gpu ($1 form) rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/trg.$1.log | tail -1)"
  grep -a -E '^deep octrees|float variant [0-9]* of|^deep float, depth 16|^stack levels: depth (1[6-9]|2[01])' $T/trg.$1.log | cut -c1-160
  grep -E 'differ between|CHECK failed' $T/trg.$1.log | head -12 | cut -c1-220
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/trg.$1.log | head -30; tail -5 $T/trg.$1.log; }
  [ -n "$OUTDIR" ] && cp $T/trg.$1.log $OUTDIR/ 2>/dev/null
}
runt file 50
runt gpu 97
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
