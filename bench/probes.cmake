# Probe GI error against a path-traced reference vs bake and render time.
if(VX_WITH_VULKAN)
  add_executable(probes_bench ${CMAKE_CURRENT_LIST_DIR}/probes_bench.c)
  target_link_libraries(probes_bench PRIVATE vx_probes vx_render vx_svo)
endif()
