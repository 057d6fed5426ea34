# formats/image: PNG/EXR (and every format it knows) through OpenImageIO
# (library vx_image); without OpenImageIO (-DVX_WITH_OIIO=OFF, e.g. for the
# GPU machines, which lack it) vx_image writes and reads .pfm/.ppm/.pgm
# only, by its own code (image_pnm.c, used for those in both builds), so
# svo_render still builds.
#
# With OpenImageIO its shim is a module of its own, libvoxkit_oiio.so
# (image_oiio.cpp), that image.c loads at the first image it needs it for:
# OpenImageIO's 250 libraries linked into a tool cost each process 0.35 s of
# dynamic loading (image.c says where the module is looked for). In the build
# tree it is <build>/voxkit/, installed <libdir>/voxkit/.
if(VX_WITH_OIIO)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)
  add_library(voxkit_oiio MODULE ${CMAKE_CURRENT_SOURCE_DIR}/image_oiio.cpp)
  # vx_core's vx_fail and allocation (malloc: the caller frees what a read returns with vx_free)
  target_link_libraries(voxkit_oiio PRIVATE vx_core PkgConfig::OIIO)
  set_target_properties(voxkit_oiio PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/voxkit
                                               CXX_VISIBILITY_PRESET hidden)
  add_library(vx_image STATIC ${CMAKE_CURRENT_SOURCE_DIR}/image.c ${CMAKE_CURRENT_SOURCE_DIR}/image_pnm.c)
  include(GNUInstallDirs)
  file(RELATIVE_PATH vx_image_from_bin /p/${CMAKE_INSTALL_BINDIR} /p/${CMAKE_INSTALL_LIBDIR}/voxkit)
  target_compile_definitions(vx_image PRIVATE VX_IMAGE_OIIO=1 VX_IMAGE_MODULE_FROM_BIN="${vx_image_from_bin}"
                                              VX_IMAGE_MODULE_DIR="${CMAKE_INSTALL_FULL_LIBDIR}/voxkit")
  target_link_libraries(vx_image PUBLIC vx_core PRIVATE ${CMAKE_DL_LIBS})
  # whatever links vx_image can write a PNG once built: the module comes with it
  add_dependencies(vx_image voxkit_oiio)
  install(TARGETS voxkit_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/voxkit)
else()
  add_library(vx_image STATIC ${CMAKE_CURRENT_SOURCE_DIR}/image.c ${CMAKE_CURRENT_SOURCE_DIR}/image_pnm.c)
  target_link_libraries(vx_image PUBLIC vx_core)
endif()
# 8-bit PNGs through libpng's simplified API (libpng-dev) where found, in both builds: a process that writes a PNG
# does not load OpenImageIO (image.c)
find_package(PNG)
if(PNG_FOUND)
  target_compile_definitions(vx_image PRIVATE VX_IMAGE_PNG=1)
  target_link_libraries(vx_image PRIVATE PNG::PNG)
endif()
