# Stop 72's GPU check, ready for the next lent NVIDIA machine (no device was lent in stop 72): what the gi
# methods bring through glass (test_glass_gi) and the tests whose kernels it touched, on NVIDIA's compiler.
# Payload (made on the dev machine at the revision in payload/REV): gzip each Release test binary into
# payload/NAME.gz, the libraries it needs beside the driver's into payload/lib; run with carry [".gl","payload"].
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/payload/lib
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
echo "rev $(cat payload/REV)"
for b in test_glass_gi test_glass_contact test_glass_direct test_glass_thick test_pathtrace test_photons test_cones test_probes_gpu; do
  gunzip -c payload/$b.gz > /tmp/$b; chmod +x /tmp/$b
  echo "== $b"; ( time timeout 240 /tmp/$b ) 2>&1 | grep -E "ok|FAIL|CHECK|through the pane|pixels|ratio|passed|real|device" | head -40
done
