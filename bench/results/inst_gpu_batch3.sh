#!/bin/bash
# branch inst, batch 3 (final check): the branch's final svo_render (BVH leaves of one instance over
# the models' cells' boxes; g = with the instances' grid walk, its default; bvh = --instance-bvh)
# against main's (base): sphere shell 2048^3 in 968 regions of 128^3 and as one model, helmet 512
# in 271 regions and as one model; plain layout, close-up then whole view; at most 65 s of processes
ROUNDS=2 BUDGET=40 HARD=62 COLOR_BUDGET=60 WARM=1 FRAMES=11 RES=2048 REGIONS="128 2048" LAYOUTS=plain \
    VIEWS="close whole" VARIANTS="base g bvh" VARIANTS1="base" \
    bash bench/out/inst/inst_gpu.sh bench/out/inst bench/out/base/bin
