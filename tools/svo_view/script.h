/* tools/svo_view/script.h - svo_view's script (script.c; --script FILE, the
 * commands in docs/VIEWER.md). */
#ifndef VX_SVO_VIEW_SCRIPT_H
#define VX_SVO_VIEW_SCRIPT_H

#include "tools/svo_view/app.h"

/* Reads a->o.script into a->lines (nonzero, with a message, on failure). */
int sv_script_load(app* a);
/* Runs one script line; false (with a message) on a malformed command. */
bool sv_script_command(app* a, char* line, uint32_t lineno);

#endif
