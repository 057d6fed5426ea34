add_test(NAME test_tools COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_tools.sh ${CMAKE_BINARY_DIR}/bin ${VX_CORPUS_DIR})
set_tests_properties(test_tools PROPERTIES TIMEOUT 600)
# a .svo cut short before and during a read, at the tools (issue 18): an
# LD_PRELOAD module cuts the file at a chosen read (tests/tools/cut_preload.c)
if(TARGET svo_render AND TARGET svo_bake AND TARGET svo_info AND TARGET vox2svo)
  add_library(vx_cut_preload MODULE ${CMAKE_CURRENT_LIST_DIR}/cut_preload.c)
  # not instrumented: it runs ahead of the ASan runtime in the link order
  target_compile_options(vx_cut_preload PRIVATE -fno-sanitize=all)
  target_link_options(vx_cut_preload PRIVATE -fno-sanitize=all)
  target_link_libraries(vx_cut_preload PRIVATE ${CMAKE_DL_LIBS})
  add_test(NAME test_tools_cut COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_tools_cut.sh ${CMAKE_BINARY_DIR}/bin
           $<TARGET_FILE:vx_cut_preload> ${CMAKE_SOURCE_DIR}/tests/fuzz/svo_reader_seeds)
  set_tests_properties(test_tools_cut PROPERTIES TIMEOUT 300 LABELS tools)
endif()
vx_test_cost(test_tools 75)
