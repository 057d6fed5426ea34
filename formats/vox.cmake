# zlib: Teardown's .vox files hold each model's voxels as a zlib stream (TDCZ)
find_package(ZLIB REQUIRED)
add_library(vx_formats STATIC ${CMAKE_CURRENT_LIST_DIR}/vox.c ${CMAKE_CURRENT_LIST_DIR}/vox_write.c)
target_link_libraries(vx_formats PUBLIC vx_core PRIVATE ZLIB::ZLIB)
