#include "viewer/key_trickle.h"

#include <set>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>

namespace voxlux {
namespace {

KeyTrickle* installed = nullptr;   // GLFW's callbacks are plain functions; the viewer has one window

}  // namespace

KeyTrickle::KeyTrickle(GLFWwindow* window) : window_(window) {
    installed = this;
    glfwSetKeyCallback(window, onKey);
    glfwSetCharCallback(window, onChar);
}

KeyTrickle::~KeyTrickle() {
    glfwSetKeyCallback(window_, ImGui_ImplGlfw_KeyCallback);
    glfwSetCharCallback(window_, ImGui_ImplGlfw_CharCallback);
    installed = nullptr;
}

void KeyTrickle::onKey(GLFWwindow*, int key, int scancode, int action, int mods) {
    if (installed) installed->queue_.push_back({false, key, scancode, action, mods});
}

void KeyTrickle::onChar(GLFWwindow*, unsigned int code_point) {
    if (installed) installed->queue_.push_back({true, int(code_point), 0, 0, 0});
}

void KeyTrickle::deliver() {
    std::set<int> changed;
    bool typed = false, keyed = false;
    while (!queue_.empty()) {
        const Event e = queue_.front();
        // The frame ends before a second change of a key, and where keys and characters meet.
        if (e.character ? keyed : typed || (e.action != GLFW_REPEAT && changed.count(e.code))) break;
        queue_.pop_front();
        if (e.character) {
            typed = true;
            ImGui_ImplGlfw_CharCallback(window_, unsigned(e.code));
            continue;
        }
        keyed = true;
        if (e.action != GLFW_REPEAT) changed.insert(e.code);
        ImGui_ImplGlfw_KeyCallback(window_, e.code, e.scancode, e.action, e.mods);
        // A press is a frame's last event: the shortcut it makes (Ctrl held, Z pressed) is seen
        // before a release that follows it.
        if (e.action == GLFW_PRESS) break;
    }
}

}  // namespace voxlux
