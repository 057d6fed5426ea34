# Emissive voxels as the direct pass's lights: one per voxel or one per
# cluster, against the path tracer (docs/PERFORMANCE.md section 11); needs only
# libvulkan and libc.
if(VX_WITH_VULKAN)
  add_executable(emissive_bench ${CMAKE_CURRENT_LIST_DIR}/emissive_bench.c)
  target_link_libraries(emissive_bench PRIVATE vx_probes vx_render vx_svo m)
endif()
