# OpenVDB conversion tests (need the vx_conv_vdb library).
if(TARGET vx_conv_vdb)
  vx_add_test(vdb_convert SOURCES ${CMAKE_CURRENT_LIST_DIR}/vdb_test.cpp ${CMAKE_CURRENT_LIST_DIR}/vdb_new_guard.cpp
              LIBS vx_conv_vdb)
  # The brute-force references sort millions of cells; unoptimised template
  # code under ASan made that half a minute.
  target_compile_options(vdb_convert PRIVATE -O1)
  # Seeds are tiny grids written by OpenVDB (tests/fuzz/make_vdb_seeds.cpp:
  # level sets with zip and blosc, half floats, a fog volume with a tile, vec3
  # and double grids).
  # 120 mutations each keeps the replay to seconds under ASan.
  vx_add_fuzz(vdb_fuzz ${CMAKE_SOURCE_DIR}/tests/fuzz/vdb_fuzz.c LIBS vx_conv_vdb
              SEEDS -n 120 ${CMAKE_SOURCE_DIR}/tests/fuzz/vdb_seeds)
  target_sources(vdb_fuzz_replay PRIVATE ${CMAKE_CURRENT_LIST_DIR}/vdb_new_guard.cpp)
  if(TARGET vdb_fuzz)
    target_sources(vdb_fuzz PRIVATE ${CMAKE_CURRENT_LIST_DIR}/vdb_new_guard.cpp)
  endif()
  # OpenVDB sizes allocations from file fields: a garbled size must come back
  # as a failed allocation (VX_ERR_NOMEM), not abort inside ASan's malloc
  # (operator new is covered by vdb_new_guard.cpp).
  set_tests_properties(vdb_fuzz_replay vdb_convert PROPERTIES
                       ENVIRONMENT "ASAN_OPTIONS=allocator_may_return_null=1;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/vdb_lsan.supp:print_suppressions=0")
endif()
