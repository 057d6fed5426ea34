#!/bin/bash
# issue 21, branch bake5, payload 2: the caller's process released at the file (svo_bake's detached front), against
# main's binary in turn. M = main's svo_bake (527d0fd); D = the branch (the front released once the output is
# renamed; the teardown and the replaced file's release in the bake's own process after it; the instance made
# without enumerating its extensions first); D0 = D with main's instance start. Whole processes from the shell;
# A/B rounds with 0.3 s between processes (no process overlaps the last one's detached teardown), then runs back
# to back (each process right after the last: the detached teardown beside the next process's start).
S0=$SECONDS; LIMIT=${LIMIT:-95}
T=/tmp/${NAME:-bake5}; rm -rf $T; mkdir -p $T/o
for f in *.gz; do gzip -dc $f > $T/${f%.gz}; done; chmod +x $T/svo_bake* 2>/dev/null
cp cornell.svo $T/
ARGS=${BAKE_ARGS:-"--grid 8,8,8 --res 128 --spp 64 -q -v"}
echo "== $(date -u +%T) $(nproc) CPUs, uptime: $(uptime)"
echo "== GPU: $(nvidia-smi --query-gpu=name,driver_version,persistence_mode,pstate,clocks.sm,clocks.max.sm --format=csv,noheader 2>&1 | head -1)"
: > $T/runs.txt
# run TAG BIN OUT full [env...]
run() {
  local tag=$1 bin=$2 out=$3 full=$4; shift 4
  local s=$EPOCHREALTIME
  env X=0 "$@" timeout 30 $bin $T/cornell.svo $out $ARGS > $T/run.log 2>&1; local rc=$?
  local e=$EPOCHREALTIME
  local w=$(( (${e/./} - ${s/./} + 500) / 1000 ))
  local tl=$(sed -n 's/^timeline: s since main(): //p' $T/run.log)
  local gt=$(sed -n 's/.*GPU trace \([0-9.]*\) s, filter \([0-9.]*\) s, copy \([0-9.]*\) s, busy \([0-9]*\)%.*/\1 \2 \3 \4/p' $T/run.log | head -1)
  local oe=$(sed -n "s/.*the output's end \([0-9.]*\) s (last blocks \([0-9.]*\) s, CRC, sync and rename \([0-9.]*\) s).*/\1 \2 \3/p" $T/run.log)
  local vk=$(sed -n 's/.*(Vulkan \([0-9.]*\) s; waited \([0-9.]*\) s).*/\1 \2/p' $T/run.log)
  local su=$(sed -n 's/.*, setup \([0-9.]*\) s (context.*loop \([0-9.]*\) s.*/\1 \2/p' $T/run.log)
  local k=$(sed -n 's/.*kernel: \(.*\)$/\1/p' $T/run.log)
  local same="-"; [ -e $T/ref.probes ] && { cmp -s $T/ref.probes $out && same=same || same=DIFFER; }
  echo "  $tag rc=$rc wall $w ms $same; $tl; trace/filter/copy/busy $gt; Vulkan/waited $vk; setup/loop $su; end/last/commit $oe; $k"
  [ $full -ge 1 ] && grep -E "^(gpu|close):" $T/run.log | sed 's/^/    /'
  [ $rc = 0 ] || tail -5 $T/run.log | sed 's/^/    ! /'
  [ $rc = 0 ] && echo "$tag $w $(echo $gt | cut -d' ' -f1) $(echo $tl | sed 's/[a-z ]*\([0-9.][0-9.]*\),*/\1 /g')" >> $T/runs.txt
}
echo "== 1: each binary's first process (this machine's first Vulkan process is M's; a binary's kernels are compiled on its first run: the driver's cache is per executable)"
run M1 $T/svo_bake.main $T/o/M.probes 1
cp $T/o/M.probes $T/ref.probes
run D1 $T/svo_bake.D $T/o/D.probes 1; sleep 1
run Z1 $T/svo_bake.D0 $T/o/Z.probes 1; sleep 1
run D2 $T/svo_bake.D $T/o/D.probes 1; run M2 $T/svo_bake.main $T/o/M.probes 1
echo "== 2: rounds M D Z (Z = D0), order rotated, 0.3 s between processes"
V=(M D Z)
one() {
  case $1 in
    M) run M $T/svo_bake.main $T/o/M.probes 0;;
    D) run D $T/svo_bake.D $T/o/D.probes 0;;
    Z) run Z $T/svo_bake.D0 $T/o/Z.probes 0;;
  esac
  sleep 0.3
}
for r in $(seq 1 15); do
  (( SECONDS - S0 > LIMIT - 40 )) && { echo "== time: stopped before round $r"; break; }
  echo "= round $r ($((SECONDS - S0)) s)"
  for k in 0 1 2; do one ${V[$(( (k + r) % 3 ))]}; done
done
echo "== 3: back to back, 6 processes each: M then D (each right after the last)"
for i in 1 2 3 4 5 6; do run MB $T/svo_bake.main $T/o/M.probes 0; done
sleep 0.3
for i in 1 2 3 4 5 6; do run DB $T/svo_bake.D $T/o/D.probes 0; done
sleep 0.5
echo "== 4: empty shader caches: M, then D, each in a cache of its own; then D again in its cache 1 s later (bake() compiled on after D's caller was released?)"
for i in 1 2; do
  (( SECONDS - S0 > LIMIT - 8 )) && { echo "== time: stopped"; break; }
  mkdir -p $T/cm$i $T/cd$i
  run MC $T/svo_bake.main $T/o/M.probes 1 __GL_SHADER_DISK_CACHE_PATH=$T/cm$i; sleep 0.5
  run DC $T/svo_bake.D $T/o/D.probes 1 __GL_SHADER_DISK_CACHE_PATH=$T/cd$i; sleep 1
  run DW $T/svo_bake.D $T/o/D.probes 1 __GL_SHADER_DISK_CACHE_PATH=$T/cd$i; sleep 0.5
done
echo "== medians by tag (n; wall ms min-max; GPU trace s; timeline since main(): read placed ready from setup loop-end renamed released-or-joined)"
for tag in M D Z MB DB MC DC DW; do
  awk -v t=$tag '$1==t' $T/runs.txt > $T/t.txt; n=$(wc -l < $T/t.txt); (( n )) || continue
  line="$tag n=$n"
  for c in 2 3 4 5 6 7 8 9 10 11; do
    v=($(awk -v c=$c '{print $c}' $T/t.txt | sort -g)); k=${#v[@]}
    if (( k % 2 )); then m=${v[$((k/2))]}; else m=$(awk -v a=${v[k/2-1]} -v b=${v[k/2]} 'BEGIN{printf "%.4g", (a+b)/2}'); fi
    line="$line $m"; [ $c = 2 ] && line="$line (${v[0]}-${v[k-1]})"
  done
  echo "$line"
done
sleep 0.5; echo "== processes left: $(ps -eo stat,cmd | grep -c '[s]vo_bake')"
echo "== done $(date -u +%T) ($((SECONDS - S0)) s)"
