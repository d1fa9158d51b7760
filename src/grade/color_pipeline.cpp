#include "grade/color_pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "core/error.h"

namespace voxlux {

const std::map<std::string, std::string>& embeddedColorConfigs();  // generated at build time

namespace {

constexpr const char* kBuiltinSource = "voxlux built-in config (ocio/voxlux.ocio)";

std::string oneLine(const std::exception& e) {
    std::string why = e.what();
    std::replace(why.begin(), why.end(), '\n', ' ');
    return why;
}

// "A, B, C" for an error message; long lists end in "and N more" so the line stays readable.
std::string listNames(const std::vector<std::string>& names) {
    constexpr size_t kShown = 30;
    std::string out;
    for (size_t i = 0; i < names.size() && i < kShown; ++i) out += (i ? ", " : "") + names[i];
    if (names.size() > kShown) out += " and " + std::to_string(names.size() - kShown) + " more";
    return out.empty() ? "none" : out;
}

std::vector<std::string> colorSpaceNames(const OCIO::Config& config) {
    std::vector<std::string> names;
    const int n = config.getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL);
    for (int i = 0; i < n; ++i)
        names.push_back(config.getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL, i));
    return names;
}


// Every look a look string ("a, +b, -c") names must exist.
void requireLooks(const OCIO::Config& config, const std::string& looks, const std::string& key, const std::string& source) {
    std::vector<std::string> known;
    for (int i = 0; i < config.getNumLooks(); ++i) known.push_back(config.getLookNameByIndex(i));
    std::stringstream list(looks);
    std::string item;
    int count = 0;
    while (std::getline(list, item, ',')) {
        const auto first = item.find_first_not_of(" \t+-");
        const auto last = item.find_last_not_of(" \t");
        if (first == std::string::npos) continue;
        const std::string name = item.substr(first, last - first + 1);
        ++count;
        if (!config.getLook(name.c_str()))
            throw InputError(key + ": no look '" + name + "' in " + source + " (it has: " + listNames(known) + ")");
    }
    if (count == 0) throw InputError(key + ": names no look (" + source + " has: " + listNames(known) + ")");
}

OCIO::Interpolation interpolationOf(const std::string& name) {
    if (name == "nearest") return OCIO::INTERP_NEAREST;
    if (name == "linear") return OCIO::INTERP_LINEAR;
    if (name == "tetrahedral") return OCIO::INTERP_TETRAHEDRAL;
    return OCIO::INTERP_BEST;
}

// One grade step as an OCIO transform working -> working.
OCIO::TransformRcPtr gradeTransform(const OCIO::Config& config, const GradeStep& step, const std::string& working,
                                    const std::string& key, const std::string& source) {
    const OCIO::TransformDirection direction = step.inverse ? OCIO::TRANSFORM_DIR_INVERSE : OCIO::TRANSFORM_DIR_FORWARD;
    if (step.kind == GradeKind::Look) {
        requireLooks(config, step.look, key + ".look", source);
        auto look = OCIO::LookTransform::Create();
        look->setSrc(working.c_str());
        look->setDst(working.c_str());
        look->setLooks(step.look.c_str());
        look->setDirection(direction);
        return look;
    }
    OCIO::TransformRcPtr core;
    if (step.kind == GradeKind::Cdl) {
        auto cdl = OCIO::CDLTransform::Create();
        const double slope[3] = {step.slope.x, step.slope.y, step.slope.z};
        const double offset[3] = {step.offset.x, step.offset.y, step.offset.z};
        const double power[3] = {step.power.x, step.power.y, step.power.z};
        cdl->setSlope(slope);
        cdl->setOffset(offset);
        cdl->setPower(power);
        cdl->setSat(step.saturation);
        cdl->setStyle(step.clamp ? OCIO::CDL_ASC : OCIO::CDL_NO_CLAMP);
        cdl->setDirection(direction);
        core = cdl;
    } else {
        if (!std::filesystem::is_regular_file(step.file)) throw InputError(key + ".file: " + step.file + ": no such file");
        auto file = OCIO::FileTransform::Create();
        file->setSrc(step.file.c_str());
        file->setCCCId(step.cccid.c_str());
        file->setInterpolation(interpolationOf(step.interpolation));
        file->setCDLStyle(step.clamp ? OCIO::CDL_ASC : OCIO::CDL_NO_CLAMP);
        file->setDirection(direction);
        core = file;
    }
    const std::string space = step.space.empty() ? working : requireColorSpace(config, step.space, key + ".space", source);
    if (space == working) return core;
    // The step works in its own space: there and back around it.
    auto group = OCIO::GroupTransform::Create();
    auto to = OCIO::ColorSpaceTransform::Create();
    to->setSrc(working.c_str());
    to->setDst(space.c_str());
    group->appendTransform(to);
    group->appendTransform(core);
    auto back = OCIO::ColorSpaceTransform::Create();
    back->setSrc(space.c_str());
    back->setDst(working.c_str());
    group->appendTransform(back);
    return group;
}

glm::vec3 applyTo(const OCIO::ConstCPUProcessorRcPtr& cpu, glm::vec3 rgb) {
    float px[3] = {rgb.x, rgb.y, rgb.z};
    cpu->applyRGB(px);
    return {px[0], px[1], px[2]};
}

// The 3x3 matrix of a processor that is linear, or nothing when it is not (a log or display
// encoding): checked on scaled primaries and on their sum.
std::optional<glm::mat3> linearMatrix(const OCIO::ConstProcessorRcPtr& processor) {
    auto cpu = processor->getDefaultCPUProcessor();
    glm::mat3 m;
    for (int c = 0; c < 3; ++c) {
        glm::vec3 e(0.0f);
        e[c] = 1.0f;
        m[c] = applyTo(cpu, e);
    }
    auto close = [](glm::vec3 a, glm::vec3 b) { return glm::all(glm::lessThanEqual(glm::abs(a - b), 1e-5f * (glm::abs(b) + 1.0f))); };
    for (glm::vec3 v : {glm::vec3(0.25f, 0.5f, 2.0f), glm::vec3(4.0f, 0.1f, 0.0f), glm::vec3(1.0f)})
        if (!close(applyTo(cpu, v), m * v)) return std::nullopt;
    return m;
}

// ACES2065-1 (AP0, D60 white) to CIE XYZ, SMPTE ST 2065-1.
const glm::mat3 kAp0ToXyz = glm::transpose(glm::mat3(0.9525523959f, 0.0f, 0.0000936786f,     //
                                                     0.3439664498f, 0.7281660966f, -0.0721325464f,  //
                                                     0.0f, 0.0f, 1.0088251844f));

// The output space's primaries and white as the config places them in the ACES reference frame
// (through aces_interchange: ACEScg gives AP1 with the ACES white exactly). A space the config
// reaches with a chromatic adaptation (Rec.709 from D65) comes out adapted to D60. Without that
// role, through the CIE XYZ D65 display reference instead. Nothing for a non-linear space.
std::optional<Chromaticities> chromaticitiesOf(const OCIO::Config& config, const std::string& space) {
    std::optional<glm::mat3> to_xyz;
    if (config.getColorSpace(OCIO::ROLE_INTERCHANGE_SCENE)) {
        if (auto m = linearMatrix(config.getProcessor(space.c_str(), OCIO::ROLE_INTERCHANGE_SCENE))) to_xyz = kAp0ToXyz * *m;
    } else if (config.getColorSpace(OCIO::ROLE_INTERCHANGE_DISPLAY)) {
        to_xyz = linearMatrix(config.getProcessor(space.c_str(), OCIO::ROLE_INTERCHANGE_DISPLAY));
    }
    if (!to_xyz) return std::nullopt;
    auto xy = [](glm::vec3 XYZ) { return glm::vec2(XYZ.x, XYZ.y) / (XYZ.x + XYZ.y + XYZ.z); };
    const glm::mat3& m = *to_xyz;
    return Chromaticities{xy(m[0]), xy(m[1]), xy(m[2]), xy(m[0] + m[1] + m[2])};
}

std::string resolveDisplay(const OCIO::Config& config, const std::string& wanted, const std::string& source) {
    std::vector<std::string> displays;
    for (int i = 0; i < config.getNumDisplays(); ++i) displays.push_back(config.getDisplay(i));
    if (wanted.empty()) {
        if (displays.empty()) throw InputError(source + ": has no displays, so no preview can be made");
        return config.getDefaultDisplay();
    }
    for (const auto& d : displays)
        if (d == wanted) return d;
    throw InputError("color.display: no display '" + wanted + "' in " + source + " (it has: " + listNames(displays) + ")");
}

std::string resolveView(const OCIO::Config& config, const std::string& display, const std::string& wanted,
                        const std::string& source) {
    std::vector<std::string> views;
    for (int i = 0; i < config.getNumViews(display.c_str()); ++i) views.push_back(config.getView(display.c_str(), i));
    if (wanted.empty()) return config.getDefaultView(display.c_str());
    for (const auto& v : views)
        if (v == wanted) return v;
    throw InputError("color.view: display '" + display + "' of " + source + " has no view '" + wanted + "' (it has: " +
                     listNames(views) + ")");
}

}  // namespace

// The canonical name of a colour space given by name, alias or role.
std::string requireColorSpace(const OCIO::Config& config, const std::string& name, const std::string& key,
                              const std::string& source) {
    OCIO::ConstColorSpaceRcPtr cs = config.getColorSpace(name.c_str());
    if (!cs)
        throw InputError(key + ": no colour space '" + name + "' in " + source + " (it has: " +
                         listNames(colorSpaceNames(config)) + ")");
    return cs->getName();
}

OCIO::ConstConfigRcPtr loadColorConfig(const ColorSettings& color, std::string& source) {
    std::string file = color.config;
    std::string key = "color.config";
    if (file.empty()) {
        const char* env = std::getenv("OCIO");
        if (env && *env) {
            file = env;
            key = "$OCIO";
        }
    }
    try {
        if (file.empty()) {
            source = kBuiltinSource;
            std::istringstream text(embeddedColorConfigs().at("voxlux.ocio"));
            return OCIO::Config::CreateFromStream(text);
        }
        source = file;
        if (!std::filesystem::is_regular_file(file)) throw InputError(file + ": no such OCIO config (" + key + ")");
        OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(file.c_str());
        config->validate();
        return config;
    } catch (const OCIO::Exception& e) {
        throw InputError(file + ": not a usable OCIO config (" + oneLine(e) + ")");
    }
}

ColorPipeline resolveWorkingSpace(const ColorSettings& color) {
    ColorPipeline p;
    p.config = loadColorConfig(color, p.config_source);
    const OCIO::Config& config = *p.config;
    const std::string& source = p.config_source;
    try {
        if (color.working_space.empty()) {
            if (!config.getColorSpace(OCIO::ROLE_SCENE_LINEAR))
                throw InputError(source + ": has no scene_linear role; set color.working_space (it has: " +
                                 listNames(colorSpaceNames(config)) + ")");
            p.working_space = config.getColorSpace(OCIO::ROLE_SCENE_LINEAR)->getName();
        } else {
            p.working_space = requireColorSpace(config, color.working_space, "color.working_space", source);
        }
        if (config.getColorSpace(OCIO::ROLE_INTERCHANGE_DISPLAY))
            p.xyz_to_working = linearMatrix(config.getProcessor(OCIO::ROLE_INTERCHANGE_DISPLAY, p.working_space.c_str()));
    } catch (const OCIO::Exception& e) {
        throw InputError(source + ": " + oneLine(e));
    }
    return p;
}

ColorPipeline buildColorTransforms(ColorPipeline p, const ColorSettings& color, bool with_preview) {
    const OCIO::Config& config = *p.config;
    const std::string& source = p.config_source;
    try {
        p.output_space = color.output_space.empty()
                             ? p.working_space
                             : requireColorSpace(config, color.output_space, "color.output_space", source);
        p.unpremultiply = color.unpremultiply;

        auto grade = OCIO::GroupTransform::Create();
        for (size_t i = 0; i < color.grade.size(); ++i) {
            const std::string key = "color.grade[" + std::to_string(i) + "]";
            OCIO::TransformRcPtr step = gradeTransform(config, color.grade[i], p.working_space, key, source);
            try {
                config.getProcessor(step);  // parses its file now, so a bad one is named by its step
            } catch (const OCIO::Exception& e) {
                throw InputError(key + ": " + oneLine(e));
            }
            grade->appendTransform(step);
        }
        p.grade = config.getProcessor(grade);
        p.output = config.getProcessor(p.working_space.c_str(), p.output_space.c_str());
        if (with_preview || !color.display.empty() || !color.view.empty()) {
            p.display = resolveDisplay(config, color.display, source);
            p.view = resolveView(config, p.display, color.view, source);
            auto view = OCIO::DisplayViewTransform::Create();
            view->setSrc(p.working_space.c_str());
            view->setDisplay(p.display.c_str());
            view->setView(p.view.c_str());
            p.preview = config.getProcessor(view);
        }
        p.output_chromaticities = chromaticitiesOf(config, p.output_space);
    } catch (const OCIO::Exception& e) {
        // Transforms OCIO cannot chain in this config.
        throw InputError(source + ": " + oneLine(e));
    }
    return p;
}

ColorPipeline buildColorPipeline(const ColorSettings& color, bool with_preview) {
    return buildColorTransforms(resolveWorkingSpace(color), color, with_preview);
}

}  // namespace voxlux
