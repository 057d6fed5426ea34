# probes: octahedral mapping, the CPU bake (box distances, furnace,
# determinism, shards), the .probes reader, probe GI against the path tracer.
if(VX_WITH_VULKAN)
  vx_add_test(test_probes SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_probes.c LIBS vx_probes vx_render vx_svo LABELS probes)
  # the placement from a model reader against vx_probe_place of the scene read whole (issue 18)
  vx_add_test(test_probe_place_reader SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_probe_place_reader.c
              LIBS vx_probes vx_render vx_svo LABELS probes)
  vx_add_test(test_probes_gpu SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_probes_gpu.c
              LIBS vx_probes vx_render vx_convert vx_formats vx_svo ${CMAKE_DL_LIBS}
              LABELS probes)
  # the path tracer with lights and materials (furnaces, analytic lights, a stiff emitter, GPU vs CPU)
  vx_add_test(test_pathtrace SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_pathtrace.c LIBS vx_probes vx_render vx_svo
              ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_pathtrace PROPERTIES TIMEOUT 600 ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  # under the sanitizers without the two long convergence checks (59 s of lavapipe under ASan, stop 60): the
  # tracer's host code runs in the furnaces, the lights and the GPU-against-CPU materials
  vx_sanitize_trim(test_pathtrace SKIP test_converges_to_itself test_stiff_emitter)
  # metal seen directly in the pass pipeline: a metal plate against the BRDF in double, the CPU path tracer
  # and the sky term's closed form; a diffuse plate unchanged
  vx_add_test(test_metal_direct SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_metal_direct.c LIBS vx_probes vx_render vx_svo
              ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_metal_direct PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  # glass seen directly in the pass pipeline: a glass slab in front of a lit floor against the closed form
  # (Fresnel in and out, the tint) and the CPU path tracer; a scene without glass unchanged
  vx_add_test(test_glass_direct SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_glass_direct.c LIBS vx_probes vx_render vx_svo
              ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_glass_direct PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  # glass thicker than the walks' old limits (a uniform slab of 600 cells, one of 300 alternating cells):
  # the passes, the CPU and the GPU path tracers against the closed form (render/trace.h vx__glass_walk_steps)
  vx_add_test(test_glass_thick SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_glass_thick.c LIBS vx_probes vx_render vx_svo
              ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_glass_thick PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  # opaque voxels against glass (a slab standing on a floor), seen through it: the passes, the CPU and the
  # GPU path tracers against the closed forms (emission; the sky through the glass)
  vx_add_test(test_glass_contact SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_glass_contact.c LIBS vx_photons vx_probes
              vx_render vx_svo ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_glass_contact PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  # what every gi method of the pass pipeline brings through glass: a pane of index 1 against no pane, and
  # gi=pathtrace's frame through a pane of index 1.5 against the reference path tracer
  vx_add_test(test_glass_gi SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_glass_gi.c LIBS vx_cones vx_photons vx_probes
              vx_render vx_svo ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_glass_gi PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  # metal's specular lobe in the probe modes: a mirror and a rough metal against the path tracer (CPU, GPU,
  # the pass pipeline's gi=probes and gi=lightfield)
  vx_add_test(test_metal_gi SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_metal_gi.c LIBS vx_probes vx_render vx_svo
              ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_metal_gi PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  # allocation failures on the GPU side: the render scene, the passes, the gi methods, the probe renderer
  vx_add_test(test_gpu_alloc_fail SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_gpu_alloc_fail.c LIBS vx_cones vx_photons
              vx_probes vx_render vx_svo ${CMAKE_DL_LIBS} LABELS probes)
  set_tests_properties(test_gpu_alloc_fail PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  set_tests_properties(test_probes_gpu PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp")
  # the descriptors' GPU form forced on CPU devices too (tests/render/render.cmake's *_gpu_form)
  add_test(NAME test_probes_gpu_gpu_form COMMAND test_probes_gpu)
  set_tests_properties(test_probes_gpu_gpu_form PROPERTIES TIMEOUT 900 LABELS probes ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_SOURCE_DIR}/tests/render/lsan.supp;VX_GPU_NODE_FORM=gpu")
  # less the bake with the sun's map (120 of its 260 s in Release on 2 cores, docs/TESTING.md, stop 59): the
  # other bakes walk the GPU form here, and on GPUs, where it is the default, the device runs bake the sun's map
  set_property(TEST test_probes_gpu_gpu_form APPEND PROPERTY ENVIRONMENT "VX_TEST_SKIP=test_gpu_bake_sun_map")
  # the sanitizer run leaves the repeat to the release run: the GPU form's upload runs under ASan in
  # test_render_edit_gpu_form and test_compact_passes_gpu_form (tests/CMakeLists.txt vx_sanitize_trim)
  vx_sanitize_trim(test_probes_gpu_gpu_form DISABLE)
  vx_test_cost(test_probes_gpu_gpu_form 173)
  vx_test_cost(test_probes_gpu 180)
  # the sun's map in the bake (78 s of lavapipe in Release): its host code is the renderer's shadow map
  # (test_render_smap runs under the sanitizers) and the bake's is the other bakes'
  # and the one-walk bake's comparison (33 s; the bake's host code is the other bakes'; stop 59)
  vx_sanitize_trim(test_probes_gpu SKIP test_gpu_bake_sun_map test_gpu_bake_one_walk)
  # .probes reader fuzz target; seeds written by svo_bake --cpu (tiny: res 16,
  # one probe and one shard of two)
  vx_add_fuzz(probes_fuzz ${CMAKE_SOURCE_DIR}/tests/fuzz/probes_fuzz.c LIBS vx_probes vx_render vx_svo
              SEEDS ${CMAKE_CURRENT_LIST_DIR}/fuzz_seeds ARGS -n 300)
endif()
if(VX_WITH_VULKAN AND VX_WITH_OIIO)
  add_test(NAME test_svo_bake COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_svo_bake.sh ${CMAKE_BINARY_DIR}/bin)
  # the tools' GPU runs leak inside lavapipe once its module is unloaded at
  # exit (unattributable, so not suppressible); the libraries' leak checks are
  # test_probes and test_probes_gpu
  set_tests_properties(test_svo_bake PROPERTIES TIMEOUT 300 ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
  # under the sanitizers without the two 3x3x3 bakes at R=32 (the kernels' edge rays; the same tool paths run in
  # the script's other bakes): the script took 247 s of CI's sanitizer run (stop 57; docs/TESTING.md, stop 59)
  vx_sanitize_trim(test_svo_bake ENV VX_BAKE_EDGE_RAYS=0)
endif()
if(VX_WITH_VULKAN)
  # rays through the probes' distance maps against the octree tracer
  vx_add_test(test_lightfield SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_lightfield.c LIBS vx_probes vx_render vx_svo
              LABELS probes)
endif()
vx_test_cost(test_svo_bake 100)
