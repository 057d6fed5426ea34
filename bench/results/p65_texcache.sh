#!/bin/bash
# Stop 65 (texcache65): vox2svo on glTF with per-cell materials, before and after. base = main b79e53c,
# new = this branch. Usage: p65_texcache.sh BASE_VOX2SVO NEW_VOX2SVO [rounds, default 7]
#   1. the .svo files of both byte for byte (cmp) and their messages (the tool's name, times and peak memory left
#      out) for every glTF of
#      $CORPUS (../shared/corpus/gltf) at --res 256 and 64, DamagedHelmet also --solid and --normals;
#   2. DamagedHelmet --res 256, processes alternated (base, new) for `rounds` rounds after one warm-up each:
#      wall from $EPOCHREALTIME, the tool's -v read / convert times, minor page faults (/usr/bin/time %R);
#      medians last.
# Built here (2 cores shared with other sessions, lavapipe GPU): cmake -DCMAKE_BUILD_TYPE=Release -DVX_WERROR=ON,
# base from `git archive b79e53c` in a folder of its own.
set -u
B=$1; N=$2; R=${3:-7}
C=${CORPUS:-$(dirname "$0")/../../../shared/corpus/gltf}
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
same=0; diff=0
for f in "$C"/*.glb "$C"/*/*.gltf; do
  for o in "--res 256" "--res 64"; do
    $B "$f" $T/a.svo $o > $T/a.txt 2>&1; ra=$?
    $N "$f" $T/b.svo $o > $T/b.txt 2>&1; rb=$?
    for x in a:$B b:$N; do # the tool's name and times left out
      sed -i "/^  \(time\|peak memory\)  /d; s|${x#*:}|vox2svo|; s|$(basename ${x#*:}):|vox2svo:|; s|$T/${x%%:*}.svo|OUT|" $T/${x%%:*}.txt
    done
    if [ $ra = $rb ] && cmp -s $T/a.txt $T/b.txt && { [ $ra != 0 ] || cmp -s $T/a.svo $T/b.svo; }; then
      same=$((same + 1)); echo "same  $(basename "$f") $o (exit $ra)"
    else
      diff=$((diff + 1)); echo "DIFF  $(basename "$f") $o (exit $ra / $rb)"
    fi
    rm -f $T/a.svo $T/b.svo
  done
done
H="$C/khronos_DamagedHelmet.glb"
for o in "--res 256 --solid" "--res 256 --normals"; do
  $B "$H" $T/a.svo $o > /dev/null 2>&1; $N "$H" $T/b.svo $o > /dev/null 2>&1
  if cmp -s $T/a.svo $T/b.svo; then same=$((same + 1)); echo "same  DamagedHelmet $o"; else diff=$((diff + 1)); echo "DIFF  DamagedHelmet $o"; fi
done
echo "files: $same the same, $diff different"
for b in base new; do x=$B; [ $b = new ] && x=$N; $x "$H" $T/w.svo --res 256 > /dev/null 2>&1; done
for r in $(seq 1 $R); do
  for b in base new; do
    x=$B; [ $b = new ] && x=$N
    s=$EPOCHREALTIME
    /usr/bin/time -f "faults %R" -o $T/t.txt $x "$H" $T/w.svo --res 256 -v > $T/v.txt 2>&1
    e=$EPOCHREALTIME
    rc=$(sed -n 's/.*read \([0-9.]*\), convert \([0-9.]*\),.*/read \1 convert \2/p' $T/v.txt)
    echo "$b round $r wall $(awk -v a=$s -v b=$e 'BEGIN{printf "%.3f", b-a}') $rc $(cat $T/t.txt)"
  done
done | tee $T/runs.txt
for b in base new; do
  printf "%s median:" $b
  for k in wall read convert faults; do
    v=$(awk -v b=$b -v k=$k '$1 == b { for (i = 1; i < NF; i++) if ($i == k) print $(i + 1) }' $T/runs.txt | sort -g |
        awk '{ a[NR] = $1 } END { print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2 }')
    printf " %s %s" $k $v
  done
  echo
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
