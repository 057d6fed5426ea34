# formats/image: PNG/EXR through OpenImageIO (library vx_image).
if(VX_WITH_OIIO)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)
  add_library(vx_image STATIC ${CMAKE_CURRENT_SOURCE_DIR}/image_oiio.cpp)
  target_link_libraries(vx_image PUBLIC vx_core PRIVATE PkgConfig::OIIO)
endif()
