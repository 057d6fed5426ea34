#!/bin/bash
# (as run: svo_bake and test_compact_passes of edf1d59 (build-gpu), vox2svo likewise; corpus/vox/: eph_monu1.vox and
# ogt_chr_knight.vox from the corpus, copied into the ignored bench/out/bakex for the run)
# issue 18 (branch bakex), batch 3: the relapse tests on the H200. test_compact_passes (edf1d59; its new part: a
# 3x3x3 probe grid at R=32 baked in both layouts per scene, whose centre rays meet solid cubes at their edges;
# eph_monu1 and ogt_chr_knight from the corpus) and test_svo_bake's new check by hand: the demo scene baked
# --load whole and --load models at 3x3x3, R=32, 1 spp (main 338 bytes apart on lavapipe); main's svo_bake
# beside it (A) for the record.
START=$SECONDS
D=bench/out/bakex; B=bench/out/base/bin; T=/tmp/bakexq; rm -rf $T; mkdir -p $T
export LD_LIBRARY_PATH=$PWD/$B
echo "== $(date -u) host: $(nproc) CPUs, $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1)"
for f in svo_bake vox2svo test_compact_passes; do gzip -dc $D/$f.gz > $T/$f; chmod +x $T/$f; done
timeout 5 $T/vox2svo --write-demo $T/demo.vox > /dev/null && timeout 5 $T/vox2svo $T/demo.vox $T/demo.svo > /dev/null; echo "demo rc=$?"
E="--grid 3,3,3 --res 32 --spp 1 -q"
for w in A B; do
  bin=$T/svo_bake; [ $w = A ] && bin=$B/svo_bake
  timeout 15 $bin $T/demo.svo $T/${w}w.probes $E > /dev/null 2>&1; r1=$?
  timeout 15 $bin $T/demo.svo $T/${w}m.probes $E --load models > /dev/null 2>&1; r2=$?
  echo "  demo 3x3x3 R=32, $w: rc $r1 $r2, whole vs models: $(cmp -l $T/${w}w.probes $T/${w}m.probes 2>/dev/null | wc -l) bytes differ"
done
echo "== test_compact_passes, elapsed $((SECONDS-START)) s"
export VX_CORPUS_DIR=$PWD/$D/corpus
(cd $T && timeout $((58 - (SECONDS - START))) ./test_compact_passes > $T/tcp.log 2>&1); echo "  rc=$?"
grep -E "probe bake|passed|failed|FAIL|ok  \]|SKIP" $T/tcp.log | head -40
echo "== done in $((SECONDS-START)) s"
