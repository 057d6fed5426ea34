# Stop 73's second GPU check (NVIDIA H200; carry [".gl","payload"]; payload made at the revision in payload/REV):
# (0) the light field walk's crossing sort before and after the fix on NVIDIA's compiler: p73_lfdiff.c built against
#     the kernel before the fix (payload/lfdiff_old.gz) and after it (lfdiff_new.gz), the whole image's GPU / CPU
#     ratio of the indirect light field mode at 2048 samples, seeds 1-3 (lavapipe: before 0.948-0.963, after
#     0.992-1.005); the first run of p73_h200_glass_gi.sh lost these lines to the output's cut;
# (1) test_metal_gi (metal's specular lobe in the probe modes, branch metal73), test_glass_gi, test_photons and
#     test_probes_gpu on NVIDIA.
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/payload/lib
R=${OUT:-/tmp}/p73b.txt
{ nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; echo "rev $(cat payload/REV)"; } | tee $R
for v in old new; do gunzip -c payload/lfdiff_$v.gz > /tmp/lfdiff_$v; chmod +x /tmp/lfdiff_$v
  for sd in 1 2 3; do echo "lfdiff_$v seed $sd: $(timeout 60 /tmp/lfdiff_$v 2048 0 $sd 2>&1 | tail -1)" | tee -a $R; done; done
for b in test_metal_gi test_glass_gi test_photons test_probes_gpu; do
  gunzip -c payload/$b.gz > /tmp/$b; chmod +x /tmp/$b
  echo "== $b $(date -u +%T)" | tee -a $R; ( time timeout 150 /tmp/$b ) > /tmp/$b.log 2>&1; echo "rc $?" | tee -a $R
  grep -E "ok \]|FAIL|CHECK|passed|real|device|mirror|rough|light field|lightfield|path tracer|gi " /tmp/$b.log | head -40 | tee -a $R
done
