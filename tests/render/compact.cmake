# The compact GPU layout (render/compact.h, issue 18) against the models' own
# voxel lists: generated scenes, the corpus .vox scenes and, with the mesh
# converter, a textured glTF (exact RGBA). CPU only.
vx_add_test(test_compact SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_compact.c LIBS vx_trace vx_convert vx_formats vx_svo)
if(TARGET vx_conv_mesh)
  target_link_libraries(test_compact PRIVATE vx_conv_mesh)
  target_compile_definitions(test_compact PRIVATE VX_TEST_HAVE_MESH)
endif()
