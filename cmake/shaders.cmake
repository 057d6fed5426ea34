# A compute kernel's spec in the shader lists of render/render.cmake and
# probes/probes.cmake: NAME:FILE[:DEFINE] -> the embedded kernel's name, its
# source FILE.comp and the glslangValidator define (-DDEFINE, or empty); the
# kernels of VX_WALK_PRECISE_KERNELS get -DWALK_PRECISE too (vx_walk_defs). With a
# fifth argument, the folder the embedded header NAME.comp.h is written to, a
# listed kernel's header is recorded for test_spirv_precise (vx_walk_defs).
function(vx_shader_spec spec name_var file_var defs_var)
  string(REPLACE ":" ";" parts ${spec})
  list(GET parts 0 name)
  list(GET parts 1 file)
  set(defs)
  list(LENGTH parts nparts)
  if(nparts GREATER 2)
    list(GET parts 2 def)
    set(defs -D${def})
  endif()
  if(ARGC GREATER 4)
    vx_walk_defs(${name} defs ${ARGV4}/${name}.comp.h)
  else()
    vx_walk_defs(${name} defs)
  endif()
  set(${name_var} ${name} PARENT_SCOPE)
  set(${file_var} ${file} PARENT_SCOPE)
  set(${defs_var} ${defs} PARENT_SCOPE)
endfunction()

# The one rule for the octree walk's float arithmetic (WALK_PRECISE, render/shaders/trace_common.glsl: every float
# operation of the walk `precise`, so the driver may not contract it into fused multiply-adds). The NVIDIA compiler
# (driver 580) contracts each pipeline on its own: the plain and the compact layout are two pipelines of one kernel
# (the COMPACT constant), and with the walk contractible 5 of 380 hits of test_compact_passes' room came out one
# float step apart in depth (issue 18, H200; lavapipe never contracts, so no lavapipe render can show it). So every
# kernel whose walk's results are compared between the layouts (test_compact_passes) or between the separate
# passes and the merged frame.comp walks non-contracted: the pass pipeline's G-buffer, direct (shadow rays) and AO
# passes and the merged frame (and its display form), the cones' voxelization, injection (shadow rays) and gi
# pass, and the photons' kernel. Names are the embedded arrays' (vx__NAME_spv_arr); test_spirv_precise checks each
# listed kernel's walk for the marks, through a table generated from this list and the headers the kernels' build
# rules record (vx_walk_defs' third argument), so a kernel added here is checked without editing the test; it fails
# on a listed name whose header no rule recorded (not built here, or its rule does not pass the header). So the rule is this list, not "every walking kernel": not listed (docs/PERFORMANCE.md, issue 18,
# branch prec2) are trace.comp and trace_precise, the single-shader tracers of vx_render_frame and the primary-ray
# benchmarks (trace.comp non-contracted cost 2.7% on eph_monu1's close-up on the H200; test_passes compares its colour
# mode with the passes bit for bit, and on the H200 they agreed with its walk contractible), trace_compact.comp (its
# own walk, which the define does not reach) and probe.comp's kernels (probes/: the bake's probe and probe_one, the
# render passes' probe_pt), which walk non-contracted through their own define (probe.comp: their path too; the
# bake's walk contractible gave the animated demo's plain and compact bakes 150 hit distances one float step apart
# on the H200, issue 18, branch rdr4).
set(VX_WALK_PRECISE_KERNELS gbuffer frame frame_display direct ao cone_voxelize cone_inject cone_trace photon)

# Appends -DWALK_PRECISE to the list defs_var where name (the embedded array's) is in VX_WALK_PRECISE_KERNELS;
# the optional third argument, the kernel's embedded header (absolute path), is then recorded in the global
# property VX_WALK_PRECISE_HEADERS as NAME=HEADER (read by tests/render/render.cmake's table for
# test_spirv_precise).
function(vx_walk_defs name defs_var)
  if(name IN_LIST VX_WALK_PRECISE_KERNELS)
    set(${defs_var} ${${defs_var}} -DWALK_PRECISE PARENT_SCOPE)
    if(ARGC GREATER 2)
      set_property(GLOBAL APPEND PROPERTY VX_WALK_PRECISE_HEADERS "${name}=${ARGV2}")
    endif()
  endif()
endfunction()

# The Vulkan environment every kernel is compiled for (glslangValidator --target-env in each build rule; the SPIR-V
# 1.3 of Vulkan 1.1, what the device layer asks for) and validated for (tests/render/spirv_valid.cmake: spirv-val
# --target-env): one setting, so the test checks the modules against the rules they were built by.
set(VX_SPIRV_TARGET_ENV vulkan1.1)

# The one build rule of an embedded kernel: glslangValidator compiles the GLSL compute shader SRC into OUT, a C
# header holding the SPIR-V as the array ARRAY (const uint32_t ARRAY[]), for VX_SPIRV_TARGET_ENV.
#   INCLUDES dirs...  searched by its #include "..." after SRC's own folder (-I)
#   DEFINES -DX...    passed as they are (vx_shader_spec's defs)
#   DEPENDS files...  generated files it includes (probes' beam_body.glsl): named so that the rule that writes them
#                     runs first; the depfile only knows a file once it exists
#   COMMENT text      the build's line (default "glslangValidator SRC's name")
# The files SRC includes are not listed by hand: glslangValidator writes them to OUT.d (--depfile: every file it
# opened, absolute paths), which the Makefile and Ninja generators read (DEPFILE), so an edit of any .glsl rebuilds
# exactly the headers whose source includes it, directly or through another include (docs/TESTING.md says how that
# was checked, and tests/render/shader_deps.cmake checks it on a small tree in every ctest run). --depfile does not
# change the SPIR-V.
function(vx_spirv_header out src array)
  cmake_parse_arguments(PARSE_ARGV 3 arg "" "COMMENT" "INCLUDES;DEFINES;DEPENDS")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "vx_spirv_header: unknown arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()
  find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
  set(incs)
  foreach(dir ${arg_INCLUDES})
    list(APPEND incs -I${dir})
  endforeach()
  if(NOT arg_COMMENT)
    get_filename_component(file ${src} NAME)
    set(arg_COMMENT "glslangValidator ${file}")
  endif()
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env ${VX_SPIRV_TARGET_ENV} ${incs} ${arg_DEFINES} --vn ${array}
            --depfile ${out}.d -o ${out} ${src}
    DEPENDS ${src} ${arg_DEPENDS}
    DEPFILE ${out}.d
    COMMENT "${arg_COMMENT}"
    VERBATIM)
endfunction()
