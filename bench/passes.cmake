# The pass pipeline's per-pass costs and its overhead over the single trace
# shader; needs only libvulkan and libc, like render_bench.
if(VX_WITH_VULKAN)
  add_executable(passes_bench ${CMAKE_CURRENT_LIST_DIR}/passes_bench.c)
  target_link_libraries(passes_bench PRIVATE vx_render vx_convert vx_formats vx_svo)
endif()
