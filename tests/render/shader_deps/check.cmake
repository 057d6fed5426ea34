# tests/render/shader_deps/check.cmake - ctest's test_shader_deps (cmake -P; tests/render/shader_deps.cmake passes
# SRC this folder, WORK a scratch folder, GEN and MAKE the build's generator and make program, SHADERS
# cmake/shaders.cmake, GLSLANG the compiler). The build rules of the embedded kernels take the files a kernel
# includes from the compiler's depfile (vx_spirv_header), not from lists kept by hand; this checks on a copy of
# the small tree in this folder, with the generator the build itself uses, that touching each file rebuilds
# exactly the kernels that include it: through a nested include, from an INCLUDES folder, under a -D define (and
# not in the same kernel built without it), a generated include, and nothing on a build with no change. A few
# seconds: a second's wait before each touch, so that the touched file is newer than the headers on any clock.
foreach(v SRC WORK GEN SHADERS GLSLANG)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "check.cmake: -D${v}= is missing")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK})
file(COPY ${SRC}/ DESTINATION ${WORK}/src PATTERN check.cmake EXCLUDE)
set(make_arg)
if(MAKE)
  set(make_arg -DCMAKE_MAKE_PROGRAM=${MAKE})
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${WORK}/src -B ${WORK}/build -G ${GEN} ${make_arg}
                        -DVX_SHADERS_CMAKE=${SHADERS} -DGLSLANG_VALIDATOR=${GLSLANG}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the small tree failed:\n${out}")
endif()

set(failed 0)
# Builds the small tree; the rules that ran (their COMMENT spv:NAME in the output) must be the list want.
function(build step)
  set(want ${ARGN})
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}/build RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${step}: the build failed:\n${out}")
  endif()
  string(REGEX MATCHALL "spv:[a-z_]+" ran "${out}")
  string(REPLACE "spv:" "" ran "${ran}")
  list(SORT ran)
  list(SORT want)
  if("${ran}" STREQUAL "${want}")
    message(STATUS "ok: ${step}: rebuilt [${ran}]")
  else()
    message(SEND_ERROR "${step}: rebuilt [${ran}], expected [${want}]\n${out}")
    set(failed 1 PARENT_SCOPE)
  endif()
endfunction()
# Touches FILE (relative to the copy) after a second's wait, builds, expects the rules listed.
function(touch_build file)
  execute_process(COMMAND ${CMAKE_COMMAND} -E sleep 1)
  file(TOUCH ${WORK}/src/${file})
  build("touch ${file}" ${ARGN})
  set(failed ${failed} PARENT_SCOPE)
endfunction()

build("first build" a b_on b_off c d)
foreach(h a b_on b_off c d)
  file(READ ${WORK}/build/${h}.comp.h text LIMIT 4096)
  if(NOT text MATCHES "vx_${h}")
    message(SEND_ERROR "${h}.comp.h holds no array vx_${h}")
    set(failed 1)
  endif()
endforeach()
build("no change")
touch_build(shaders/y.glsl a b_on)   # x.glsl's include, and b.comp's under WITH_Y only
touch_build(shaders/x.glsl a)
touch_build(lib/z.glsl a)            # from the INCLUDES folder
touch_build(shaders/gen.in c)        # regenerates gen.glsl, which c.comp includes
touch_build(shaders/b.comp b_on b_off)
touch_build(shaders/d.comp d)
build("no change again")
if(failed)
  message(FATAL_ERROR "test_shader_deps: some edit did not rebuild exactly the kernels that include the file")
endif()
