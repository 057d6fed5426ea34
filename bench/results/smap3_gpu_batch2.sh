#!/bin/bash
# smap3 (issue 18, branch smap3), batch 2: the bake's sun rays without the map's own-cube rule (batch 1: with it,
# eph_monu1 differed with and without the map, 64 bytes whole and 168 over the compact layout; its exploration build
# without the rule gave 0). new: the branch without the rule in probe.comp; rule: batch 1's binary (the rule kept).
# (1) bytes: cornell, eph_monu1 and the animated demo (23 instances), whole (W) and over the model reader (M,
#     compact layout), with the map and without (Wn, Mn); cmp -l counts the differing bytes.
# (2) time: the whole process, warm, new W, new M, rule W, rule M in turn, 9 rounds, medians (GPU trace too);
#     the -v times of round 1's new W and new M (Cornell): where models' process time goes.
# SMAP3_ARGS / SMAP3_ROUNDS / SMAP3_BUDGET / SMAP3_CAP: smaller runs for the dev VM's lavapipe only.
START=$SECONDS; T=/tmp/$NAME; rm -rf $T; mkdir -p $T
for b in new rule; do gzip -dc $b.gz > $T/$b && chmod +x $T/$b; done
echo "== $(date -u +%T) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), load $(cut -d' ' -f1-3 /proc/loadavg); new $(cat NEW_REV), rule $(cat RULE_REV)"
ARGS=${SMAP3_ARGS:-"--grid 8,8,8 --res 128 --spp 64 -q -v"}
ROUNDS=${SMAP3_ROUNDS:-9}
BUDGET=${SMAP3_BUDGET:-85} # seconds this script plans within (the batch's limit is a little more)
CAP=${SMAP3_CAP:-20}       # seconds a process may take at most
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
echo "== (1) bytes (new), elapsed $((SECONDS-START)) s"
for sc in eph_monu1 cornell anim; do
  for v in W M Wn Mn; do
    bake new $sc $v b_${sc}_$v
    echo "  $sc $v: $(cat $T/b_${sc}_$v.ms 2>/dev/null) ms; $(grep -oE 'GPU trace [0-9.]+ s' $T/b_${sc}_$v.log | head -1); $(grep -E '^sun map' $T/b_${sc}_$v.log | cut -c1-100)"
  done
  echo "  $sc: W/M $(nd b_${sc}_W b_${sc}_M), W/Wn $(nd b_${sc}_W b_${sc}_Wn), M/Mn $(nd b_${sc}_M b_${sc}_Mn), Wn/Mn $(nd b_${sc}_Wn b_${sc}_Mn) bytes differ (of $(stat -c %s $T/b_${sc}_W.probes 2>/dev/null))"
done
echo "== (2) time, elapsed $((SECONDS-START)) s; rule's warm-up:"
for sc in cornell eph_monu1; do for v in W M; do bake rule $sc $v t_warm_rule_${sc}_$v && echo "  rule $sc $v (first): $(cat $T/t_warm_rule_${sc}_$v.ms) ms; bytes vs new $v: $(nd t_warm_rule_${sc}_$v b_${sc}_$v)"; done; done
for r in $(seq 1 $ROUNDS); do
  [ $(left) -gt 12 ] || { echo "  (time: round $r not run)"; break; }
  line="  round $r:"
  for sc in cornell eph_monu1; do
    for who in new rule; do for v in W M; do bake $who $sc $v t_${sc}_${who}${v}_$r; line="$line $sc $who$v $(cat $T/t_${sc}_${who}${v}_$r.ms 2>/dev/null)"; done; done
  done
  echo "$line"
done
for sc in cornell eph_monu1; do for k in newW newM ruleW ruleM; do
  echo "  $sc $k: process ms median $(cat $T/t_${sc}_${k}_*.ms 2>/dev/null | med); GPU trace ms median $(grep -ohE 'GPU trace [0-9.]+' $T/t_${sc}_${k}_*.log 2>/dev/null | awk '{print $3*1000}' | med)"
done; done
for sc in cornell eph_monu1; do echo "  $sc: timed new W/M the bytes of (1)'s new W: $(for f in $T/t_${sc}_new?_*.probes; do cmp -s $f $T/b_${sc}_W.probes && echo y || echo n; done | sort | uniq -c | tr '\n' ' ')"; done
for v in W M; do echo "  -- cornell new $v, round 1 (-v):"; grep -E '^(load|times|timeline|sun map)' $T/t_cornell_new${v}_1.log | cut -c1-330 | sed 's/^/  /'; done
echo "== done in $((SECONDS-START)) s"
