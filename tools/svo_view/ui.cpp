// tools/svo_view/ui.cpp - the Dear ImGui shim behind ui.h (C++17; nothing
// of the viewer's logic lives here).
#include "tools/svo_view/ui.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h> // a window's visible rows (ImGuiWindow::InnerClipRect), for ui_find
#include <backends/imgui_impl_vulkan.h>

#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <new>

static_assert(sizeof(ImDrawVert) == sizeof(vf_vertex) && offsetof(ImDrawVert, pos) == offsetof(vf_vertex, x) &&
                  offsetof(ImDrawVert, uv) == offsetof(vf_vertex, u) && offsetof(ImDrawVert, col) == offsetof(vf_vertex, rgba),
              "ImDrawVert and vf_vertex differ");
static_assert(sizeof(ImDrawIdx) == sizeof(uint16_t), "ImDrawIdx must be 16 bits");

// the GPU panels' objects (ui_gpu_init); Vulkan's own types here, void* in ui.h
enum { UI_GPU_MAX_FRAMES = 8 };
struct ui_gpu {
    bool ready;
    VkDevice device;
    VkRenderPass pass;
    VkDescriptorPool pool;
    uint32_t frames;
    VkFramebuffer fb[UI_GPU_MAX_FRAMES]; // the last framebuffer made for each frame slot
};

struct ui {
    ImGuiContext* ctx;
    vf_texture font;
    ui_gpu gpu;
    // ui_find: the widget whose rectangle the next frame notes (scripted clicks)
    char find[128];
    float found[4];
    bool found_ok;
};

extern "C" ui* ui_create(void) {
    ui* u = new (std::nothrow) ui();
    if (!u) return nullptr;
    u->ctx = ImGui::CreateContext();
    ImGui::SetCurrentContext(u->ctx);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // no imgui.ini next to the user's files
    io.UserData = u;          // the widgets find their ui (ui_find) through their context
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
    ui_gpu_shutdown(u);
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
    if (cv) ui_draw_cpu(u, cv);
    ImGui::GetIO().MouseWheel = 0;
}

extern "C" void ui_draw_cpu(ui* u, vf_canvas* cv) {
    ImGui::SetCurrentContext(u->ctx);
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
}

// ---- the panels drawn on the GPU -------------------------------------------------------

static void gpu_fail(char* why, size_t n, const char* what, VkResult r) {
    if (why && n) std::snprintf(why, n, "panels on the GPU: %s failed (VkResult %d)", what, static_cast<int>(r));
}

extern "C" bool ui_gpu_init(ui* u, const ui_gpu_desc* d, char* why, size_t why_size) {
    if (!u || !d || !d->device || !d->queue || u->gpu.ready) {
        if (why && why_size) std::snprintf(why, why_size, "panels on the GPU: no device, or made already");
        return false;
    }
    ImGui::SetCurrentContext(u->ctx);
    ui_gpu& g = u->gpu;
    g.device = static_cast<VkDevice>(d->device);
    g.frames = d->frames ? d->frames : 3;
    if (g.frames < 2 || g.frames > UI_GPU_MAX_FRAMES) {
        if (why && why_size) std::snprintf(why, why_size, "panels on the GPU: %u frames in flight (2..%d)", g.frames,
                                           static_cast<int>(UI_GPU_MAX_FRAMES));
        return false;
    }
    VkFormat format = d->format ? static_cast<VkFormat>(d->format) : VK_FORMAT_B8G8R8A8_UNORM;
    VkImageLayout final_layout = d->final_layout ? static_cast<VkImageLayout>(d->final_layout) : VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    // the scene is in the image already: load it, draw over it, store; the caller's barrier orders the tracer's
    // writes before the load (ui.h), the external dependency below the blend after it
    VkAttachmentDescription att = {};
    att.format = format;
    att.samples = VK_SAMPLE_COUNT_1_BIT;
    att.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    att.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    att.finalLayout = final_layout;
    VkAttachmentReference ref = {0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &ref;
    VkSubpassDependency dep = {};
    dep.srcSubpass = VK_SUBPASS_EXTERNAL;
    dep.dstSubpass = 0;
    dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dep.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo rp = {};
    rp.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
    rp.attachmentCount = 1;
    rp.pAttachments = &att;
    rp.subpassCount = 1;
    rp.pSubpasses = &sub;
    rp.dependencyCount = 1;
    rp.pDependencies = &dep;
    VkResult r = vkCreateRenderPass(g.device, &rp, nullptr, &g.pass);
    if (r != VK_SUCCESS) return gpu_fail(why, why_size, "vkCreateRenderPass", r), ui_gpu_shutdown(u), false;
    VkDescriptorPoolSize ps = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1}; // the font's
    VkDescriptorPoolCreateInfo pi = {};
    pi.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pi.maxSets = 1;
    pi.poolSizeCount = 1;
    pi.pPoolSizes = &ps;
    if ((r = vkCreateDescriptorPool(g.device, &pi, nullptr, &g.pool)) != VK_SUCCESS)
        return gpu_fail(why, why_size, "vkCreateDescriptorPool", r), ui_gpu_shutdown(u), false;
    ImGui_ImplVulkan_InitInfo ii = {};
    ii.Instance = static_cast<VkInstance>(d->instance);
    ii.PhysicalDevice = static_cast<VkPhysicalDevice>(d->phys);
    ii.Device = g.device;
    ii.QueueFamily = d->queue_family;
    ii.Queue = static_cast<VkQueue>(d->queue);
    ii.DescriptorPool = g.pool;
    // the backend's vertex and index buffers rotate per recorded frame: one per frame in flight, plus one
    ii.MinImageCount = g.frames;
    ii.ImageCount = g.frames + 1;
    ii.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    if (!ImGui_ImplVulkan_Init(&ii, g.pass)) {
        if (why && why_size) std::snprintf(why, why_size, "panels on the GPU: ImGui_ImplVulkan_Init failed");
        ui_gpu_shutdown(u);
        return false;
    }
    g.ready = true; // from here ui_gpu_shutdown also shuts the backend down
    // the font atlas, uploaded once in a submission of its own
    VkCommandPool cp = VK_NULL_HANDLE;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkCommandPoolCreateInfo ci = {};
    ci.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    ci.queueFamilyIndex = d->queue_family;
    const char* what = "vkCreateCommandPool";
    r = vkCreateCommandPool(g.device, &ci, nullptr, &cp);
    if (r == VK_SUCCESS) {
        VkCommandBufferAllocateInfo ai = {};
        ai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
        ai.commandPool = cp;
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 1;
        what = "vkAllocateCommandBuffers";
        r = vkAllocateCommandBuffers(g.device, &ai, &cmd);
    }
    if (r == VK_SUCCESS) {
        VkCommandBufferBeginInfo bi = {};
        bi.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        what = "vkBeginCommandBuffer";
        r = vkBeginCommandBuffer(cmd, &bi);
    }
    if (r == VK_SUCCESS) {
        bool fonts = ImGui_ImplVulkan_CreateFontsTexture(cmd);
        what = "vkEndCommandBuffer";
        r = vkEndCommandBuffer(cmd);
        if (r == VK_SUCCESS && !fonts) what = "ImGui_ImplVulkan_CreateFontsTexture", r = VK_ERROR_UNKNOWN;
    }
    if (r == VK_SUCCESS) {
        VkSubmitInfo si = {};
        si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        what = "vkQueueSubmit (the font upload)";
        r = vkQueueSubmit(static_cast<VkQueue>(d->queue), 1, &si, VK_NULL_HANDLE);
        if (r == VK_SUCCESS) what = "vkQueueWaitIdle", r = vkQueueWaitIdle(static_cast<VkQueue>(d->queue));
    }
    if (cp) vkDestroyCommandPool(g.device, cp, nullptr);
    ImGui_ImplVulkan_DestroyFontUploadObjects();
    if (r != VK_SUCCESS) return gpu_fail(why, why_size, what, r), ui_gpu_shutdown(u), false;
    return true;
}

extern "C" bool ui_gpu_ready(const ui* u) { return u && u->gpu.ready; }

extern "C" bool ui_gpu_record(ui* u, void* cmd_handle, uint32_t slot, uint64_t view, uint32_t w, uint32_t h, char* why,
                              size_t why_size) {
    if (!u || !u->gpu.ready || !cmd_handle || !view || !w || !h || slot >= u->gpu.frames) {
        if (why && why_size) std::snprintf(why, why_size, "panels on the GPU: not made, or no image or slot");
        return false;
    }
    ImGui::SetCurrentContext(u->ctx);
    ui_gpu& g = u->gpu;
    // the slot's frame ended (ui.h): its framebuffer can go; the view may be another image's now
    if (g.fb[slot]) vkDestroyFramebuffer(g.device, g.fb[slot], nullptr), g.fb[slot] = VK_NULL_HANDLE;
    VkImageView iv = reinterpret_cast<VkImageView>(static_cast<uintptr_t>(view));
    VkFramebufferCreateInfo fi = {};
    fi.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
    fi.renderPass = g.pass;
    fi.attachmentCount = 1;
    fi.pAttachments = &iv;
    fi.width = w;
    fi.height = h;
    fi.layers = 1;
    VkResult r = vkCreateFramebuffer(g.device, &fi, nullptr, &g.fb[slot]);
    if (r != VK_SUCCESS) return gpu_fail(why, why_size, "vkCreateFramebuffer", r), false;
    VkCommandBuffer cmd = static_cast<VkCommandBuffer>(cmd_handle);
    VkRenderPassBeginInfo bi = {};
    bi.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
    bi.renderPass = g.pass;
    bi.framebuffer = g.fb[slot];
    bi.renderArea.extent = {w, h};
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    ImDrawData* dd = ImGui::GetDrawData();
    // draw lists made for another size are not drawn (a resize: the next frame's panels are)
    if (dd && dd->Valid && dd->DisplaySize.x == static_cast<float>(w) && dd->DisplaySize.y == static_cast<float>(h))
        ImGui_ImplVulkan_RenderDrawData(dd, cmd);
    vkCmdEndRenderPass(cmd);
    return true;
}

extern "C" void ui_gpu_shutdown(ui* u) {
    if (!u || !u->gpu.device) return;
    ImGui::SetCurrentContext(u->ctx);
    ui_gpu& g = u->gpu;
    vkDeviceWaitIdle(g.device); // frames in flight may still draw with these objects
    if (g.ready) ImGui_ImplVulkan_Shutdown();
    for (VkFramebuffer& f : g.fb)
        if (f) vkDestroyFramebuffer(g.device, f, nullptr), f = VK_NULL_HANDLE;
    if (g.pool) vkDestroyDescriptorPool(g.device, g.pool, nullptr);
    if (g.pass) vkDestroyRenderPass(g.device, g.pass, nullptr);
    g = ui_gpu{};
}

extern "C" bool ui_window_begin(const char* title, float x, float y, float w, float h) {
    ImGui::SetNextWindowPos(ImVec2(x, y), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(w, h), ImGuiCond_FirstUseEver);
    return ImGui::Begin(title);
}
// After a widget: its rectangle noted when it is the one ui_find asked for (the first drawn with that label).
// framed: a widget whose label is beside its frame (sliders, drags, combos, text fields), where a click on the label
// does nothing: the rectangle is the frame's (the item's width), not the label's.
static bool note(const char* label, bool result, bool framed = false) {
    ui* u = static_cast<ui*>(ImGui::GetIO().UserData);
    if (u && u->find[0] && !u->found_ok && !std::strcmp(label, u->find)) {
        ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        // not wholly inside its window's visible rows (scrolled out, or cut by the window's edge, where a click
        // would land on what lies beyond): scrolled into view, found next frame
        const ImRect& clip = ImGui::GetCurrentWindowRead()->InnerClipRect;
        if (a.y < clip.Min.y || b.y > clip.Max.y) {
            ImGui::SetScrollHereY(0.5f);
            return result;
        }
        if (framed && a.x + ImGui::CalcItemWidth() < b.x) b.x = a.x + ImGui::CalcItemWidth();
        u->found[0] = a.x, u->found[1] = a.y, u->found[2] = b.x, u->found[3] = b.y;
        u->found_ok = true;
    }
    return result;
}
extern "C" void ui_window_end(void) { ImGui::End(); }
extern "C" bool ui_collapsing(const char* label, bool open) {
    return note(label, ImGui::CollapsingHeader(label, open ? ImGuiTreeNodeFlags_DefaultOpen : 0));
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
extern "C" void ui_find(ui* u, const char* label) {
    std::snprintf(u->find, sizeof u->find, "%s", label);
    u->found_ok = false;
}
extern "C" bool ui_found(const ui* u, float rect[4]) {
    if (!u->found_ok) return false;
    for (int k = 0; k < 4; k++) rect[k] = u->found[k];
    return true;
}
extern "C" bool ui_button(const char* label) { return note(label, ImGui::Button(label)); }
extern "C" bool ui_checkbox(const char* label, bool* v) { return note(label, ImGui::Checkbox(label, v)); }
extern "C" bool ui_selectable(const char* label, bool selected) { return note(label, ImGui::Selectable(label, selected)); }
// ImGui::Combo's own loop, so that the open list's items can be found by ui_find too
extern "C" bool ui_combo(const char* label, int* current, const char* const* items, int count) {
    bool open = ImGui::BeginCombo(label, *current >= 0 && *current < count ? items[*current] : "");
    if (!open) return note(label, false, true); // (open, the last item is the list's window, not the combo)
    bool changed = false;
    for (int i = 0; i < count; i++) {
        bool sel = i == *current;
        if (note(items[i], ImGui::Selectable(items[i], sel)) && !sel) *current = i, changed = true;
        if (sel) ImGui::SetItemDefaultFocus();
    }
    ImGui::EndCombo();
    return changed;
}
extern "C" bool ui_input_text(const char* label, char* buf, size_t size) {
    return note(label, ImGui::InputText(label, buf, size, ImGuiInputTextFlags_EnterReturnsTrue), true);
}
extern "C" bool ui_input_int3(const char* label, int32_t v[3]) {
    int t[3] = {v[0], v[1], v[2]};
    if (!ImGui::InputInt3(label, t, ImGuiInputTextFlags_EnterReturnsTrue)) return false;
    v[0] = t[0], v[1] = t[1], v[2] = t[2];
    return true;
}
extern "C" bool ui_drag_double(const char* label, double* v, double speed, double min, double max) {
    return note(label, ImGui::DragScalar(label, ImGuiDataType_Double, v, static_cast<float>(speed), &min, &max, "%.3f"),
                true);
}
extern "C" bool ui_drag_double3(const char* label, double v[3], double speed) {
    return ImGui::DragScalarN(label, ImGuiDataType_Double, v, 3, static_cast<float>(speed), nullptr, nullptr, "%.2f");
}
extern "C" bool ui_slider_int(const char* label, int* v, int min, int max) {
    return note(label, ImGui::SliderInt(label, v, min, max), true);
}
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
