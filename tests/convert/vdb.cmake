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
  # 120 mutations each in Release; under the sanitizers 40: OpenVDB's reader (uninstrumented) is most of the
  # time, and the replay took 135 s of CI's sanitizer run (stop 57), where .ci/run's fuzz step then fuzzes
  # vdb_fuzz itself with ASan and UBSan (docs/TESTING.md, stop 59).
  if(VX_SANITIZE)
    set(vx_vdb_mutations 40)
  else()
    set(vx_vdb_mutations 120)
  endif()
  vx_add_fuzz(vdb_fuzz ${CMAKE_SOURCE_DIR}/tests/fuzz/vdb_fuzz.c LIBS vx_conv_vdb
              SEEDS -n ${vx_vdb_mutations} ${CMAKE_SOURCE_DIR}/tests/fuzz/vdb_seeds)
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
