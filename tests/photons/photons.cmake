# photons: emitted power of every light type, the diffuse furnace, a caustic
# against the path tracer, progressive convergence (lavapipe without a GPU).
if(VX_WITH_VULKAN)
  vx_add_test(test_photons SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_photons.c LIBS vx_photons vx_probes vx_render vx_svo
              ${CMAKE_DL_LIBS} LABELS photons)
  set_tests_properties(test_photons PROPERTIES TIMEOUT 900 ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  vx_test_cost(test_photons 277)
  # the caustic, glossy and GGX checks and the progressive convergence are physics on lavapipe (170 s in Release;
  # the convergence 48 s under ASan, stop 60): under the sanitizers the photons' host code runs in the emission,
  # furnace, gather, kernel and reproducibility tests
  # and the seam between two models' floors (31 s under ASan; the kernel's face test, physics)
  vx_sanitize_trim(test_photons SKIP test_caustic test_ggx_finite test_glossy test_progressive test_kernel_seam)
endif()
if(VX_WITH_VULKAN AND VX_BENCH)
  # issue 13's spelling (--radius, --passes-count) against the old one, .pfm: no OpenImageIO
  add_test(NAME test_photons_cli COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_photons_cli.sh ${CMAKE_BINARY_DIR}/bin)
  set_tests_properties(test_photons_cli PROPERTIES TIMEOUT 900 LABELS photons)
  # option spellings compared through whole photon renders: lavapipe's time; under the sanitizers svo_render's
  # photon path runs in test_photons_tool, the library's in test_photons (tests/CMakeLists.txt vx_sanitize_trim)
  vx_sanitize_trim(test_photons_cli DISABLE)
endif()
if(VX_WITH_VULKAN AND VX_WITH_OIIO)
  add_test(NAME test_photons_tool COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_photons_tool.sh ${CMAKE_BINARY_DIR}/bin
           ${VX_CORPUS_DIR})
  set_tests_properties(test_photons_tool PROPERTIES TIMEOUT 300 LABELS photons)
endif()
vx_test_cost(test_photons_tool 60)
