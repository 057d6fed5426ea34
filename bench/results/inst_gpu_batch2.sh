#!/bin/bash
# branch inst, batch 2: many instances (issue 18): sphere shell at 2048^3 as 1 model and as
# 128^3 / 64^3 regions, helmet 512 as 1 model and as 64^3 regions; main's svo_render (base)
# against this branch's: g = the instances' grid walk (default), bl = the BVH over the
# models' cells' boxes with leaves of one instance (VX_INST_GRID=0 VX_BVH_MAX_LEAF=1)
ROUNDS=2 BUDGET=80 COLOR_BUDGET=138 RES=2048 REGIONS="2048 128 64" VARIANTS="base g bl" VARIANTS1="base" \
    bash bench/out/inst/inst_gpu.sh bench/out/inst bench/out/base/bin
