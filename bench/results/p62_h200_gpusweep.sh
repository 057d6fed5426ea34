#!/bin/bash
# GPU sweep on NVIDIA (stop 62): the 71 public MagicaVoxel scenes of docs/TESTING.md's "Real files from outside the
# corpus": depth and normal/instance GPU against the CPU reference (three views), and every light transport path
# (pass pipeline, cones, photons, GPU and CPU path tracer) for crashes, hangs, NaN/Inf. Run with carry [".gl","payload"].
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
P=$PWD/payload/gsweep; SV=${SV:-svo}; CAMS=${CAMS:-cams.txt}; SPP=${SPP:-64}; T=/tmp/gs; rm -rf $T; mkdir -p $T/o; R=$P/svo_render
echo "== $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1), $(nproc) CPUs, python3: $(command -v python3)"
W=256x192; J=$T/jobs; : > $J.gpu; : > $J.cpu
while read n m2 obl close; do
  S=$P/$SV/$n.svo; o=$T/o/$n
  for mode in depth $m2; do e=pfm; [ $mode = instance ] && e=ppm
    echo "$R $S ${o}_def_${mode}_gpu.$e --mode $mode --size $W --view2 $obl ${o}_obl_${mode}_gpu.$e" >> $J.gpu
    echo "$R $S ${o}_close_${mode}_gpu.$e --mode $mode --size $W --camera $close" >> $J.gpu
    echo "$R $S ${o}_def_${mode}_cpu.$e --mode $mode --size $W --cpu" >> $J.cpu
    echo "$R $S ${o}_obl_${mode}_cpu.$e --mode $mode --size $W --cpu --camera $obl" >> $J.cpu
    echo "$R $S ${o}_close_${mode}_cpu.$e --mode $mode --size $W --cpu --camera $close" >> $J.cpu
  done
  echo "$R $S ${o}_pt_gpu.pfm --mode pathtrace --size $W --spp $SPP --voxel-lights" >> $J.gpu
  echo "$R $S ${o}_pt_cpu.pfm --mode pathtrace --size $W --spp $SPP --voxel-lights --cpu" >> $J.cpu
  [ -n "$LITE" ] || echo "$R $S ${o}_direct_ao.pfm --passes gbuffer,direct,ao --size $W --voxel-lights" >> $J.gpu
  echo "$R $S ${o}_gi_pt.pfm --passes gbuffer,direct,gi=pathtrace --spp 16 --size $W --voxel-lights" >> $J.gpu
  echo "$R $S ${o}_gi_cones.pfm --passes gbuffer,direct,gi=cones --size $W --voxel-lights" >> $J.gpu
  echo "$R $S ${o}_gi_photons.pfm --passes gbuffer,direct,gi=photons --photons 262144 --spp 4 --size $W --voxel-lights" >> $J.gpu
  [ -n "$LITE" ] || echo "$R $S ${o}_tonemap.ppm --passes gbuffer,dof,direct,ao,aa,tonemap --size $W --voxel-lights" >> $J.gpu
done < $P/$CAMS
one() { local t0=$(date +%s%N) lg=/tmp/gs/log.$BASHPID; timeout 120 "$@" > $lg 2>&1; local rc=$?; echo "rc=$rc $(( ($(date +%s%N) - t0) / 1000000 ))ms $(basename $3)"; grep -q -i -E 'error|warning|nan|lost|assert|invalid|fail' $lg && { echo "   LOG $(basename $3): $(head -c 300 $lg | tr '\n' '|')"; }; rm -f $lg; }
export -f one
s0=$(date +%s)
(cat $J.cpu | timeout ${LIM:-440} xargs -P ${PC:-12} -I{} bash -c 'one {}' > $T/cpu.txt) &
cat $J.gpu | timeout ${LIM:-440} xargs -P ${PG:-3} -I{} bash -c 'one {}' > $T/gpu.txt
echo "gpu jobs done $(( $(date +%s) - s0 )) s"; wait; echo "cpu jobs done $(( $(date +%s) - s0 )) s"
grep -h -v '^rc=0 ' $T/gpu.txt $T/cpu.txt | head -40
grep -h LOG $T/gpu.txt $T/cpu.txt | head -30
grep -h '^rc' $T/gpu.txt | sort -t' ' -k2 -g -r | head -8
LITE=$LITE python3 $P/cmp.py $T/o $P/$CAMS > $OUT/cmp.txt 2>&1; tail -60 $OUT/cmp.txt
cp $T/gpu.txt $T/cpu.txt $OUT/
command -v python3 >/dev/null || tar czf $OUT/o.tar.gz -C $T o; ls -la $OUT
