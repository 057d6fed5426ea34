/* tools/svo_view/panels_none.c - svo_view built without Dear ImGui: no
 * panels (the text overlay stays); see panels.h. */
#include "tools/svo_view/panels.h"

bool sv_panels_built(void) { return false; }
bool sv_panels_create(app* a) {
    (void)a;
    return false;
}
void sv_panels_destroy(app* a) { (void)a; }
void sv_panels_draw(app* a, vf_canvas* cv) { (void)a, (void)cv; }
bool sv_panels_gpu_init(app* a, char* why, size_t why_size) {
    (void)a, (void)why, (void)why_size;
    return false;
}
bool sv_panels_gpu_record(app* a, void* cmd, uint32_t slot, uint64_t view, uint32_t w, uint32_t h, char* why,
                          size_t why_size) {
    (void)a, (void)cmd, (void)slot, (void)view, (void)w, (void)h, (void)why, (void)why_size;
    return false;
}
void sv_panels_mouse(app* a, double x, double y) { (void)a, (void)x, (void)y; }
void sv_panels_button(app* a, int button, bool down) { (void)a, (void)button, (void)down; }
void sv_panels_wheel(app* a, double dy) { (void)a, (void)dy; }
void sv_panels_key(app* a, int key, bool down, int mods) { (void)a, (void)key, (void)down, (void)mods; }
void sv_panels_char(app* a, unsigned int c) { (void)a, (void)c; }
void sv_panels_find(app* a, const char* label) { (void)a, (void)label; }
bool sv_panels_found(const app* a, float rect[4]) { return (void)a, (void)rect, false; }
bool sv_panels_wants_mouse(const app* a) {
    (void)a;
    return false;
}
bool sv_panels_wants_keyboard(const app* a) {
    (void)a;
    return false;
}
