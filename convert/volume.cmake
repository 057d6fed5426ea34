# OpenVDB grids -> svo (needs the vx_vdb shim from formats/vdb.cmake).
if(TARGET vx_vdb)
  add_library(vx_conv_vdb STATIC ${CMAKE_CURRENT_LIST_DIR}/volume.c)
  target_link_libraries(vx_conv_vdb PUBLIC vx_vdb vx_svo vx_core m)
endif()
