#!/bin/bash
# Stop 74: the GI table's material scenes on NVIDIA (first time) with the metal chains (merge 0e21e9b): gi_bench as
# bench/gi_table --gpu runs it (1920x1080, references 2 x 4096 spp, median of 5 after a 100-ms warm frame), for the
# scenes in $SCENES (metal-room, island: about 4.5 minutes each, so one per call), after test_metal_gi on the device.
# Run with carry [".gl", "payload"]: payload/ holds gi_bench.gz, test_metal_gi.gz, test_glass_gi.gz (build/, Release),
# island.vox (vox2svo --write-demo), REV and lib/.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p74b; rm -rf $T; mkdir -p $T; O=${OUT:-/tmp}
for b in gi_bench test_metal_gi test_glass_gi; do gunzip -c payload/$b.gz > $T/$b; chmod +x $T/$b; done
R=$O/p74b.txt
{ nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; echo "rev $(cat payload/REV)"; } | tee -a $R
for t in ${TESTS:-}; do echo "== $t $(date -u +%T)" | tee -a $R
  ( time timeout 150 $T/$t ) > $T/$t.log 2>&1; echo "rc $?" | tee -a $R; grep -vE "^\[ run" $T/$t.log | tail -40 | tee -a $R; done
SZ=${SIZE:-1920x1080} REF=${REF:-4096} RUNS=${RUNS:-5} WARM=${WARM:-100}
SPP="--max-spp pathtrace=1024 --max-spp lightfield=256 --max-spp photons=64 --photons 1000000"
for s in ${SCENES:-}; do echo "== $s $(date -u +%T)" | tee -a $R
  case $s in
  metal-room) A="--camera 58,8,20,20,40,2 --up 0,0,1 metal-room $SZ 8:64:16 4:64:16" ;;
  island) A="--camera 34,-34,22,10,-6,8 --up 0,0,1 payload/island.vox $SZ 8:64:16 4:64:16" ;;
  esac
  timeout ${LIM:-540} $T/gi_bench --name $s --ref-spp $REF --runs $RUNS --warm $WARM --threads $(nproc) $SPP \
    --csv $O/gi_table_$s.csv $A > $O/gi_table_$s.txt 2>&1; echo "rc $?" | tee -a $R
  tail -30 $O/gi_table_$s.txt | tee -a $R
done
