# Many lights in the direct pass: brute force, tiled and clustered culling at
# several light counts (docs/PERFORMANCE.md "Many lights"); needs only
# libvulkan and libc, like passes_bench.
if(VX_WITH_VULKAN)
  add_executable(lights_bench ${CMAKE_CURRENT_LIST_DIR}/lights_bench.c)
  target_link_libraries(lights_bench PRIVATE vx_render vx_convert vx_formats vx_svo)
endif()
