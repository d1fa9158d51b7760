// `voxlux view --script actions.json`: UI actions replayed in order, for tests and for scripted
// look-dev captures. The file is {"actions": [ ... ]}, each action an object with one kind key:
//   {"set": "material.density_scale=20"}             any scene key, as --set takes it
//   {"light": "sun", "set": {"intensity": 4}}        a light's keys, by name or index (and selects it)
//   {"enable": "sun", "on": false}   {"solo": "sun"}   {"remove_light": 0}   {"add_light": {...}}
//   {"drag_light": "key", "by": [dx, dy]}            a gizmo drag, in viewport pixels (an environment
//                                                    light: dx turns its map, as Shift + right drag does)
//   {"drag_volume": "smoke", "by": [dx, dy], "mode": "move" | "rotate" | "scale"}
//                                                    a volume's gizmo drag (mode: the gizmo's, unset)
//   {"orbit": [yaw, pitch]}  {"pan": [x, y]}  {"dolly": 0.8}  {"frame": true}   (degrees, view heights)
//   {"frame_number": 12}  {"aov": "direct"}
//   {"wait": "converged"}  {"wait": 0.5} (seconds of running UI)  {"wait_file": "go.flag"}
//   {"screenshot": "view.png"}   the viewport's image as `voxlux render --preview` writes it
//   {"window_screenshot": "ui.png"}   the whole window, panels and all
//   {"layout": "widgets.json"}   where named widgets are on screen, for tests that send X events
//   {"save": "scene.json"}  {"render": true}  {"stats": "stats.json"}  {"quit": true}
// Every action is checked when the file is read: a bad one is an error naming the file and its
// JSON pointer before the window opens. An edit the scene refuses is shown as in the UI (and
// printed as a warning), and the script goes on.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace voxlux {

struct ViewAction {
    std::string kind;         // the action's kind key
    nlohmann::json value;     // the whole action object
    std::string where;        // "<file>: /actions/<k>", for messages
};

std::vector<ViewAction> loadViewScript(const std::string& path);
std::vector<ViewAction> parseViewScript(const std::string& text, const std::string& path);

}  // namespace voxlux
