# svo_view: the editor's operations in-process (leak-checked), then the
# window tests under Xvfb (the test re-executes itself with xvfb-run -a when
# DISPLAY is unset, and skips the window tests when neither is available).
if(TARGET svo_view)
  add_executable(test_view ${CMAKE_CURRENT_LIST_DIR}/test_view.c ${CMAKE_SOURCE_DIR}/tools/svo_view/editor.c ${CMAKE_SOURCE_DIR}/tools/svo_view/settings.c
                         ${CMAKE_SOURCE_DIR}/tools/svo_view/voxels.c ${CMAKE_SOURCE_DIR}/tools/svo_view/batch.c)
  target_link_libraries(test_view PRIVATE vx_tool vx_probes vx_render vx_convert vx_conv_export vx_image vx_svo m) # vx_tool: settings.c's parsing
  if(TARGET vx_conv_vdb) # export FILE.vdb read back
    target_link_libraries(test_view PRIVATE vx_conv_vdb)
    target_compile_definitions(test_view PRIVATE VX_VIEW_VDB=1)
  endif()
  target_compile_definitions(test_view PRIVATE VX_CORPUS_DIR_DEFAULT="${VX_CORPUS_DIR}" VX_VIEW_PANELS=$<BOOL:$<TARGET_PROPERTY:svo_view,VX_PANELS>>)
  add_dependencies(test_view svo_view)
  add_test(NAME test_view_editor COMMAND test_view --editor)
  # svo_render is passed by path, without a build dependency: when it is not
  # built the screenshot comparison skips. Lavapipe's and X's modules are
  # unloaded at exit, so their leaks cannot be attributed or suppressed
  # (as for test_svo_bake); our code's leak check is test_view_editor.
  add_test(NAME test_view COMMAND test_view $<TARGET_FILE:svo_view> ${CMAKE_BINARY_DIR}/bin/svo_render
           ${CMAKE_CURRENT_BINARY_DIR}/view_out)
  set_tests_properties(test_view PROPERTIES TIMEOUT 600 ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
  vx_test_cost(test_view 100)
  # svo_view's GI frames (pathtrace, cones, photons, the material edits, the GI mode switch) as a test of their own:
  # in one entry with the rest test_view took 411 s of its 600 s on a clean clone beside a helper's builds and timed
  # out once at 600 s under heavier load (stop 66); apart, each has room
  add_test(NAME test_view_gi COMMAND test_view $<TARGET_FILE:svo_view> ${CMAKE_BINARY_DIR}/bin/svo_render
           ${CMAKE_CURRENT_BINARY_DIR}/view_gi_out gi)
  set_tests_properties(test_view_gi PROPERTIES TIMEOUT 600 ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
  vx_test_cost(test_view_gi 200)
  # Under the sanitizers: the material edits' and the GI options' scripts (svo_view's frames against svo_render's
  # for pathtrace, cones and photons: 105 s of lavapipe in Release, about 200 under ASan) and the GI mode switch are
  # the release run's, and so is the photons' frame against svo_render's (68 s under ASan, stop 60); svo_view's GI
  # host code runs under ASan in test_scripted_lights_gi (pathtrace, cones and photons, an edit and its undo), the
  # material edits in test_view_editor (tests/CMakeLists.txt vx_sanitize_trim; test_view took 577 s of its 600 s
  # timeout in CI's sanitizer run, stop 57; these are test_view_gi's since stop 66)
  vx_sanitize_trim(test_view_gi SKIP test_scripted_materials_gi test_gi_mode test_photons_view)
  # the long scripts (a thousand random edits undone, ...) as a test of their own, run beside test_view
  add_test(NAME test_view_script COMMAND test_view $<TARGET_FILE:svo_view> ${CMAKE_BINARY_DIR}/bin/svo_render
           ${CMAKE_CURRENT_BINARY_DIR}/view_script_out script)
  set_tests_properties(test_view_script PROPERTIES TIMEOUT 600 ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()
vx_test_cost(test_view_script 90)
