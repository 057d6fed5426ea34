# Tracer benchmark: needs only libvulkan and libc (no OpenImageIO/OpenVDB/GLFW),
# so the binary runs on a GPU machine that has just a Vulkan loader. The ESVO
# baseline's kernel (bench/shaders/esvo.comp) is embedded like render's shaders.
if(VX_WITH_VULKAN)
  set(VX_BENCH_SPV_DIR ${CMAKE_CURRENT_BINARY_DIR}/spv)
  file(MAKE_DIRECTORY ${VX_BENCH_SPV_DIR})
  add_custom_command(
    OUTPUT ${VX_BENCH_SPV_DIR}/esvo.comp.h
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env ${VX_SPIRV_TARGET_ENV} --vn vx__esvo_spv_arr -o ${VX_BENCH_SPV_DIR}/esvo.comp.h
            ${CMAKE_CURRENT_LIST_DIR}/shaders/esvo.comp
    DEPENDS ${CMAKE_CURRENT_LIST_DIR}/shaders/esvo.comp
    COMMENT "glslangValidator esvo.comp"
    VERBATIM)
  add_custom_command(
    OUTPUT ${VX_BENCH_SPV_DIR}/tree64.comp.h
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env ${VX_SPIRV_TARGET_ENV} --vn vx__tree64_spv_arr -o ${VX_BENCH_SPV_DIR}/tree64.comp.h
            ${CMAKE_CURRENT_LIST_DIR}/shaders/tree64.comp
    DEPENDS ${CMAKE_CURRENT_LIST_DIR}/shaders/tree64.comp
    COMMENT "glslangValidator tree64.comp"
    VERBATIM)
  add_executable(render_bench ${CMAKE_CURRENT_LIST_DIR}/render_bench.c ${CMAKE_CURRENT_LIST_DIR}/esvo.c
                 ${CMAKE_CURRENT_LIST_DIR}/tree64.c ${VX_BENCH_SPV_DIR}/esvo.comp.h ${VX_BENCH_SPV_DIR}/tree64.comp.h)
  target_include_directories(render_bench PRIVATE ${VX_BENCH_SPV_DIR})
  target_link_libraries(render_bench PRIVATE vx_render vx_convert vx_formats vx_svo)
endif()
