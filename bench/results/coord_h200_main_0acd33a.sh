#!/bin/bash
# Coordinator's check (stop 53): main 0acd33a's GPU tests that stop 52's merged check did not reach.
T=/tmp/coord2; rm -rf $T; mkdir -p $T/t; for f in t/*.gz; do gzip -dc $f > $T/t/$(basename $f .gz); done; chmod +x $T/t/*
export VX_CORPUS_DIR=$PWD/corpus; s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
runt() { # test [VX_TEST_ONLY]
  local l=$(left ${LIMIT:-170}); [ $l -gt 3 ] || { echo "== $1: no time left"; return; }
  local s=$(date +%s); (cd $T && VX_TEST_ONLY=$2 timeout $l $T/t/$1 > $T/$1.log 2>&1); local rc=$?
  echo "== $1 ${2:+($2) }rc=$rc $(( $(date +%s) - s )) s: $(grep -E 'passed|failed' $T/$1.log | tail -1)"
  [ $rc != 0 ] && { grep -n -i -B3 -A2 'fail' $T/$1.log | head -20; tail -4 $T/$1.log; }
}
runt test_render_hits; runt test_render_edit; runt test_render_beam
runt test_compact_gpu
echo "== end $(( $(date +%s) - s0 )) s"
