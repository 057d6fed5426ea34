# vox2svo --gpu (issue 12): the GPU voxelizer's file equals the CPU path's;
# skipped (77) without a Vulkan device with float64 shaders.
if(TARGET vox2svo AND TARGET vx_conv_mesh_gpu)
  add_test(NAME test_vox2svo_gpu COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_vox2svo_gpu.sh ${CMAKE_BINARY_DIR}/bin)
  # LeakSanitizer off for the tool runs (as test_tools' svo_render): lavapipe's
  # JIT-compiled shader code leaks a cache entry through frames no module
  # names, so tests/render/lsan.supp cannot match it; the GPU voxelizer's own
  # allocations are leak-checked by mesh_gpu_test, which keeps lavapipe mapped.
  set_tests_properties(test_vox2svo_gpu PROPERTIES TIMEOUT 900 SKIP_RETURN_CODE 77 LABELS tools
                       ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
  # the release run's alone: 156 s of CI's sanitizer run (stop 57) in corpus meshes through lavapipe's float64
  # emulation; under ASan the GPU voxelizer's host code runs in mesh_gpu_test (generated meshes, regions, shares)
  # and vox2svo's own in test_tools (docs/TESTING.md, stop 59)
  vx_sanitize_trim(test_vox2svo_gpu DISABLE)
endif()
vx_test_cost(test_vox2svo_gpu 60)
