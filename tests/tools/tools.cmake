add_test(NAME test_tools COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_tools.sh ${CMAKE_BINARY_DIR}/bin ${VX_CORPUS_DIR})
set_tests_properties(test_tools PROPERTIES TIMEOUT 600)
