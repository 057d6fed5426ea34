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
vx_test_cost(test_passes_tool 55)
