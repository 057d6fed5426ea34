#!/bin/bash
# Coordinator (stop 49): how svo_bake --load models' .probes differ from --load whole's on the H200.
C=bench/out/coord; T=/tmp/coord; rm -rf $T; mkdir -p $T; export LD_LIBRARY_PATH=$PWD/$C:$PWD/bench/out/base/bin
gzip -dc $C/svo_bake.gz > $T/svo_bake; chmod +x $T/svo_bake
for a in "--grid 8,8,8 --res 128 --spp 64" "--grid 4,4,4 --res 16 --spp 4" "--grid 4,4,4 --res 16 --spp 1"; do
  echo "== $a"
  timeout 20 $T/svo_bake $C/cornell.svo $T/w.probes $a -q; timeout 20 $T/svo_bake $C/cornell.svo $T/w2.probes $a -q
  timeout 20 $T/svo_bake $C/cornell.svo $T/m.probes $a -q --load models
  VX_BAKE_PLACE=reader timeout 20 $T/svo_bake $C/cornell.svo $T/r.probes $a -q --load models
  ls -l $T/*.probes | awk '{print $5, $9}'
  echo "whole/whole2: $(cmp -l $T/w.probes $T/w2.probes | wc -l) bytes differ; whole/models: $(cmp -l $T/w.probes $T/m.probes | wc -l); models/reader-placed: $(cmp -l $T/m.probes $T/r.probes | wc -l)"
  cmp -l $T/w.probes $T/m.probes | head -3; cmp -l $T/w.probes $T/m.probes | awk 'function o(s,  v,i){v=0;for(i=1;i<=length(s);i++)v=v*8+substr(s,i,1);return v} {d=o($2)-o($3); if(d<0)d=-d; h[d>4?">4":d]++} END{for(k in h) print "  byte diff "k": "h[k]}'
done
