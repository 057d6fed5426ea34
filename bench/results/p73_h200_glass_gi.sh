# Stop 73's GPU check. (0) the light field walk's crossing sort (docs/TESTING.md "Stop 73"): p73_lfdiff.c built
# against the kernel before the fix (payload/lfdiff_old) and after it (lfdiff_new), the whole image's GPU / CPU
# ratio of the indirect light field mode at 2048 samples, seeds 1-3 (lavapipe: before 0.948-0.963, after 0.992-1.005).
# Then (stop 72's p72_h200_glass_gi.sh, which no lent machine ran, plus the GPU allocation
# failures and the passes' and GPU renderer's tests): what the gi methods bring through glass (test_glass_gi) and
# the tests whose kernels stop 72 touched, on NVIDIA's compiler.
# Payload (made on the dev machine at the revision in payload/REV): each Release test binary gzipped into
# payload/NAME.gz, the libraries it needs beside the driver's in payload/lib; run with carry [".gl","payload"].
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/payload/lib
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
echo "rev $(cat payload/REV)"
for v in old new; do for sd in 1 2 3; do echo "lfdiff_$v seed $sd: $(gunzip -c payload/lfdiff_$v.gz > /tmp/lfdiff_$v; chmod +x /tmp/lfdiff_$v; timeout 60 /tmp/lfdiff_$v 2048 0 $sd 2>&1 | tail -1)"; done; done
for b in test_glass_gi test_glass_contact test_glass_direct test_glass_thick test_pathtrace test_photons test_cones \
         test_probes_gpu test_gpu_alloc_fail test_render_gpu test_passes; do
  gunzip -c payload/$b.gz > /tmp/$b; chmod +x /tmp/$b
  echo "== $b $(date -u +%T)"; ( time timeout 100 /tmp/$b ) > /tmp/$b.log 2>&1; echo "rc $?"
  grep -E "ok|FAIL|CHECK|through the pane|pixels|ratio|passed|real|device|mean|gi |light field" /tmp/$b.log | head -60
  [ -n "$OUT" ] && cp /tmp/$b.log $OUT/
done
