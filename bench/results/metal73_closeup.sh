#!/bin/sh
# the statue close-up (metal fills a large share of the pixels): gi=probes pass and frame, alternating
M=/work/main/build/bin/svo_render; W=/tmp/wA/build/bin/svo_render; CAM=20,-32,17,6.5,-13.5,11
for run in 1 2 3; do for b in $M $W; do
  t=$($b island.svo /tmp/m/c.png --camera $CAM --size 320x180 --passes gbuffer,direct,gi=probes --probes island.probes --spp 4 -v 2>&1 | awk '/^gi /{g=$2} /^frame /{f=$2} END{print g, f}')
  echo "closeup $(echo $b | cut -d/ -f3) run$run gi/frame ms: $t"
done; done
