# The pass pipeline (render/pipeline.h) on lavapipe.
if(VX_WITH_VULKAN)
  vx_add_test(test_passes SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_passes.c
              LIBS vx_render vx_convert vx_formats vx_svo)
  set_tests_properties(test_passes PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp")
endif()
# The tools' pass options (svo_render, svo_view's script command).
if(VX_WITH_VULKAN)
  add_test(NAME test_passes_tool COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_passes_tool.sh ${CMAKE_BINARY_DIR}/bin)
  set_tests_properties(test_passes_tool PROPERTIES TIMEOUT 300 ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()
# a long tool script started early (ctest -j runs the highest COST first), so that neither run ends on one alone:
# in stop 60's timed CI run test_view_script, last in order, ran alone 49 s (Release) and 54 s (ASan) (docs/TESTING.md)
vx_test_cost(test_passes_tool 55)
