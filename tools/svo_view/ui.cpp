// tools/svo_view/ui.cpp - the Dear ImGui shim behind ui.h (C++17; nothing
// of the viewer's logic lives here).
#include "tools/svo_view/ui.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <cstdarg>
#include <cstddef>
#include <new>

static_assert(sizeof(ImDrawVert) == sizeof(vf_vertex) && offsetof(ImDrawVert, pos) == offsetof(vf_vertex, x) &&
                  offsetof(ImDrawVert, uv) == offsetof(vf_vertex, u) && offsetof(ImDrawVert, col) == offsetof(vf_vertex, rgba),
              "ImDrawVert and vf_vertex differ");
static_assert(sizeof(ImDrawIdx) == sizeof(uint16_t), "ImDrawIdx must be 16 bits");

struct ui {
    ImGuiContext* ctx;
    vf_texture font;
};

extern "C" ui* ui_create(void) {
    ui* u = new (std::nothrow) ui();
    if (!u) return nullptr;
    u->ctx = ImGui::CreateContext();
    ImGui::SetCurrentContext(u->ctx);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // no imgui.ini next to the user's files
    io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    // the navigation keys ImGui reads from KeysDown[], indexed by GLFW key codes
    const int keys[][2] = {{ImGuiKey_Tab, GLFW_KEY_TAB},         {ImGuiKey_LeftArrow, GLFW_KEY_LEFT},
                           {ImGuiKey_RightArrow, GLFW_KEY_RIGHT}, {ImGuiKey_UpArrow, GLFW_KEY_UP},
                           {ImGuiKey_DownArrow, GLFW_KEY_DOWN},   {ImGuiKey_PageUp, GLFW_KEY_PAGE_UP},
                           {ImGuiKey_PageDown, GLFW_KEY_PAGE_DOWN}, {ImGuiKey_Home, GLFW_KEY_HOME},
                           {ImGuiKey_End, GLFW_KEY_END},          {ImGuiKey_Insert, GLFW_KEY_INSERT},
                           {ImGuiKey_Delete, GLFW_KEY_DELETE},    {ImGuiKey_Backspace, GLFW_KEY_BACKSPACE},
                           {ImGuiKey_Space, GLFW_KEY_SPACE},      {ImGuiKey_Enter, GLFW_KEY_ENTER},
                           {ImGuiKey_Escape, GLFW_KEY_ESCAPE},    {ImGuiKey_KeyPadEnter, GLFW_KEY_KP_ENTER},
                           {ImGuiKey_A, GLFW_KEY_A},              {ImGuiKey_C, GLFW_KEY_C},
                           {ImGuiKey_V, GLFW_KEY_V},              {ImGuiKey_X, GLFW_KEY_X},
                           {ImGuiKey_Y, GLFW_KEY_Y},              {ImGuiKey_Z, GLFW_KEY_Z}};
    for (const auto& k : keys) io.KeyMap[k[0]] = k[1];
    unsigned char* px = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsAlpha8(&px, &w, &h);
    io.Fonts->SetTexID(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(1)));
    u->font = vf_texture{px, static_cast<uint32_t>(w), static_cast<uint32_t>(h)};
    ImGui::StyleColorsDark();
    ImGui::GetStyle().WindowRounding = 0; // square windows: cheaper on the CPU rasterizer
    return u;
}

extern "C" void ui_destroy(ui* u) {
    if (!u) return;
    ImGui::DestroyContext(u->ctx);
    delete u;
}

extern "C" void ui_mouse(ui* u, double x, double y) {
    ImGui::SetCurrentContext(u->ctx);
    ImGui::GetIO().MousePos = ImVec2(static_cast<float>(x), static_cast<float>(y));
}

extern "C" void ui_mouse_button(ui* u, int button, bool down) {
    ImGui::SetCurrentContext(u->ctx);
    if (button >= 0 && button < 5) ImGui::GetIO().MouseDown[button] = down;
}

extern "C" void ui_wheel(ui* u, double dy) {
    ImGui::SetCurrentContext(u->ctx);
    ImGui::GetIO().MouseWheel += static_cast<float>(dy);
}

extern "C" void ui_key(ui* u, int key, bool down, bool ctrl, bool shift, bool alt) {
    ImGui::SetCurrentContext(u->ctx);
    ImGuiIO& io = ImGui::GetIO();
    if (key >= 0 && key < 512) io.KeysDown[key] = down;
    io.KeyCtrl = ctrl, io.KeyShift = shift, io.KeyAlt = alt;
}

extern "C" void ui_char(ui* u, unsigned int c) {
    ImGui::SetCurrentContext(u->ctx);
    ImGui::GetIO().AddInputCharacter(c);
}

extern "C" bool ui_wants_mouse(const ui* u) {
    ImGui::SetCurrentContext(u->ctx);
    return ImGui::GetIO().WantCaptureMouse;
}

extern "C" bool ui_wants_keyboard(const ui* u) {
    ImGui::SetCurrentContext(u->ctx);
    return ImGui::GetIO().WantCaptureKeyboard;
}

extern "C" void ui_frame_begin(ui* u, uint32_t width, uint32_t height, double dt) {
    ImGui::SetCurrentContext(u->ctx);
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
    io.DeltaTime = dt > 1e-6 ? static_cast<float>(dt) : 1e-6f;
    ImGui::NewFrame();
}

extern "C" void ui_frame_end(ui* u, vf_canvas* cv) {
    ImGui::SetCurrentContext(u->ctx);
    ImGui::Render();
    const ImDrawData* dd = ImGui::GetDrawData();
    for (int l = 0; dd && l < dd->CmdListsCount; l++) {
        const ImDrawList* dl = dd->CmdLists[l];
        for (const ImDrawCmd& c : dl->CmdBuffer) {
            if (c.UserCallback) continue; // the panels register none
            const float clip[4] = {c.ClipRect.x - dd->DisplayPos.x, c.ClipRect.y - dd->DisplayPos.y,
                                   c.ClipRect.z - dd->DisplayPos.x, c.ClipRect.w - dd->DisplayPos.y};
            vf_triangles(cv, reinterpret_cast<const vf_vertex*>(dl->VtxBuffer.Data) + c.VtxOffset,
                         dl->IdxBuffer.Data + c.IdxOffset, c.ElemCount, clip, &u->font);
        }
    }
    ImGui::GetIO().MouseWheel = 0;
}

extern "C" bool ui_window_begin(const char* title, float x, float y, float w, float h) {
    ImGui::SetNextWindowPos(ImVec2(x, y), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(w, h), ImGuiCond_FirstUseEver);
    return ImGui::Begin(title);
}
extern "C" void ui_window_end(void) { ImGui::End(); }
extern "C" bool ui_collapsing(const char* label, bool open) {
    return ImGui::CollapsingHeader(label, open ? ImGuiTreeNodeFlags_DefaultOpen : 0);
}
extern "C" bool ui_tree_begin(const char* label, bool open) {
    return ImGui::TreeNodeEx(label, open ? ImGuiTreeNodeFlags_DefaultOpen : 0);
}
extern "C" void ui_tree_end(void) { ImGui::TreePop(); }
extern "C" void ui_text(const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    ImGui::TextV(fmt, ap);
    va_end(ap);
}
extern "C" void ui_separator(void) { ImGui::Separator(); }
extern "C" void ui_same_line(void) { ImGui::SameLine(); }
extern "C" void ui_push_id(int id) { ImGui::PushID(id); }
extern "C" void ui_pop_id(void) { ImGui::PopID(); }
extern "C" bool ui_button(const char* label) { return ImGui::Button(label); }
extern "C" bool ui_checkbox(const char* label, bool* v) { return ImGui::Checkbox(label, v); }
extern "C" bool ui_selectable(const char* label, bool selected) { return ImGui::Selectable(label, selected); }
extern "C" bool ui_combo(const char* label, int* current, const char* const* items, int count) {
    return ImGui::Combo(label, current, items, count);
}
extern "C" bool ui_input_text(const char* label, char* buf, size_t size) {
    return ImGui::InputText(label, buf, size, ImGuiInputTextFlags_EnterReturnsTrue);
}
extern "C" bool ui_input_int3(const char* label, int32_t v[3]) {
    int t[3] = {v[0], v[1], v[2]};
    if (!ImGui::InputInt3(label, t, ImGuiInputTextFlags_EnterReturnsTrue)) return false;
    v[0] = t[0], v[1] = t[1], v[2] = t[2];
    return true;
}
extern "C" bool ui_drag_double(const char* label, double* v, double speed, double min, double max) {
    return ImGui::DragScalar(label, ImGuiDataType_Double, v, static_cast<float>(speed), &min, &max, "%.3f");
}
extern "C" bool ui_drag_double3(const char* label, double v[3], double speed) {
    return ImGui::DragScalarN(label, ImGuiDataType_Double, v, 3, static_cast<float>(speed), nullptr, nullptr, "%.2f");
}
extern "C" bool ui_slider_int(const char* label, int* v, int min, int max) { return ImGui::SliderInt(label, v, min, max); }
extern "C" bool ui_color3(const char* label, double rgb[3]) {
    float c[3] = {static_cast<float>(rgb[0]), static_cast<float>(rgb[1]), static_cast<float>(rgb[2])};
    if (!ImGui::ColorEdit3(label, c, ImGuiColorEditFlags_Float)) return false;
    for (int k = 0; k < 3; k++) rgb[k] = c[k];
    return true;
}
extern "C" bool ui_swatch(const char* id, uint32_t rgba, bool selected, float size) {
    ImVec4 c = ImGui::ColorConvertU32ToFloat4(rgba | 0xFF000000u);
    if (selected) {
        ImGui::PushStyleVar(ImGuiStyleVar_FrameBorderSize, 2.0f);
        ImGui::PushStyleColor(ImGuiCol_Border, ImVec4(1, 1, 1, 1));
    }
    bool r = ImGui::ColorButton(id, c, ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoAlpha, ImVec2(size, size));
    if (selected) {
        ImGui::PopStyleColor();
        ImGui::PopStyleVar();
    }
    return r;
}
extern "C" void ui_stacked_bars(const float* values, int count, int layers, int stride, const uint32_t* colours,
                                int colour_count, float top, float height) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    ImVec2 p = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    if (count <= 0 || colour_count <= 0 || !(width > 0) || !(top > 0)) {
        ImGui::Dummy(ImVec2(width, height));
        return;
    }
    float bw = width / static_cast<float>(count);
    dl->AddRectFilled(p, ImVec2(p.x + width, p.y + height), IM_COL32(0, 0, 0, 120));
    for (int f = 0; f < count; f++) {
        float y = p.y + height;
        for (int l = 0; l < layers; l++) {
            float h = values[f * stride + l] / top * height;
            if (!(h > 0)) continue;
            float y1 = y - h < p.y ? p.y : y - h;
            dl->AddRectFilled(ImVec2(p.x + f * bw, y1), ImVec2(p.x + (f + 1) * bw - (bw > 3 ? 1 : 0), y),
                              colours[l % colour_count] | 0xFF000000u);
            y = y1;
        }
    }
    ImGui::Dummy(ImVec2(width, height));
}
extern "C" void ui_legend(uint32_t rgba, const char* label) {
    ImVec2 p = ImGui::GetCursorScreenPos();
    float s = ImGui::GetTextLineHeight();
    ImGui::GetWindowDrawList()->AddRectFilled(p, ImVec2(p.x + s, p.y + s), rgba | 0xFF000000u);
    ImGui::Dummy(ImVec2(s, s));
    ImGui::SameLine();
    ImGui::TextUnformatted(label);
}
extern "C" void ui_image_rgba(const uint32_t* texels, int w, int h, float scale) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    ImVec2 p = ImGui::GetCursorScreenPos();
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w;) {
            uint32_t c = texels[y * w + x];
            int e = x + 1;
            while (e < w && texels[y * w + e] == c) e++;
            dl->AddRectFilled(ImVec2(p.x + x * scale, p.y + y * scale), ImVec2(p.x + e * scale, p.y + (y + 1) * scale),
                              c | 0xFF000000u);
            x = e;
        }
    ImGui::Dummy(ImVec2(w * scale, h * scale));
}
extern "C" void ui_progress(float fraction, const char* label) { ImGui::ProgressBar(fraction, ImVec2(-1, 0), label); }
