# The embedded kernels' build rules take their includes from the compiler's depfile (cmake/shaders.cmake
# vx_spirv_header): an edit of any included file rebuilds exactly the kernels that include it, checked on the small
# tree of shader_deps/ with this build's generator (a few seconds; no GPU; docs/TESTING.md).
if(VX_WITH_VULKAN)
  add_test(NAME test_shader_deps
           COMMAND ${CMAKE_COMMAND} -DSRC=${CMAKE_CURRENT_LIST_DIR}/shader_deps -DWORK=${CMAKE_CURRENT_BINARY_DIR}/shader_deps
                   -DGEN=${CMAKE_GENERATOR} -DMAKE=${CMAKE_MAKE_PROGRAM} -DSHADERS=${CMAKE_SOURCE_DIR}/cmake/shaders.cmake
                   -DGLSLANG=${GLSLANG_VALIDATOR} -P ${CMAKE_CURRENT_LIST_DIR}/shader_deps/check.cmake)
  set_tests_properties(test_shader_deps PROPERTIES TIMEOUT 120)
  vx_sanitize_trim(test_shader_deps DISABLE) # (cmake and glslang only: nothing for ASan to see)
endif()
