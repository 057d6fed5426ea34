#!/bin/bash
# bench/inst_gpu.sh - the frame time with many instances (issue 18, branch inst):
# a generated sphere shell (bench/svo_regions.c) as one model and as grid-aligned
# region models (the converter's layout), and the DamagedHelmet at 512 as one model
# and as 64^3 regions (carried), rendered at 1920x1080 by main's svo_render (base)
# and this branch's (mine), processes alternated (ABAB...).
# Prints one ROW per process and the medians per (variant, scene, view, layout).
# Usage (from the repository root): bash bench/inst_gpu.sh I B  (I: this branch's
# binaries and inputs, B: main's binaries)
I=${1:-bench/out/inst}
B=${2:-bench/out/base/bin}
export LD_LIBRARY_PATH=$I:$B${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/inst_bench
mkdir -p $T
rm -f $T/rows $T/img_*
SIZE=${SIZE:-1920x1080}
RES=${RES:-2048}
REGIONS=${REGIONS:-"2048 512 128 64"}
ROUNDS=${ROUNDS:-2}
BUDGET=${BUDGET:-120}   # seconds: no new round starts past this
HARD=${HARD:-140}       # seconds: no new process starts past this
VIEWS=${VIEWS:-"whole close"}
FRAMES=${FRAMES:-21}
VARIANTS=${VARIANTS:-"base mine"}
VARIANTS1=${VARIANTS1:-"base mine"}   # on one-model scenes (no BVH)
LAYOUTS=${LAYOUTS:-"plain compact"}
nvidia-smi -L 2>/dev/null
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,temperature.gpu --format=csv 2>/dev/null
echo "== generate (t=$SECONDS)"
for R in $REGIONS; do
    $I/svo_regions $T/s${RES}_r$R.svo --res $RES --region $R || exit 1
done
ls -la $T
# views: the default framing (whole) and a close-up (about 93% of pixels hit)
close_sphere=$(awk -v N=$RES 'BEGIN{printf "%g,%g,%g,%g,%g,%g", 0.5*N, -0.25*N, 0.65*N, 0.5*N, 0.5*N, 0.45*N}')
close_helmet=0.396,-0.698,0.576,-0.002,0.187,-0.144
scenes=""
for R in $REGIONS; do scenes="$scenes $T/s${RES}_r$R.svo"; done
for f in $I/h512_r512.svo $I/h512_r64.svo; do [ -f $f ] && scenes="$scenes $f"; done
run() { # variant file view layout
    local v=$1 f=$2 view=$3 lay=$4 bin=$I cam=""
    [ $v = base ] && bin=$B
    if [ $view = close ]; then
        case $f in *h512*) cam="--camera $close_helmet" ;; *) cam="--camera $close_sphere" ;; esac
    fi
    local args=""
    local out
    out=$($bin/svo_render $args $f $T/o_${v}.ppm --size $SIZE --mode albedo --frames $FRAMES -v --layout $lay $cam 2>&1)
    local ms hit models
    ms=$(echo "$out" | sed -n 's/.*GPU ms median \([0-9.]*\).*/\1/p' | head -1)
    hit=$(echo "$out" | sed -n 's/.*view: \([0-9.]*\)% of pixels hit.*/\1/p' | head -1)
    models=$(echo "$out" | sed -n 's/.*scene: \([0-9]*\) models.*/\1/p' | head -1)
    [ -z "$ms" ] && { echo "FAIL $v $f $view $lay"; echo "$out" | tail -5; return; }
    echo "ROW $v $(basename $f .svo) $view $lay $ms $hit $models" | tee -a $T/rows
    # the image against the first variant's (exactness)
    local key=$T/img_$(basename $f .svo)_${view}_$lay.ppm
    if [ -f $key ]; then cmp -s $key $T/o_${v}.ppm || echo "DIFF $v $(basename $f .svo) $view $lay"; else cp $T/o_${v}.ppm $key; fi
}
echo "== warm-up (t=$SECONDS)"
R1=$(echo $REGIONS | awk '{print $1}')
for k in $(seq 1 ${WARM:-3}); do $B/svo_render $T/s${RES}_r$R1.svo $T/w.ppm --size $SIZE --frames 40 >/dev/null 2>&1; done
for r in $(seq 1 $ROUNDS); do
    [ $SECONDS -gt $BUDGET ] && { echo "== budget: round $r skipped (t=$SECONDS)"; break; }
    echo "== round $r (t=$SECONDS)"
    for f in $scenes; do
        vs=$VARIANTS
        case $f in *_r$RES.svo|*h512_r512.svo) vs=$VARIANTS1 ;; esac
        for view in $VIEWS; do for lay in $LAYOUTS; do for v in $vs; do
        [ $SECONDS -gt $HARD ] && { echo "== hard budget: stopped (t=$SECONDS)"; break 5; }
        run $v $f $view $lay
    done; done; done
    done
done
# the colour mode (primary and shadow rays: the any-hit walk) against main's, image for image
for v in $VARIANTS; do
    [ $SECONDS -gt ${COLOR_BUDGET:-135} ] && break
    [ $v = base ] && bin=$B || bin=$I
    args=""
    f=$T/s${RES}_r$R1.svo
    $bin/svo_render $args $f $T/col_$v.ppm --size $SIZE --mode color --camera $close_sphere >/dev/null 2>&1
    [ -f $T/col_base.ppm ] && { cmp -s $T/col_base.ppm $T/col_$v.ppm && echo "COLOR $v same as base" || echo "COLOR $v DIFF"; }
done
echo "== medians: variant scene view layout ms (n) hit% models; G rays/s at $SIZE"
px=$(echo $SIZE | awk -Fx '{print $1*$2}')
sort -k2,2 -k3,3 -k4,4 -k5,5 -k6,6n $T/rows | awk -v px=$px '
    { k = $2 " " $3 " " $4 " " $5; n[k]++; v[k, n[k]] = $6; hit[k] = $7; mod[k] = $8; if (!(k in seen)) { seen[k] = 1; order[++m] = k } }
    END { for (i = 1; i <= m; i++) { k = order[i]; c = n[k]; med = (c % 2) ? v[k, (c + 1) / 2] : 0.5 * (v[k, c / 2] + v[k, c / 2 + 1]);
          split(k, a, " "); printf "MED %-5s %-14s %-5s %-7s %8.3f ms (%d) %5s%% hit %5s models %7.2f G rays/s\n", a[1], a[2], a[3], a[4], med, c, hit[k], mod[k], px / med / 1e6 } }'
echo "== end t=$SECONDS"
