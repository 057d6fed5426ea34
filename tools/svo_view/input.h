/* tools/svo_view/input.h - the window's input (input.c): keys (docs/VIEWER.md
 * lists them), mouse buttons and motion (orbit, grab, picks), scroll, text
 * for the panels, dropped files (added to the scene), and the flight keys. */
#ifndef VX_SVO_VIEW_INPUT_H
#define VX_SVO_VIEW_INPUT_H

#include <GLFW/glfw3.h>

#include "tools/svo_view/app.h"

/* Sets w's callbacks; w's user pointer must be a (glfwSetWindowUserPointer). */
void sv_input_attach(app* a, GLFWwindow* w);
/* Moves the eye for the held W/A/S/D/Q/E keys over dt seconds. */
void sv_fly(app* a, double dt);

#endif
