# The lighting methods' settings, declared once: each method's folder names the header of its
# settings struct (the effects keys it owns, read, validated and written by its own
# readSettings/writeSettings) and the effects.shadows values it provides. Generated from that:
#   method_settings.h    ShadowMethod and its names, and MethodSettings, whose bases are the
#                        methods' settings (scene.h's Effects derives from it);
#   method_settings.cpp  the effects keys the methods own, and reading and writing them all.
# Uses voxlux_write_generated (cmake/kernel_contract.cmake).

# A lighting method's settings: HEADER (from src/) declares TYPE, and readSettings and
# writeSettings overloads for it; SOURCE (from the source root) defines them; SHADOWS lists the
# effects.shadows values it provides, three words each: the JSON name, the ShadowMethod
# enumerator and what --explain says of it.
function(voxlux_method_settings name)
  cmake_parse_arguments(ARG "" "HEADER;TYPE;SOURCE" "SHADOWS" ${ARGN})
  foreach(required HEADER TYPE SOURCE)
    if(NOT ARG_${required})
      message(FATAL_ERROR "lighting method ${name}: voxlux_method_settings needs ${required}")
    endif()
  endforeach()
  list(LENGTH ARG_SHADOWS words)
  math(EXPR rest "${words} % 3")
  if(NOT rest EQUAL 0)
    message(FATAL_ERROR "lighting method ${name}: SHADOWS takes three words a value (name, enumerator, description)")
  endif()
  set_property(GLOBAL APPEND PROPERTY VOXLUX_SETTINGS_METHODS ${name})
  foreach(field HEADER TYPE SHADOWS)
    set_property(GLOBAL PROPERTY VOXLUX_SETTINGS_${name}_${field} "${ARG_${field}}")
  endforeach()
  set_property(GLOBAL APPEND PROPERTY VOXLUX_SETTINGS_SOURCES ${CMAKE_SOURCE_DIR}/${ARG_SOURCE})
endfunction()

# Writes the files above into `dir`; CORE_SHADOWS are the march's own effects.shadows values
# (three words each, as SHADOWS), which come first. Sets VOXLUX_SETTINGS_SOURCES: the methods'
# settings sources and the generated method_settings.cpp, for the scene layer.
function(voxlux_generate_method_settings dir)
  cmake_parse_arguments(ARG "" "" "CORE_SHADOWS" ${ARGN})
  get_property(methods GLOBAL PROPERTY VOXLUX_SETTINGS_METHODS)
  set(shadows ${ARG_CORE_SHADOWS})
  set(includes "")
  set(bases "")
  set(keys "")
  set(reads "")
  set(writes "")
  foreach(m ${methods})
    get_property(header GLOBAL PROPERTY VOXLUX_SETTINGS_${m}_HEADER)
    get_property(type GLOBAL PROPERTY VOXLUX_SETTINGS_${m}_TYPE)
    get_property(method_shadows GLOBAL PROPERTY VOXLUX_SETTINGS_${m}_SHADOWS)
    list(APPEND shadows ${method_shadows})
    string(APPEND includes "#include \"${header}\"\n")
    list(APPEND bases "${type}")
    string(APPEND keys "    for (std::string& key : ${type}::keys()) keys.push_back(std::move(key));\n")
    string(APPEND reads "    readSettings(effects, static_cast<${type}&>(settings));\n")
    string(APPEND writes "    writeSettings(static_cast<const ${type}&>(settings), effects);\n")
  endforeach()
  set(enumerators "")
  set(names "")
  set(descriptions "")
  list(LENGTH shadows words)
  math(EXPR last "${words} - 1")
  foreach(i RANGE 0 ${last} 3)
    math(EXPR j "${i} + 1")
    math(EXPR k "${i} + 2")
    list(GET shadows ${i} json_name)
    list(GET shadows ${j} enumerator)
    list(GET shadows ${k} description)
    list(APPEND enumerators ${enumerator})
    list(APPEND names "\"${json_name}\"")
    string(APPEND descriptions "        \"${description}\",\n")
  endforeach()
  list(JOIN enumerators ", " enumerators)
  list(JOIN names ", " names)
  set(base_list "")
  if(bases)
    list(JOIN bases ", " base_list)
    set(base_list " : ${base_list}")
  endif()

  voxlux_write_generated(${dir}/method_settings.h "// The lighting methods' settings and effects.shadows values (cmake/method_settings.cmake).
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

${includes}
namespace voxlux {

class JsonObject;

// effects.shadows: the march's own values, then those the lighting methods provide.
enum class ShadowMethod { ${enumerators} };
// effects.shadows' names, in ShadowMethod's order.
inline const std::vector<std::string> kShadowMethodNames{${names}};
inline const std::string& shadowMethodName(ShadowMethod m) { return kShadowMethodNames[size_t(m)]; }
// What it does, as --explain says.
const char* shadowMethodDescription(ShadowMethod m);

// Every lighting method's settings, each a base: the effects keys they own.
struct MethodSettings${base_list} {};

// The effects keys of all methods' settings.
std::vector<std::string> methodSettingKeys();
// Reads (validated) and writes every method's settings from and into the scene's effects object.
void readMethodSettings(const JsonObject& effects, MethodSettings& settings);
void writeMethodSettings(const MethodSettings& settings, nlohmann::json& effects);

}  // namespace voxlux
")
  voxlux_write_generated(${dir}/method_settings.cpp "#include \"method_settings.h\"

#include <nlohmann/json.hpp>

#include \"core/json_reader.h\"

namespace voxlux {

const char* shadowMethodDescription(ShadowMethod m) {
    static const char* const descriptions[] = {
${descriptions}    };
    return descriptions[size_t(m)];
}

std::vector<std::string> methodSettingKeys() {
    std::vector<std::string> keys;
${keys}    return keys;
}

void readMethodSettings([[maybe_unused]] const JsonObject& effects, [[maybe_unused]] MethodSettings& settings) {
${reads}}

void writeMethodSettings([[maybe_unused]] const MethodSettings& settings, [[maybe_unused]] nlohmann::json& effects) {
${writes}}

}  // namespace voxlux
")
  get_property(sources GLOBAL PROPERTY VOXLUX_SETTINGS_SOURCES)
  set(VOXLUX_SETTINGS_SOURCES ${sources} ${dir}/method_settings.cpp PARENT_SCOPE)
endfunction()
