add_library(vx_convert STATIC ${CMAKE_CURRENT_LIST_DIR}/vox_import.c ${CMAKE_CURRENT_LIST_DIR}/vox_export.c)
target_link_libraries(vx_convert PUBLIC vx_svo vx_formats m)
