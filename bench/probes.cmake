# Probe bake time and GI error against a path-traced reference vs bake and
# render time (GPU by default, --cpu for the CPU paths). Needs only libvulkan
# and libc, like render_bench, so it runs on a GPU machine with a bare loader.
if(VX_WITH_VULKAN)
  add_executable(probes_bench ${CMAKE_CURRENT_LIST_DIR}/probes_bench.c)
  target_link_libraries(probes_bench PRIVATE vx_probes vx_render vx_convert vx_formats vx_tool vx_svo)
endif()
# bake_diff: a diagnostic (issue 18): one small bake in the plain and compact layouts, the differing texels
if(VX_WITH_VULKAN)
  add_executable(bake_diff ${CMAKE_CURRENT_LIST_DIR}/bake_diff.c)
  target_link_libraries(bake_diff PRIVATE vx_probes vx_render vx_convert vx_formats vx_svo)
endif()
