# The lighting methods' settings, declared once: each method's folder names its settings struct
# (the effects keys it owns, read, validated and written by its own readSettings/writeSettings)
# and the effects.shadows values it provides. Generated from that:
#   method_settings.h    ShadowMethod and its names, and MethodSettings, whose bases are the
#                        methods' settings (scene.h's Effects derives from it);
#   method_settings.cpp  the effects keys the methods own, and reading and writing them all.
# Uses voxlux_write_generated (cmake/kernel_contract.cmake).

# A lighting method's settings: TYPE, declared in src/lighting/<name>/<name>_settings.h with
# readSettings and writeSettings overloads for it, which <name>_settings.cpp beside it defines (the
# layers place these names: tests/test_layers.cpp); SHADOWS lists the effects.shadows values it
# provides, three words each: the JSON name, the ShadowMethod enumerator and what --explain says
# of it (plain text: no quote, backslash or semicolon).
function(voxlux_method_settings name)
  cmake_parse_arguments(ARG "" "TYPE" "SHADOWS" ${ARGN})
  if(NOT ARG_TYPE)
    message(FATAL_ERROR "lighting method ${name}: voxlux_method_settings needs TYPE")
  endif()
  voxlux_check_shadow_values("lighting method ${name}" ${ARG_SHADOWS})
  set_property(GLOBAL APPEND PROPERTY VOXLUX_SETTINGS_METHODS ${name})
  set_property(GLOBAL PROPERTY VOXLUX_SETTINGS_${name}_TYPE "${ARG_TYPE}")
  set_property(GLOBAL PROPERTY VOXLUX_SETTINGS_${name}_SHADOWS "${ARG_SHADOWS}")
endfunction()

# Fails unless `ARGN` is effects.shadows values, three words each, whose description can be pasted
# into a C++ string literal.
function(voxlux_check_shadow_values who)
  list(LENGTH ARGN words)
  math(EXPR rest "${words} % 3")
  if(NOT rest EQUAL 0)
    message(FATAL_ERROR "${who}: SHADOWS takes three words a value (name, enumerator, description)")
  endif()
  foreach(word ${ARGN})
    if(word MATCHES "\"" OR word MATCHES "\\\\")
      message(FATAL_ERROR "${who}: SHADOWS '${word}' holds a quote or a backslash")
    endif()
  endforeach()
endfunction()

# Writes the files above into `dir`; CORE_SHADOWS are the march's own effects.shadows values
# (three words each, as SHADOWS), which come first. Sets VOXLUX_SETTINGS_SOURCES: the methods'
# settings sources and the generated method_settings.cpp, for the scene layer.
function(voxlux_generate_method_settings dir)
  cmake_parse_arguments(ARG "" "" "CORE_SHADOWS" ${ARGN})
  get_property(methods GLOBAL PROPERTY VOXLUX_SETTINGS_METHODS)
  voxlux_check_shadow_values("voxlux_generate_method_settings" ${ARG_CORE_SHADOWS})
  set(shadows ${ARG_CORE_SHADOWS})
  set(sources "")
  set(includes "")
  set(bases "")
  set(keys "")
  set(reads "")
  set(writes "")
  foreach(m ${methods})
    set(header lighting/${m}/${m}_settings.h)
    list(APPEND sources ${CMAKE_SOURCE_DIR}/src/lighting/${m}/${m}_settings.cpp)
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
  if(words EQUAL 0)
    message(FATAL_ERROR "voxlux_generate_method_settings: no effects.shadows values (CORE_SHADOWS)")
  endif()
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
  set(VOXLUX_SETTINGS_SOURCES ${sources} ${dir}/method_settings.cpp PARENT_SCOPE)
endfunction()
