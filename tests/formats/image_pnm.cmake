# formats/image_pnm.c: .pfm/.ppm/.pgm in every build (the whole of vx_image
# where OpenImageIO is off); with OpenImageIO the test also compares a .pfm
# with an .exr of the same pixels (read back through OpenImageIO).
vx_add_test(test_image_pnm SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_image_pnm.c LIBS vx_image vx_core m)
if(VX_WITH_OIIO)
  target_compile_definitions(test_image_pnm PRIVATE VX_TEST_OIIO=1)
endif()
# the reader under libFuzzer (scripts/fuzz.sh) and, in every build, the
# replay of its seeds with deterministic mutations
vx_add_fuzz(pnm_fuzz ${CMAKE_SOURCE_DIR}/tests/fuzz/pnm_fuzz.c LIBS vx_image vx_core
            SEEDS ${CMAKE_SOURCE_DIR}/tests/fuzz/pnm_seeds ARGS -n 2000)
