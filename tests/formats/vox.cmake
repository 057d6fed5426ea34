# zlib: test_teardown writes TDCZ streams of its own
find_package(ZLIB REQUIRED)
vx_add_test(test_vox SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_vox.c LIBS vx_formats ZLIB::ZLIB m)
# The replay driver's default of 2000 mutations per seed is slow for the large
# corpus files under ASan; 500 keeps the replay to seconds. vox_seeds/: a
# Teardown-style file (TDCZ chunks, a 255-entry RGBA) from make_vox_seeds.py.
vx_add_fuzz(vox_fuzz ${CMAKE_SOURCE_DIR}/tests/fuzz/vox_fuzz.c LIBS vx_formats ARGS -n 500
            SEEDS ${VX_CORPUS_DIR}/vox ${CMAKE_SOURCE_DIR}/tests/fuzz/vox_seeds)
