# GI comparison: every GI method against a path-traced reference, full image
# and indirect light, render and build time (bench/gi_table runs it on every
# scene). Needs only libvulkan and libc, so it runs on a GPU machine with a
# bare loader.
if(VX_WITH_VULKAN)
  add_executable(gi_bench ${CMAKE_CURRENT_LIST_DIR}/gi_bench.c)
  target_link_libraries(gi_bench PRIVATE vx_photons vx_cones vx_probes vx_render vx_convert vx_formats vx_tool vx_svo)
  # gi_bench goes on past a method's failure (exit 3; bench/gi_table goes on to the next scene); registered here,
  # where the target is (tests/ is configured before bench/)
  add_test(NAME test_gi_bench_photons COMMAND sh ${CMAKE_SOURCE_DIR}/tests/tools/test_gi_bench_photons.sh
                                              ${CMAKE_BINARY_DIR}/bin)
  set_tests_properties(test_gi_bench_photons PROPERTIES TIMEOUT 300 LABELS tools ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()
# the path tracer's rate with lights and materials switched on one at a time (issue 11)
if(VX_WITH_VULKAN)
  add_executable(pathtrace_bench ${CMAKE_CURRENT_LIST_DIR}/pathtrace_bench.c)
  target_link_libraries(pathtrace_bench PRIVATE vx_probes vx_render vx_convert vx_formats vx_svo)
endif()
