# The scene out to .glb and .vdb (convert/export.h): vx_conv_export, with
# each writer where its shim is built (formats/voxmesh.cmake's vx_glb over
# tinygltf, formats/vdb.cmake's vx_vdb over OpenVDB); export.c keeps the
# functions of a missing writer, which then fail with VX_ERR_UNSUPPORTED.
add_library(vx_conv_export STATIC ${CMAKE_CURRENT_LIST_DIR}/export.c ${CMAKE_CURRENT_LIST_DIR}/export_cells.c)
target_link_libraries(vx_conv_export PUBLIC vx_svo vx_core m)
if(TARGET vx_glb)
  target_sources(vx_conv_export PRIVATE ${CMAKE_CURRENT_LIST_DIR}/export_glb.c)
  target_link_libraries(vx_conv_export PUBLIC vx_glb vx_voxmesh)
  target_compile_definitions(vx_conv_export PRIVATE VX_HAVE_GLB=1)
endif()
if(TARGET vx_vdb)
  target_sources(vx_conv_export PRIVATE ${CMAKE_CURRENT_LIST_DIR}/export_vdb.c)
  target_link_libraries(vx_conv_export PUBLIC vx_vdb)
  target_compile_definitions(vx_conv_export PRIVATE VX_HAVE_VDB=1)
endif()
