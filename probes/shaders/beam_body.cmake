# probes/shaders/beam_body.cmake - cmake -DIN=render/shaders/beam.comp -DOUT=beam_body.glsl -P beam_body.cmake:
# the camera beam pass as an include for probes/shaders/probe_beam.comp (its tube walk, beam_model,
# is the probes' too: one source), without its #version line and with its main renamed.
file(READ ${IN} s)
string(REPLACE "#version 450" "// (generated from render/shaders/beam.comp by probes/shaders/beam_body.cmake)" s "${s}")
string(REPLACE "void main()" "void vx_beam_camera_main()" s "${s}")
file(WRITE ${OUT} "${s}")
