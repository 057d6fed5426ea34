#!/bin/bash
# issue 21, branch bake5, payload 1: where the warm svo_bake process's time goes on this machine, phase by phase.
# M = main's svo_bake (527d0fd); A = the branch's (the same code plus an exploration switch); X = A with
# VX_BAKE_GPU_EXIT=1 (the GPU left to the process's exit, no driver teardown); N = M writing to a name that does
# not exist (no rename over the last file); Y = A with VX_GPU_EXT_PROBE=0. vktime.so (bench/results/bake5_vktime.c) times the Vulkan and file calls.
# A sampler (nvidia-smi -lms 20) logs the GPU's clocks through the runs. Whole processes from the shell.
S0=$SECONDS; LIMIT=${LIMIT:-95}
T=/tmp/${NAME:-bake5}; rm -rf $T; mkdir -p $T/o
for f in *.gz; do gzip -dc $f > $T/${f%.gz}; done; chmod +x $T/svo_bake* $T/floor 2>/dev/null
cp cornell.svo $T/
ARGS=${BAKE_ARGS:-"--grid 8,8,8 --res 128 --spp 64 -q -v"}
echo "== $(date -u +%T) $(nproc) CPUs, uptime: $(uptime)"
echo "== GPU: $(nvidia-smi --query-gpu=name,driver_version,persistence_mode,pstate,clocks.sm,clocks.max.sm,clocks.mem,power.draw,temperature.gpu --format=csv,noheader 2>&1 | head -1)"
echo "== shader caches: $(du -sk ~/.nv ~/.cache/nvidia 2>/dev/null | tr '\n' ' ')"
hms() { date +%H:%M:%S.%N | awk -F: '{printf "%.3f", $1*3600+$2*60+$3}'; }
SB=""; command -v stdbuf > /dev/null && SB="stdbuf -oL"
$SB nvidia-smi --query-gpu=timestamp,pstate,clocks.sm,clocks.mem,utilization.gpu,power.draw --format=csv,noheader,nounits -lms 20 > $T/smi.csv 2>$T/smi.err &
SMI=$!
sleep 1
: > $T/runs.txt
# run TAG BIN OUT full(0|1|2: 2 with vktime) [env...]
run() {
  local tag=$1 bin=$2 out=$3 full=$4; shift 4
  local pre=X=0; [ $full = 2 ] && pre=LD_PRELOAD=$T/vktime.so
  local h0=$(hms) s=$EPOCHREALTIME
  env $pre "$@" timeout 30 $bin $T/cornell.svo $out $ARGS > $T/run.log 2>&1; local rc=$?
  local e=$EPOCHREALTIME h1=$(hms)
  local w=$(( (${e/./} - ${s/./} + 500) / 1000 ))
  local tl=$(sed -n 's/^timeline: s since main(): //p' $T/run.log)
  local gt=$(sed -n 's/.*GPU trace \([0-9.]*\) s.*/\1/p' $T/run.log | head -1)
  local oe=$(sed -n "s/.*the output's end \([0-9.]*\) s (last blocks \([0-9.]*\) s, CRC, sync and rename \([0-9.]*\) s).*/\1 \2 \3/p" $T/run.log)
  local vk=$(sed -n 's/.*(Vulkan \([0-9.]*\) s; waited \([0-9.]*\) s).*/\1 \2/p' $T/run.log)
  local su=$(sed -n 's/.*, setup \([0-9.]*\) s (context \([0-9.]*\) of it sun map \([0-9.]*\), pipelines \([0-9.]*\), slots \([0-9.]*\)).*loop \([0-9.]*\) s.*/\1 \2 \3 \4 \5 \6/p' $T/run.log)
  local same="-"; [ -e $T/ref.probes ] && { cmp -s $T/ref.probes $out && same=same || same=DIFFER; }
  echo "  $tag rc=$rc wall $w ms [$h0-$h1] $same; timeline $tl; GPU trace $gt; Vulkan/waited $vk; setup/ctx/sun/pipes/slots/loop $su; end/last/commit $oe"
  [ $full -ge 1 ] && grep -E "^(gpu|bake|sun map|close|batch):" $T/run.log | sed 's/^/    /'
  [ $full = 2 ] && grep "^vkt:" $T/run.log | sed 's/^/    /'
  [ $rc = 0 ] || tail -5 $T/run.log | sed 's/^/    ! /'
  [ $rc = 0 ] && echo "$tag $w $h0 $h1 $gt $(echo $tl | sed 's/[a-z ]*\([0-9.][0-9.]*\),*/\1 /g') | $oe" >> $T/runs.txt
}
echo "== 1: the payload's first bake (M, default cache), then A, then M (cache state)"
run M1 $T/svo_bake.main $T/o/M.probes 1
cp $T/o/M.probes $T/ref.probes
run A1 $T/svo_bake $T/o/A.probes 1
run M2 $T/svo_bake.main $T/o/M.probes 1
echo "== 2: the driver's floor (instance, device, two trivial pipelines, teardown), three processes"
for i in 1 2 3; do s=$EPOCHREALTIME; LD_PRELOAD=$T/vktime.so $T/floor > $T/f.log 2>&1; e=$EPOCHREALTIME
  echo "  floor wall $(( (${e/./} - ${s/./} + 500) / 1000 )) ms: $(grep -v '^vkt: fn' $T/f.log | grep -v 'vkt: at' | tr '\n' ' ')"; done
echo "== 3: M, X and Y under vktime (each wrapped call's host time), two each"
for i in 1 2; do run VM $T/svo_bake.main $T/o/M.probes 2; run VX $T/svo_bake $T/o/X.probes 2 VX_BAKE_GPU_EXIT=1; run VY $T/svo_bake $T/o/Y.probes 2 VX_GPU_EXT_PROBE=0; done
echo "== 4: rounds M A X N Y, order rotated (Y = A with VX_GPU_EXT_PROBE=0: the instance without enumerating its extensions first)"
V=(M A X N Y)
one() {
  case $1 in
    M) run M $T/svo_bake.main $T/o/M.probes 0;;
    A) run A $T/svo_bake $T/o/A.probes 0;;
    X) run X $T/svo_bake $T/o/X.probes 0 VX_BAKE_GPU_EXIT=1;;
    N) rm -f $T/o/N.probes; run N $T/svo_bake.main $T/o/N.probes 0;;
    Y) run Y $T/svo_bake $T/o/Y.probes 0 VX_GPU_EXT_PROBE=0;;
  esac
}
for r in $(seq 1 9); do
  (( SECONDS - S0 > LIMIT - 35 )) && { echo "== time: stopped before round $r"; break; }
  echo "= round $r ($((SECONDS - S0)) s)"
  for k in 0 1 2 3 4; do one ${V[$(( (k + r) % 5 ))]}; done
done
echo "== 5: the GPU's clock phase: M after 2 s idle, then M at once after it (three pairs)"
for i in 1 2 3; do sleep 2; run I $T/svo_bake.main $T/o/M.probes 0; run B $T/svo_bake.main $T/o/M.probes 0; done
echo "== 6: X's first process in an empty shader cache, then A in the same cache (does X keep the driver's cache?)"
mkdir -p $T/c1
run XC $T/svo_bake $T/o/X.probes 1 VX_BAKE_GPU_EXIT=1 __GL_SHADER_DISK_CACHE_PATH=$T/c1
run AC $T/svo_bake $T/o/A.probes 1 __GL_SHADER_DISK_CACHE_PATH=$T/c1
kill $SMI 2>/dev/null; wait $SMI 2>/dev/null
echo "== medians by tag (n; wall ms min-max; GPU trace s; timeline since main(): read placed ready from setup loop-end renamed joined)"
for tag in M A X N Y I B VM VX VY; do
  awk -v t=$tag '$1==t' $T/runs.txt > $T/t.txt; n=$(wc -l < $T/t.txt); (( n )) || continue
  line="$tag n=$n"
  for c in 2 5 6 7 8 9 10 11 12 13; do
    v=($(awk -v c=$c '{print $c}' $T/t.txt | sort -g)); k=${#v[@]}
    if (( k % 2 )); then m=${v[$((k/2))]}; else m=$(awk -v a=${v[k/2-1]} -v b=${v[k/2]} 'BEGIN{printf "%.4g", (a+b)/2}'); fi
    line="$line $m"; [ $c = 2 ] && line="$line (${v[0]}-${v[k-1]})"
  done
  echo "$line"
done
echo "== clocks: per run, the sampler's rows inside [start, end]: SM MHz min/max, pstate, util max; and the row before"
awk -F', ' 'NR==FNR { split($1, a, " "); split(a[2], h, ":"); t = h[1]*3600 + h[2]*60 + h[3]; ts[n] = t; ps[n] = $2; sm[n] = $3; ut[n] = $5; pw[n] = $6; n++; next }
  { lo = 1e9; hi = 0; um = 0; p = ""; before = "";
    for (i = 0; i < n; i++) { if (ts[i] < $3) before = sm[i] "/" ps[i]; if (ts[i] >= $3 && ts[i] <= $4) { if (sm[i] < lo) lo = sm[i]; if (sm[i] > hi) hi = sm[i]; if (ut[i] > um) um = ut[i]; p = p ps[i] } }
    printf "  %s wall %s ms trace %s: SM %s-%s MHz, util max %s%%, before %s\n", $1, $2, $5, lo, hi, um, before }' $T/smi.csv $T/runs.txt | head -70
echo "== sampler: $(wc -l < $T/smi.csv) rows; first $(head -1 $T/smi.csv); errors: $(head -c 200 $T/smi.err)"
echo "== done $(date -u +%T) ($((SECONDS - S0)) s)"
