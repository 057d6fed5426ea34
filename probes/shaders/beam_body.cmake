# probes/shaders/beam_body.cmake - cmake -DIN=render/shaders/beam.comp -DOUT=beam_body.glsl -P beam_body.cmake:
# the camera beam pass as an include for probes/shaders/probe_beam.comp (its tube walk, beam_model,
# is the probes' too: one source), without its #version line and with its main renamed; its model walk
# (render/shaders/beam_walk.glsl instantiated for the plain layout's node words) renamed beam_model_plain:
# probe_beam.comp's beam_model takes it or the compact layout's instance of the same walk by the scene's layout.
file(READ ${IN} s)
string(REPLACE "#version 450" "// (generated from render/shaders/beam.comp by probes/shaders/beam_body.cmake)" s "${s}")
string(REPLACE "void main()" "void vx_beam_camera_main()" s "${s}")
set(walk "#define BW_NAME beam_model\n")
string(FIND "${s}" "${walk}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "beam_body.cmake: ${IN} no longer defines \"${walk}\"")
endif()
string(REPLACE "${walk}" "#define BW_NAME beam_model_plain\n" s "${s}")
file(WRITE ${OUT} "${s}")
