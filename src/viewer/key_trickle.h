// Keys and typed characters as Dear ImGui 1.86 must see them: in order, one change of a key a
// frame, a press last in its frame, never keys and characters in one frame. Its GLFW backend sets
// io.KeysDown from GLFW's key callback and queues characters apart, so a key pressed and released
// between two frames (a quick tap while the UI draws slowly beside a render) was never seen down,
// and a BackSpace typed after "abc" and before "d" landed after both (a typed path came out
// wrong); X may also release Ctrl before the Z of Ctrl+Z. This queues both kinds of event and
// hands them to the backend in their order, a frame at a time, as ImGui 1.87's input queue
// trickles them. Costs nothing: a frame is drawn for each step of the queue (two a character).
#pragma once
#include <deque>

struct GLFWwindow;

namespace voxlux {

class KeyTrickle {
public:
    // Takes GLFW's key and character callbacks of `window` in front of Dear ImGui's backend
    // (installed before), and gives them back when it goes.
    explicit KeyTrickle(GLFWwindow* window);
    ~KeyTrickle();
    KeyTrickle(const KeyTrickle&) = delete;
    KeyTrickle& operator=(const KeyTrickle&) = delete;

    // Before ImGui's NewFrame: hands over the queued events that fit in one frame.
    void deliver();
    // Events wait for a later frame: the UI must draw another.
    bool pending() const { return !queue_.empty(); }

private:
    struct Event {
        bool character;
        int code, scancode, action, mods;   // a key's, or a character's code point
    };
    static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void onChar(GLFWwindow* window, unsigned int code_point);
    GLFWwindow* window_;
    std::deque<Event> queue_;
};

}  // namespace voxlux
