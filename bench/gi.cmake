# GI comparison: every GI method against a path-traced reference, full image
# and indirect light, render and build time (bench/gi_table runs it on every
# scene). Needs only libvulkan and libc, so it runs on a GPU machine with a
# bare loader.
if(VX_WITH_VULKAN)
  add_executable(gi_bench ${CMAKE_CURRENT_LIST_DIR}/gi_bench.c)
  target_link_libraries(gi_bench PRIVATE vx_photons vx_cones vx_probes vx_render vx_convert vx_formats vx_tool vx_svo)
endif()
# the path tracer's rate with lights and materials switched on one at a time (issue 11)
if(VX_WITH_VULKAN)
  add_executable(pathtrace_bench ${CMAKE_CURRENT_LIST_DIR}/pathtrace_bench.c)
  target_link_libraries(pathtrace_bench PRIVATE vx_probes vx_render vx_convert vx_formats vx_svo)
endif()
