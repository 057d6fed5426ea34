# probes: octahedral mapping, the CPU bake (box distances, furnace,
# determinism, shards), the .probes reader, probe GI against the path tracer.
if(VX_WITH_VULKAN)
  vx_add_test(test_probes SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_probes.c LIBS vx_probes vx_render vx_svo LABELS probes)
endif()
if(VX_WITH_VULKAN AND VX_WITH_OIIO)
  add_test(NAME test_svo_bake COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_svo_bake.sh ${CMAKE_BINARY_DIR}/bin)
  set_tests_properties(test_svo_bake PROPERTIES TIMEOUT 300)
endif()
