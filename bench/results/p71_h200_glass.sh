for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export LD_LIBRARY_PATH=$PWD/payload/lib
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
echo "rev $(cat payload/REV)"
for b in test_glass_contact test_glass_direct test_glass_thick test_pathtrace test_photons test_probes_gpu; do
  gunzip -c payload/$b.gz > /tmp/$b; chmod +x /tmp/$b
  echo "== $b"; ( time timeout 240 /tmp/$b ) 2>&1 | grep -E "ok|FAIL|CHECK|pixels|ratio|passed|real|device" | head -40
done
