# Frames in flight (render/display.h, vx_frame_record) against the waited path, on lavapipe.
if(VX_WITH_VULKAN)
  vx_add_test(test_display SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_display.c LIBS vx_render vx_svo m)
  set_tests_properties(test_display PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp")
endif()
