vx_add_test(test_vox_svo SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_vox_svo.c LIBS vx_convert m)
