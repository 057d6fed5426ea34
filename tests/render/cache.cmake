# The device's pipeline cache (render/gpu_pipeline.c) under many variants:
# pipelines held across others' creation stay themselves, and frames of many
# scenes, both layouts and the GI methods through one device give the bits of
# the same frames on fresh devices (issue 18; lavapipe in CI).
if(VX_WITH_VULKAN AND TARGET vx_cones AND TARGET vx_photons)
  set(vx_cache_spv ${CMAKE_CURRENT_BINARY_DIR}/cache_value.comp.h)
  vx_spirv_header(${vx_cache_spv} ${CMAKE_CURRENT_LIST_DIR}/shaders/cache_value.comp vx_test_cache_value_spv)
  vx_add_test(test_pipeline_cache SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_pipeline_cache.c ${vx_cache_spv}
              LIBS vx_photons vx_cones vx_probes vx_render vx_trace vx_svo)
  target_include_directories(test_pipeline_cache PRIVATE ${CMAKE_CURRENT_BINARY_DIR})
  set_tests_properties(test_pipeline_cache PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp")
  # the frames on fresh devices compile about 180 pipelines (lavapipe's time); under the sanitizers the cache's
  # own code (eviction under 100 held pipelines, frames held across creation) runs in the other three tests
  vx_sanitize_trim(test_pipeline_cache SKIP test_frames_one_device)
  vx_test_cost(test_pipeline_cache 235)
endif()
