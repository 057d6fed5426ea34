#!/bin/sh
# metal in the probe modes: gi=probes pass and frame times, main against metal73, alternating
M=/work/main/build/bin/svo_render; W=/tmp/wA/build/bin/svo_render
for sc in island multi island_nm; do
  pr=$sc.probes; [ $sc = island_nm ] && pr=island.probes
  for b in $M $W; do $b $sc.svo /tmp/m/warm.png --size 320x180 --passes gbuffer,direct,gi=probes --probes $pr --spp 4 -v >/dev/null 2>&1; done
  for run in 1 2 3; do for b in $M $W; do
    t=$($b $sc.svo /tmp/m/c.png --size 320x180 --passes gbuffer,direct,gi=probes --probes $pr --spp 4 -v 2>&1 | awk '/^gi /{g=$2} /^frame /{f=$2} END{print g, f}')
    echo "$sc $(echo $b | cut -d/ -f3) run$run gi/frame ms: $t"
  done; done
done
