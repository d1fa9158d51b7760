// A light-edit file (`voxlux render --light-edit EDITS.json`, docs/cli.md): a list of edits to a
// scene's lights, replayed through a LightRig one at a time so that each is timed on its own.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/light_rig.h"

namespace voxlux {

struct LightEdit {
    nlohmann::json value;   // the edit object as written
    std::string file;       // for messages
    std::string pointer;    // JSON pointer of the edit ("/edits/3")
};

// Reads the file's edits and checks that each is well formed. Throws InputError naming the file
// and the edit.
std::vector<LightEdit> loadLightEdits(const std::string& path);
// The same from the file's text; `path` names it in messages.
std::vector<LightEdit> parseLightEdits(const std::string& text, const std::string& path);

// Applies one edit to `rig` (not yet to its renderer) and returns a short description of it, e.g.
// "update key". Throws InputError naming the file and the edit when its light does not exist or
// the edited light is invalid.
std::string applyLightEdit(LightRig& rig, const LightEdit& edit);

}  // namespace voxlux
