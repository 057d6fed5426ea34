# The path tracer's sky by direction (issue 11): gradient and environment map
# on the CPU and the GPU, a white furnace under a constant map read through
# OpenImageIO.
if(VX_WITH_VULKAN AND TARGET vx_image)
  vx_add_test(test_sky SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_sky.c LIBS vx_probes vx_render vx_image vx_svo
              ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_sky PROPERTIES TIMEOUT 600 ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
endif()
