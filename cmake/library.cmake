# The installable library (issue 19): one shared libvoxkit made of the
# objects of the module libraries that this build has, the public headers
# under <prefix>/include/voxkit, a CMake package (find_package(voxkit),
# target voxkit::voxkit) and a pkg-config file (voxkit.pc).
#
# One library, not one per module: the modules are built as static
# libraries for the tools and tests; a shared library per module would need
# its own soname, export set and link order for each of up to 13 targets
# (vx_core .. vx_probes) while users mostly want all of them. The modules'
# objects are reused as they are (no second compile); the third-party
# libraries they use (zlib, Vulkan, tinygltf, OpenVDB, OpenImageIO, ...) are
# linked privately, so users link -lvoxkit only.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# VX_VERSION_STRING in svo/core.h must be the project version.
file(STRINGS ${CMAKE_SOURCE_DIR}/svo/core.h vx_core_version REGEX "^#define VX_VERSION_STRING ")
if(NOT vx_core_version STREQUAL "#define VX_VERSION_STRING \"${PROJECT_VERSION}\"")
  message(FATAL_ERROR "svo/core.h has '${vx_core_version}' but the project version is ${PROJECT_VERSION}")
endif()

set(VX_LIB_MODULES vx_core vx_svo vx_formats vx_voxmesh vx_glb vx_gltf vx_vdb vx_image vx_convert vx_conv_export vx_conv_file vx_conv_mesh_core vx_conv_mesh
                   vx_conv_vdb vx_trace vx_render vx_probes vx_photons vx_cones)
# public header -> the module that must be built for it to be installed
set(VX_LIB_HEADERS
    svo/core.h:vx_core svo/svo.h:vx_svo svo/edit.h:vx_svo formats/vox.h:vx_formats formats/voxmesh.h:vx_voxmesh formats/glb.h:vx_glb formats/gltf.h:vx_gltf formats/vdb.h:vx_vdb
    formats/image.h:vx_image convert/convert.h:vx_convert convert/export.h:vx_conv_export convert/file.h:vx_conv_file convert/mesh.h:vx_conv_mesh convert/volume.h:vx_conv_vdb
    render/render.h:vx_trace render/pipeline.h:vx_render probes/probes.h:vx_probes
    photons/photons.h:vx_photons cones/cones.h:vx_cones)

set(VX_LIB_OBJECTS)
set(VX_LIB_BUILT)
foreach(m ${VX_LIB_MODULES})
  if(TARGET ${m})
    list(APPEND VX_LIB_OBJECTS $<TARGET_OBJECTS:${m}>)
    list(APPEND VX_LIB_BUILT ${m})
  endif()
endforeach()

# Public headers are installed with their includes of each other rewritten
# ("svo/core.h" -> "voxkit/svo/core.h"), so users need -I<prefix>/include
# only and write #include <voxkit/svo/svo.h>. Staged at configure time.
set(VX_LIB_STAGE ${CMAKE_BINARY_DIR}/include)
configure_file(${CMAKE_CURRENT_LIST_DIR}/version.h.in ${VX_LIB_STAGE}/voxkit/version.h @ONLY)
configure_file(${CMAKE_CURRENT_LIST_DIR}/version.c.in ${CMAKE_BINARY_DIR}/voxkit_version.c @ONLY)
set(VX_LIB_INSTALLED)
foreach(spec ${VX_LIB_HEADERS})
  string(REPLACE ":" ";" parts ${spec})
  list(GET parts 0 h)
  list(GET parts 1 m)
  if(TARGET ${m})
    list(APPEND VX_LIB_INSTALLED ${h})
  endif()
endforeach()
foreach(h ${VX_LIB_INSTALLED})
  set_property(DIRECTORY ${CMAKE_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/${h})
  file(READ ${CMAKE_SOURCE_DIR}/${h} text)
  string(REGEX MATCHALL "#include \"[^\"]+\"" incs "${text}")
  foreach(inc ${incs})
    string(REGEX REPLACE "#include \"([^\"]+)\"" "\\1" inc "${inc}")
    if(NOT inc IN_LIST VX_LIB_INSTALLED)
      message(FATAL_ERROR "public header ${h} includes ${inc}, which is not installed")
    endif()
  endforeach()
  string(REGEX REPLACE "#include \"(svo|formats|convert|render|probes|photons)/" "#include \"voxkit/\\1/" text "${text}")
  file(WRITE ${VX_LIB_STAGE}/voxkit/${h}.tmp "${text}")
  configure_file(${VX_LIB_STAGE}/voxkit/${h}.tmp ${VX_LIB_STAGE}/voxkit/${h} COPYONLY)
  file(REMOVE ${VX_LIB_STAGE}/voxkit/${h}.tmp)
  get_filename_component(dir ${h} DIRECTORY)
  install(FILES ${VX_LIB_STAGE}/voxkit/${h} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/voxkit/${dir})
endforeach()
install(FILES ${VX_LIB_STAGE}/voxkit/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/voxkit)

# soname: libvoxkit.so.MAJOR, and libvoxkit.so.0.MINOR while the major
# version is 0 (every 0.x release may change the ABI).
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(VX_SOVERSION 0.${PROJECT_VERSION_MINOR})
else()
  set(VX_SOVERSION ${PROJECT_VERSION_MAJOR})
endif()
add_library(voxkit SHARED ${VX_LIB_OBJECTS} ${CMAKE_BINARY_DIR}/voxkit_version.c)
target_include_directories(voxkit PRIVATE ${VX_LIB_STAGE}
                           INTERFACE $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
# The modules' own link dependencies (system and C++ libraries), privately;
# their archives add nothing since all of their objects are already in.
target_link_libraries(voxkit PRIVATE ${VX_LIB_BUILT})
set_target_properties(voxkit PROPERTIES VERSION ${PROJECT_VERSION} SOVERSION ${VX_SOVERSION}
                      LINKER_LANGUAGE CXX)
# Exports: cmake/voxkit.map (the C API only). --no-undefined: every symbol
# is resolved at link time (not under sanitizers, whose runtime the program
# brings with clang).
target_link_options(voxkit PRIVATE -Wl,--version-script=${CMAKE_CURRENT_LIST_DIR}/voxkit.map)
set_property(TARGET voxkit APPEND PROPERTY LINK_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/voxkit.map)
if(NOT VX_SANITIZE AND NOT CMAKE_C_FLAGS MATCHES "sanitize" AND NOT CMAKE_CXX_FLAGS MATCHES "sanitize")
  target_link_options(voxkit PRIVATE -Wl,--no-undefined)
endif()

install(TARGETS voxkit EXPORT voxkitTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Development)
install(EXPORT voxkitTargets NAMESPACE voxkit:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/voxkit)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/voxkitConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/voxkitConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/voxkit)
# 0.x: only the same minor version is compatible (as the soname says).
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(vx_compat SameMinorVersion)
else()
  set(vx_compat SameMajorVersion)
endif()
write_basic_package_version_file(${CMAKE_BINARY_DIR}/voxkitConfigVersion.cmake COMPATIBILITY ${vx_compat})
install(FILES ${CMAKE_BINARY_DIR}/voxkitConfig.cmake ${CMAKE_BINARY_DIR}/voxkitConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/voxkit)

# pkg-config: relocatable (prefix found from the .pc file's own folder).
file(RELATIVE_PATH VX_PC_RELPREFIX /p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /p)
string(REGEX REPLACE "/$" "" VX_PC_RELPREFIX "${VX_PC_RELPREFIX}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/voxkit.pc.in ${CMAKE_BINARY_DIR}/voxkit.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/voxkit.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# The tools (statically linked) go to <prefix>/bin.
foreach(t vox2svo svo_info svo_render svo_view svo_bake)
  if(TARGET ${t})
    install(TARGETS ${t} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()
