# GPU bytes per voxel of the compact layout against today's (issue 18), and
# with --gpu both trace kernels' speed.
add_executable(compact_bench ${CMAKE_CURRENT_LIST_DIR}/compact_bench.c)
target_link_libraries(compact_bench PRIVATE vx_trace vx_convert vx_formats vx_svo)
if(VX_WITH_VULKAN)
  # --gpu: both trace kernels on each scene (trace.comp, trace_compact.comp)
  target_link_libraries(compact_bench PRIVATE vx_render)
  target_compile_definitions(compact_bench PRIVATE VX_BENCH_HAVE_VULKAN)
endif()
