# Render tests: CPU-only parts always; GPU against the CPU reference on
# lavapipe (skipped when no Vulkan device exists).
# the CPU reference needs only the plain-C trace layer (no Vulkan)
vx_add_test(test_render_cpu SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_render_cpu.c LIBS vx_trace vx_svo)
if(VX_WITH_VULKAN)
  set(VX_RENDER_LSAN "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp")
  if(EXISTS ${CMAKE_CURRENT_LIST_DIR}/test_render_gpu.c)
    vx_add_test(test_render_gpu SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_render_gpu.c
                LIBS vx_render vx_convert vx_formats vx_svo)
    set_tests_properties(test_render_gpu PROPERTIES ENVIRONMENT "${VX_RENDER_LSAN}")
  endif()
endif()
# The hits frame on the bench's deep terrain (issue 21: it hung on an H100).
if(VX_WITH_VULKAN AND EXISTS ${CMAKE_CURRENT_LIST_DIR}/test_render_hits.c)
  vx_add_test(test_render_hits SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_render_hits.c
              LIBS vx_render vx_svo)
  set_tests_properties(test_render_hits PROPERTIES ENVIRONMENT "${VX_RENDER_LSAN}")
endif()
# The beam pass against the frame without it (issue 21): same hits, fewer steps.
if(VX_WITH_VULKAN AND EXISTS ${CMAKE_CURRENT_LIST_DIR}/test_render_beam.c)
  vx_add_test(test_render_beam SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_render_beam.c
              LIBS vx_render vx_svo)
  set_tests_properties(test_render_beam PROPERTIES ENVIRONMENT "${VX_RENDER_LSAN}")
endif()
# The light's depth map that clips shadow rays (issue 21): the same pixels, fewer steps.
if(VX_WITH_VULKAN AND EXISTS ${CMAKE_CURRENT_LIST_DIR}/test_render_smap.c)
  vx_add_test(test_render_smap SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_render_smap.c
              LIBS vx_render vx_svo)
  set_tests_properties(test_render_smap PROPERTIES ENVIRONMENT "${VX_RENDER_LSAN}")
endif()
# vx_render_scene_update_model: edited models' appends against scenes made from scratch.
if(VX_WITH_VULKAN AND EXISTS ${CMAKE_CURRENT_LIST_DIR}/test_render_edit.c)
  vx_add_test(test_render_edit SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_render_edit.c LIBS vx_render vx_svo)
  set_tests_properties(test_render_edit PROPERTIES ENVIRONMENT "${VX_RENDER_LSAN}")
endif()
# The float walk's error-free sums reach the driver as NoContraction
# arithmetic (issue 18: the NVIDIA compiler folded one that was not). Reads
# the embedded SPIR-V headers only: no GPU, no library.
if(VX_WITH_VULKAN AND EXISTS ${CMAKE_CURRENT_LIST_DIR}/test_spirv_precise.c)
  vx_add_test(test_spirv_precise SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_spirv_precise.c)
  target_include_directories(test_spirv_precise PRIVATE ${CMAKE_BINARY_DIR}/render/spv)
  add_dependencies(test_spirv_precise vx_render)
  # the kernels whose walk must be non-contracted (cmake/shaders.cmake), checked each
  string(JOIN " " walk_precise ${VX_WALK_PRECISE_KERNELS})
  target_compile_definitions(test_spirv_precise PRIVATE "VX_WALK_PRECISE_KERNELS=\"${walk_precise}\"")
  if(TARGET vx_probes)
    # the path tracer's kernel (probes/shaders/probe.comp) too
    target_include_directories(test_spirv_precise PRIVATE ${CMAKE_BINARY_DIR}/probes/spv)
    target_compile_definitions(test_spirv_precise PRIVATE VX_TEST_PROBES=1)
    add_dependencies(test_spirv_precise vx_probes)
  endif()
  if(TARGET vx_cones)
    # the cones' kernels (cones/shaders: their walks WALK_PRECISE)
    target_include_directories(test_spirv_precise PRIVATE ${CMAKE_BINARY_DIR}/cones/spv)
    target_compile_definitions(test_spirv_precise PRIVATE VX_TEST_CONES=1)
    add_dependencies(test_spirv_precise vx_cones)
  endif()
  if(TARGET vx_photons)
    # the photons' kernel (photons/shaders/photon.comp)
    target_include_directories(test_spirv_precise PRIVATE ${CMAKE_BINARY_DIR}/photons/spv)
    target_compile_definitions(test_spirv_precise PRIVATE VX_TEST_PHOTONS=1)
    add_dependencies(test_spirv_precise vx_photons)
  endif()
endif()
# The same tests with the descriptors' GPU form forced (issue 21: CPU devices
# such as lavapipe keep the file's form in the node buffer, GPUs the GPU form;
# VX_GPU_NODE_FORM=gpu makes lavapipe run the GPU form's upload, edits and
# kernels, so CI tests both forms).
if(VX_WITH_VULKAN)
  foreach(t test_render_gpu test_render_beam test_render_edit)
    if(TARGET ${t})
      add_test(NAME ${t}_gpu_form COMMAND ${t})
      set_tests_properties(${t}_gpu_form PROPERTIES TIMEOUT 900 ENVIRONMENT "${VX_RENDER_LSAN};VX_GPU_NODE_FORM=gpu")
    endif()
  endforeach()
endif()
