#!/bin/bash
# Coordinator's merged check, part 2 (stop 53): merged d6c73c6's GPU tests that part 1 did not reach.
T=/tmp/coord2; rm -rf $T; mkdir -p $T/t; for f in t/*.gz; do gzip -dc $f > $T/t/$(basename $f .gz); done; chmod +x $T/t/*
export VX_CORPUS_DIR=$PWD/corpus; s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
runt() { # test [VX_TEST_ONLY]
  local l=$(left ${LIMIT:-250}); [ $l -gt 3 ] || { echo "== $1: no time left"; return; }
  local s=$(date +%s); (cd $T && VX_TEST_ONLY=$2 timeout $l $T/t/$1 > $T/$1.log 2>&1); local rc=$?
  echo "== $1 ${2:+($2) }rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$1.log | tail -1)"
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$1.log | head -20; tail -4 $T/$1.log; }
}
runt test_probes_gpu
runt test_passes
runt test_photons
runt test_render_beam
runt test_render_hits
runt test_render_edit
runt test_compact_load_gpu
runt test_compact_page_file
echo "== end $(( $(date +%s) - s0 )) s"
