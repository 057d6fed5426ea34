# photon mapping on its own scenes (issue 13): one pass's trace, grid build
# and gather per photon count, and the progressive error against the path
# tracer's against time. Needs only libvulkan and libc (a bare GPU machine).
if(VX_WITH_VULKAN)
  add_executable(photons_bench ${CMAKE_CURRENT_LIST_DIR}/photons_bench.c)
  target_link_libraries(photons_bench PRIVATE vx_photons vx_probes vx_render vx_convert vx_formats vx_svo)
endif()
