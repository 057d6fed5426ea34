# svo core: octree building/decoding/validation and the .svo file format.
vx_add_test(svo_build SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_svo_build.c LIBS vx_svo LABELS svo)
vx_add_test(core_jobs SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_jobs.c LIBS vx_svo LABELS svo)
vx_add_test(core_crc SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_crc.c LIBS vx_core LABELS svo)
vx_add_test(svo_io SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_svo_io.c LIBS vx_svo LABELS svo)
# Seeds are written by `svo_io --write-seeds tests/fuzz/svo_seeds` (our own files).
vx_add_fuzz(svo_fuzz ${CMAKE_SOURCE_DIR}/tests/fuzz/svo_fuzz.c LIBS vx_svo SEEDS ${CMAKE_SOURCE_DIR}/tests/fuzz/svo_seeds)
# The model reader (vx_svo_reader_*) against the whole read, on svo_fuzz's seeds and its own (many models in
# each form, written by `make_svo_reader_seeds tests/fuzz/svo_reader_seeds`).
add_executable(make_svo_reader_seeds ${CMAKE_SOURCE_DIR}/tests/fuzz/make_svo_reader_seeds.c)
target_link_libraries(make_svo_reader_seeds PRIVATE vx_svo)
vx_add_fuzz(svo_reader_fuzz ${CMAKE_SOURCE_DIR}/tests/fuzz/svo_reader_fuzz.c LIBS vx_svo
            SEEDS ${CMAKE_SOURCE_DIR}/tests/fuzz/svo_seeds ${CMAKE_SOURCE_DIR}/tests/fuzz/svo_reader_seeds ARGS -n 600)
vx_add_test(svo_pack SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_svo_pack.c LIBS vx_svo LABELS svo)
vx_add_test(svo_light SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_svo_light.c LIBS vx_svo LABELS svo)
vx_add_test(svo_edit SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_svo_edit.c LIBS vx_svo LABELS svo)
vx_add_test(svo_reader_rewind SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_svo_reader_rewind.c LIBS vx_svo LABELS svo)
# The model reader's random access (vx_svo_reader_model): every model read again on its own equals the whole
# read's, on generated scenes in every NODE form and the corpus .vox scenes.
vx_add_test(svo_reader_model SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_svo_reader_model.c
            LIBS vx_svo vx_formats vx_convert LABELS svo)
