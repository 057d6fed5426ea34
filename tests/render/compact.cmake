# The compact GPU layout (render/compact.h, issue 18) against the models' own
# voxel lists: generated scenes, the corpus .vox scenes and, with the mesh
# converter, a textured glTF (exact RGBA). CPU only.
vx_add_test(test_compact SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_compact.c LIBS vx_trace vx_convert vx_formats vx_svo)
if(TARGET vx_conv_mesh)
  target_link_libraries(test_compact PRIVATE vx_conv_mesh)
  target_compile_definitions(test_compact PRIVATE VX_TEST_HAVE_MESH)
endif()
# The compact layout's trace kernel against trace.comp on the same scenes,
# pixel by pixel (lavapipe in CI).
if(VX_WITH_VULKAN)
  vx_add_test(test_compact_gpu SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_compact_gpu.c
              LIBS vx_render vx_trace vx_convert vx_formats vx_svo)
  # two ctest entries of the one binary (VX_TEST_ONLY): the generated scenes, and the walk's path, the start
  # paths and the corpus (ck11's path tests doubled its time: 658 s whole under the sanitizers on a loaded
  # 2-core machine, against the 900 s timeout)
  set_tests_properties(test_compact_gpu PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp;VX_TEST_ONLY=test_generated,test_seams,test_inside_leaf,test_deep,test_start_table,test_uniform_cubes,test_attr_parts")
  add_test(NAME test_compact_gpu_paths COMMAND test_compact_gpu)
  # 1800 s: 785 s in Release on CI's cold shader cache (the 2-core emulation of stop 55), against ctest's 900
  set_tests_properties(test_compact_gpu_paths PROPERTIES TIMEOUT 1800 ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp;VX_TEST_ONLY=test_path_start,test_path_records,test_corpus")
  # the compact kernels' forced starts of every depth over four models, paged too: 785 s in Release on a cold
  # shader cache, lavapipe compiling per-scene variants; under the sanitizers the starts' host code runs in
  # test_render_gpu's test_path_start and this entry's records and corpus (tests/CMakeLists.txt vx_sanitize_trim)
  # and the corpus files' frames (89 s under ASan, stop 60): the compact build over real files runs under the
  # sanitizers in test_compact_passes' corpus frames
  vx_sanitize_trim(test_compact_gpu_paths SKIP test_path_start test_corpus$)
  vx_test_cost(test_compact_gpu_paths 785)
  vx_test_cost(test_compact_gpu 213)
  # scenes of one instance in the descriptors' GPU form (VX_GPU_NODE_FORM=gpu): both kernels' lean walks (DEEP 0:
  # the start table's and the uniform cubes' models; DEEP 1: the generated 10-level model), which GPUs run and
  # lavapipe's file form does not (trace_compact.comp and trace_common.glsl LEAN; issue 18, lean3)
  add_test(NAME test_compact_gpu_gpu_form COMMAND test_compact_gpu)
  set_tests_properties(test_compact_gpu_gpu_form PROPERTIES TIMEOUT 900 ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp;VX_TEST_ONLY=test_generated,test_inside_leaf,test_uniform_cubes;VX_GPU_NODE_FORM=gpu")
  # (not the start table's frames, 63 s in Release on a cold shader cache: the DEEP 0 lean walk runs in the uniform
  # cubes' models here, the start records on every device in test_compact_gpu; stop 60, docs/TESTING.md)
  # the GPU form's compact host code runs under the sanitizers in test_compact_passes_gpu_form
  vx_sanitize_trim(test_compact_gpu_gpu_form DISABLE)
  # under the sanitizers the start table's frames (63 s of lavapipe in Release) are left out: the host code that
  # writes the start records runs in test_compact_gpu_paths' test_path_records (stop 59, docs/TESTING.md); and the
  # uniform cubes' frames (44 s under ASan, stop 60): the build's marking pass runs in every compact build
  vx_sanitize_trim(test_compact_gpu SKIP test_start_table test_uniform_cubes)
  if(TARGET vx_conv_mesh)
    target_link_libraries(test_compact_gpu PRIVATE vx_conv_mesh)
    target_compile_definitions(test_compact_gpu PRIVATE VX_TEST_HAVE_MESH)
  endif()
endif()
# The paged compact layout (scenes bigger than GPU memory): fly-throughs
# under a pool of a quarter of the pages, convergence to the whole layout's
# image, pages evicted and loaded elsewhere (lavapipe in CI).
if(VX_WITH_VULKAN)
  vx_add_test(test_compact_page SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_compact_page.c
              LIBS vx_render vx_trace vx_svo)
  set_tests_properties(test_compact_page PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp")
endif()
# Paging from files (the file source: pages cut from their models read again
# from the file, a host cache under a byte budget): the in-memory pager's page
# table, images and frames, a file cut mid-run (lavapipe in CI).
if(VX_WITH_VULKAN)
  vx_add_test(test_compact_page_file SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_compact_page_file.c
              LIBS vx_render vx_trace vx_svo)
  set_tests_properties(test_compact_page_file PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp")
endif()
# The pass pipeline and the GI methods over a compact scene (trace_common.glsl's
# COMPACT kernels): the plain layout's images bit for bit, the probe bake's
# bytes (lavapipe in CI).
if(VX_WITH_VULKAN AND TARGET vx_cones AND TARGET vx_photons)
  vx_add_test(test_compact_passes SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_compact_passes.c
              LIBS vx_photons vx_cones vx_probes vx_render vx_trace vx_convert vx_formats vx_svo)
  # two ctest entries of the one binary (VX_TEST_ONLY): the scenes' frames, and their probe bakes with the GI
  # methods that read them, each within its timeout under the sanitizers on a loaded machine
  set_tests_properties(test_compact_passes PROPERTIES TIMEOUT 900 ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp;VX_TEST_ONLY=_frames")
  # the corpus models' GI frames (cones, photons, probes over the compact layout) are lavapipe's time (over 240 s
  # under ASan); the generated scene's and the room's GI frames run the same host code under the sanitizers
  # (the room's GI frames too: the same host code as the generated scene's, which stay)
  vx_sanitize_trim(test_compact_passes SKIP test_corpus_gi_frames test_room_gi_frames)
  vx_test_cost(test_compact_passes 273)
  # the room's frames (one instance) in the descriptors' GPU form: the compact G-buffer's lean walk (trace_common.glsl
  # LEAN) against the plain one's, which lavapipe's file form does not run (issue 18, lean3)
  add_test(NAME test_compact_passes_gpu_form COMMAND test_compact_passes)
  set_tests_properties(test_compact_passes_gpu_form PROPERTIES TIMEOUT 900 ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp;VX_TEST_ONLY=test_room_frames;VX_GPU_NODE_FORM=gpu")
  add_test(NAME test_compact_passes_bakes COMMAND test_compact_passes)
  set_tests_properties(test_compact_passes_bakes PROPERTIES TIMEOUT 900 ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp;VX_TEST_ONLY=_bakes")
  # the corpus models' bakes: the generated scene's and the room's bakes run the same host code under the sanitizers
  vx_sanitize_trim(test_compact_passes_bakes SKIP test_corpus_bakes)
endif()
# The compact layout built model by model from a file (vx_compact_build_reader,
# svo/svo.h's model reader): the whole-scene build's words, damaged models. CPU only.
vx_add_test(test_compact_load SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_compact_load.c
            LIBS vx_trace vx_convert vx_formats vx_svo)
if(TARGET vx_conv_mesh)
  target_link_libraries(test_compact_load PRIVATE vx_conv_mesh)
  target_compile_definitions(test_compact_load PRIVATE VX_TEST_HAVE_MESH)
endif()
# The render scene from a model reader (vx_render_scene_create_reader): the
# whole read's frames pixel for pixel (lavapipe in CI).
if(VX_WITH_VULKAN)
  vx_add_test(test_compact_load_gpu SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_compact_load_gpu.c
              LIBS vx_render vx_trace vx_svo)
  set_tests_properties(test_compact_load_gpu PROPERTIES ENVIRONMENT
                       "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp")
endif()
