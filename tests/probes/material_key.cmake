# a record's material keyed by its material id (vx_svo_attr_material) in every renderer: a palette room against
# its RGBA twin with a material channel (CPU and GPU path tracers, gbuffer,direct, gi=cones, gi=photons; the
# compact layout's frames, which carry the material ids, against the plain layout's). lavapipe in CI.
if(VX_WITH_VULKAN AND TARGET vx_cones AND TARGET vx_photons)
  vx_add_test(test_material_key SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_material_key.c
              LIBS vx_photons vx_cones vx_probes vx_render vx_svo ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_material_key PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  vx_test_cost(test_material_key 155)
  # under the sanitizers 711 s whole on 2 cores (timeout 900), 406 s trimmed: the plain layout's frames of test_passes and
  # test_pathtrace_gpu are rendered again (plain and compact) by test_compact_materials, which keeps the host code
  vx_sanitize_trim(test_material_key SKIP test_passes test_pathtrace_gpu)
endif()
