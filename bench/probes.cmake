# Probe bake time and GI error against a path-traced reference vs bake and
# render time (GPU by default, --cpu for the CPU paths). Needs only libvulkan
# and libc, like render_bench, so it runs on a GPU machine with a bare loader.
if(VX_WITH_VULKAN)
  add_executable(probes_bench ${CMAKE_CURRENT_LIST_DIR}/probes_bench.c)
  target_link_libraries(probes_bench PRIVATE vx_probes vx_render vx_convert vx_formats vx_tool vx_svo)
endif()
