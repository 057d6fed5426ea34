# probes/shaders/beam_body.cmake - cmake -DIN=render/shaders/beam.comp -DOUT=beam_body.glsl -P beam_body.cmake:
# the camera beam pass as an include for probes/shaders/probe_beam.comp (its tube walk, beam_model,
# is the probes' too: one source), without its #version line and with its main renamed; its model walk
# renamed beam_model_plain (the plain layout's node words): probe_beam.comp's beam_model takes it or the
# compact layout's walk by the scene's layout.
file(READ ${IN} s)
string(REPLACE "#version 450" "// (generated from render/shaders/beam.comp by probes/shaders/beam_body.cmake)" s "${s}")
string(REPLACE "void main()" "void vx_beam_camera_main()" s "${s}")
set(walk "bool beam_model(uint mi, vec3 o, vec3 d, float scale, float t0, inout Hit h) {")
string(FIND "${s}" "${walk}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "beam_body.cmake: ${IN} no longer defines \"${walk}\"")
endif()
string(REPLACE "${walk}" "bool beam_model_plain(uint mi, vec3 o, vec3 d, float scale, float t0, inout Hit h) {" s "${s}")
file(WRITE ${OUT} "${s}")
