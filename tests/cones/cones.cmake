# cones: voxel cone tracing (issue 12) on lavapipe at small sizes: the
# voxelizer against a CPU brute force, the filter against CPU averages,
# analytic cases (open sky, an emitting ceiling, a furnace) and the path
# tracer.
if(VX_WITH_VULKAN)
  vx_add_test(test_cones SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_cones.c
              LIBS vx_cones vx_photons vx_probes vx_render vx_svo ${CMAKE_DL_LIBS} LABELS cones)
  set_tests_properties(test_cones PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
endif()
if(VX_WITH_VULKAN AND VX_WITH_OIIO)
  # svo_render --passes ...,gi=cones: options, usage errors, frames
  add_test(NAME test_cones_tool COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_cones_tool.sh ${CMAKE_BINARY_DIR}/bin)
  set_tests_properties(test_cones_tool PROPERTIES TIMEOUT 600 LABELS cones)
endif()
