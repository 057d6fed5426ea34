# Input files by extension (convert/file.h), with whichever converters this
# build has. Fragments are included in name order, so this one sees the
# readers (formats/) but not yet vx_conv_mesh / vx_conv_vdb: it tests the
# targets their fragments (mesh.cmake, volume.cmake) are conditioned on.
add_library(vx_conv_file STATIC ${CMAKE_CURRENT_LIST_DIR}/file.c)
target_link_libraries(vx_conv_file PUBLIC vx_convert)
if(TARGET vx_gltf)
  target_link_libraries(vx_conv_file PUBLIC vx_conv_mesh)
  target_compile_definitions(vx_conv_file PRIVATE VX_HAVE_MESH=1)
endif()
if(TARGET vx_vdb)
  target_link_libraries(vx_conv_file PUBLIC vx_conv_vdb)
  target_compile_definitions(vx_conv_file PRIVATE VX_HAVE_VDB=1)
endif()
