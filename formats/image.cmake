# formats/image: PNG/EXR (and every format it knows) through OpenImageIO
# (library vx_image); without OpenImageIO (-DVX_WITH_OIIO=OFF, e.g. for the
# GPU machines, which lack it) vx_image writes and reads .pfm/.ppm/.pgm
# only, by its own code (image_pnm.c, used for those in both builds), so
# svo_render still builds.
if(VX_WITH_OIIO)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)
  add_library(vx_image STATIC ${CMAKE_CURRENT_SOURCE_DIR}/image_oiio.cpp ${CMAKE_CURRENT_SOURCE_DIR}/image_pnm.c)
  target_compile_definitions(vx_image PRIVATE VX_IMAGE_OIIO=1)
  target_link_libraries(vx_image PUBLIC vx_core PRIVATE PkgConfig::OIIO)
else()
  add_library(vx_image STATIC ${CMAKE_CURRENT_SOURCE_DIR}/image_pnm.c)
  target_link_libraries(vx_image PUBLIC vx_core)
endif()
