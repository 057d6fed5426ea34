#!/bin/bash
# smap3 (issue 18, branch smap3): the sun's depth map over the compact layout (svo_bake --load models).
# (1) bytes: each scene baked whole (W) and through the model reader (M, compact layout), each with the sun's map
#     and without (Wn, Mn: --no-shadow-map); cmp -l counts the differing bytes; -v's sun map line of each.
# (2) time: the whole process, warm, W and M of the branch and M of main (base: main's binary) in turn, 9 rounds,
#     medians (the first process of each binary and variant, in (1) or a warm-up, not counted).
# (3) eph_monu1's bytes with and without the map (issue 18, bakeq's 64 bytes): three exploration builds of the
#     branch whose smap_tmax drops one part: x1 the own-cube rule (m2), x2 every clip (the SMAP pipeline walks each
#     sun ray whole), x3 the occluder layer (occl); each D against the branch's Wn.
# (4) the passes' direct pass over the compact layout: passes_bench --layout compact --quick (gbuffer, gbuffer+direct
#     merged, the bit check with and without the map), main's binary (no map on compact scenes) and the branch's.
# SMAP3_ARGS / SMAP3_ROUNDS / SMAP3_PB / SMAP3_BUDGET / SMAP3_CAP: smaller runs for the dev VM's lavapipe only (unset on the device).
START=$SECONDS; T=/tmp/$NAME; rm -rf $T; mkdir -p $T
for b in new base x1 x2 x3 pb_new pb_base; do gzip -dc $b.gz > $T/$b && chmod +x $T/$b; done
echo "== $(date -u +%T) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), load $(cut -d' ' -f1-3 /proc/loadavg); new $(cat NEW_REV), base $(cat BASE_REV)"
ARGS=${SMAP3_ARGS:-"--grid 8,8,8 --res 128 --spp 64 -q -v"}
ROUNDS=${SMAP3_ROUNDS:-9}
BUDGET=${SMAP3_BUDGET:-105} # seconds this script plans within (the batch's limit is a little more)
CAP=${SMAP3_CAP:-20}        # seconds a process may take at most
echo "== args: $ARGS; rounds $ROUNDS"
left() { echo $((BUDGET - (SECONDS - START))); }
bake() { # binary scene variant tag
  local extra=""
  case $3 in Wn) extra="--no-shadow-map";; M) extra="--load models";; Mn) extra="--load models --no-shadow-map";; esac
  local l=$(left); [ $l -gt $CAP ] && l=$CAP
  [ $l -ge 3 ] || { echo "  $4 skipped (time)"; return 1; }
  local s=${EPOCHREALTIME/./}; timeout $l $T/$1 $2.svo $T/$4.probes $ARGS $extra > $T/$4.log 2>&1; local rc=$?
  local e=${EPOCHREALTIME/./}
  echo "$(( (e - s + 500) / 1000 ))" > $T/$4.ms
  [ $rc = 0 ] || { echo "  $4 rc=$rc"; tail -3 $T/$4.log; }
  return $rc
}
nd() { [ -s $T/$1.probes ] && [ -s $T/$2.probes ] && cmp -l $T/$1.probes $T/$2.probes | wc -l || echo n/a; }
med() { sort -n | awk '{a[NR]=$1} END {if (NR) printf "%d (%d-%d, n=%d)", a[int((NR+1)/2)], a[1], a[NR], NR; else printf "n/a"}'; }
echo "== (1) bytes, elapsed $((SECONDS-START)) s"
for sc in cornell eph_monu1; do
  for v in W M Wn Mn; do
    bake new $sc $v b_${sc}_$v
    echo "  $sc $v: $(cat $T/b_${sc}_$v.ms 2>/dev/null) ms (first process of the variant); $(grep -oE 'GPU trace [0-9.]+ s' $T/b_${sc}_$v.log | head -1); $(grep -E '^sun map' $T/b_${sc}_$v.log | cut -c1-150)"
  done
  echo "  $sc: W/M $(nd b_${sc}_W b_${sc}_M), W/Wn $(nd b_${sc}_W b_${sc}_Wn), M/Mn $(nd b_${sc}_M b_${sc}_Mn), Wn/Mn $(nd b_${sc}_Wn b_${sc}_Mn) bytes differ (of $(stat -c %s $T/b_${sc}_W.probes 2>/dev/null))"
done
echo "== (2) time, elapsed $((SECONDS-START)) s; base M warm-up:"
bake base cornell M t_warm_base_M && echo "  base cornell M (first): $(cat $T/t_warm_base_M.ms) ms; bytes vs new W: $(nd t_warm_base_M b_cornell_W)"
for r in $(seq 1 $ROUNDS); do
  [ $(left) -gt 30 ] || { echo "  (time: round $r not run)"; break; }
  for sc in cornell eph_monu1; do
    bake new $sc W t_${sc}_newW_$r; bake new $sc M t_${sc}_newM_$r
    [ $sc = cornell ] && bake base $sc M t_${sc}_baseM_$r
  done
  echo "  round $r: cornell W $(cat $T/t_cornell_newW_$r.ms) M $(cat $T/t_cornell_newM_$r.ms) baseM $(cat $T/t_cornell_baseM_$r.ms 2>/dev/null); eph_monu1 W $(cat $T/t_eph_monu1_newW_$r.ms) M $(cat $T/t_eph_monu1_newM_$r.ms) ms"
done
for k in cornell_newW cornell_newM cornell_baseM eph_monu1_newW eph_monu1_newM; do
  echo "  $k: process ms median $(cat $T/t_${k}_*.ms 2>/dev/null | med); GPU trace s median $(grep -ohE 'GPU trace [0-9.]+' $T/t_${k}_*.log 2>/dev/null | awk '{print $3*1000}' | med) (ms)"
done
for sc in cornell eph_monu1; do echo "  $sc: every timed W and M the bytes of (1)'s W: $(for f in $T/t_${sc}_new?_*.probes; do cmp -s $f $T/b_${sc}_W.probes && echo y || echo n; done | sort | uniq -c | tr '\n' ' ')"; done
grep -hE '^sun map' $T/t_cornell_newM_1.log $T/t_cornell_newW_1.log 2>/dev/null | cut -c1-200
echo "== (3) eph_monu1 exploration, elapsed $((SECONDS-START)) s"
for x in x1 x2 x3; do
  bake $x eph_monu1 W e_$x && echo "  $x D: $(cat $T/e_$x.ms) ms; vs new Wn $(nd e_$x b_eph_monu1_Wn), vs new W $(nd e_$x b_eph_monu1_W) bytes differ; $(grep -E '^sun map' $T/e_$x.log | cut -c1-80)"
done
PB=${SMAP3_PB:-"--runs 10 --warmup 0.2"}
echo "== (4) passes_bench --layout compact --quick $PB, main's binary and the branch's in turn, elapsed $((SECONDS-START)) s"
for sc in eph_monu1 cornell; do
  for b in pb_base pb_new; do
    l=$(left); [ $l -gt $CAP ] && l=$CAP
    [ $l -ge 5 ] || { echo "  $b $sc skipped (time)"; continue; }
    echo "  -- $b $sc.svo"
    timeout $l $T/$b --layout compact --quick $PB $sc.svo 2>&1 | grep -E '^## |^\| (single|gbuffer)|shadow map check|passes_bench' | sed 's/^/  /'
  done
done
echo "== done in $((SECONDS-START)) s"
