#!/bin/bash
# Coordinator (stop 56): main 54224d6's test_passes on the H200 (c1b7770's tolerance for GPUs in test_deep_models,
# never run there).
T=/tmp/coord; rm -rf $T; mkdir -p $T; gzip -dc test_passes.gz > $T/test_passes; chmod +x $T/test_passes
echo "== main $(cat REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date +%T)"
s=$(date +%s); (cd $T && ./test_passes > $T/tp.log 2>&1); rc=$?
echo "== test_passes rc=$rc $(( $(date +%s) - s )) s"; grep -E 'ok|FAIL|fail|differ|skip|left' $T/tp.log | head -60; tail -3 $T/tp.log
