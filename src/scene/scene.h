// The scene: everything a render needs, as parsed from JSON (docs/scene.md) or built by the quick
// form of `voxlux render cache.vdb`. Plain data; reading, validation and writing live in
// scene_read.cpp and scene_write.cpp, and for a lighting method's settings in its folder
// (src/lighting/<method>/<method>_settings.cpp).
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/frame_set.h"
#include "method_settings.h"   // generated from the lighting methods (cmake/method_settings.cmake)
#include "scene/filter.h"

namespace voxlux {

// A grid chosen by name; `index` picks among several grids with the same name.
struct GridRef {
    std::string name;
    int index = 0;
    bool operator==(const GridRef&) const = default;
};

enum class LevelSetPolicy { Reject, ConvertToFog };

// The world axis that points up in the cache. Auto: as the file says (src/volume/up_axis.h), else Y.
enum class UpAxis { Auto, X, Y, Z };

// The order a transform's rotations are applied in: Xyz turns about X first, then Y, then Z
// (R = Rz Ry Rx, Houdini's default); Zxy is Nuke's default for an Axis or a Camera.
enum class RotateOrder { Xyz, Xzy, Yxz, Yzx, Zxy, Zyx };
inline constexpr const char* kRotateOrderNames[] = {"xyz", "xzy", "yxz", "yzx", "zxy", "zyx"};
// The rotation of `degrees` about X, Y and Z, turned in `order`.
glm::mat3 rotationMatrix(glm::vec3 degrees, RotateOrder order);

// One key of an animated transform: its pose at `frame`.
struct TransformKey {
    double frame = 0.0;
    glm::vec3 translate{0.0f};
    glm::vec3 rotate{0.0f};
    glm::vec3 scale{1.0f};
};

// Where a volume sits in the world, applied on top of its file's own transform (Houdini's and
// Blender's object transform): a 4x4 `matrix`, or translate * rotate * scale with the rotation in
// degrees, turned in `rotate_order`. Keyed per frame, the pose between two keys is the linear
// blend of their translate, rotate and scale (as linear channels in Houdini and Nuke), and held
// before the first key and after the last.
struct VolumeTransform {
    glm::vec3 translate{0.0f};
    glm::vec3 rotate{0.0f};
    glm::vec3 scale{1.0f};
    RotateOrder rotate_order = RotateOrder::Xyz;
    std::optional<glm::mat4> matrix;       // given: translate, rotate, scale and keys are unused
    std::vector<TransformKey> keys;        // non-empty: animated, frames strictly increasing
    std::string chan;                      // the Nuke .chan file the keys were read from ("" = written inline)
};
// The keys (frames strictly increasing) around `frame`: keys a and b and the weight of b there,
// held at the first key before it and at the last after it (a == b, weight 0).
struct KeyBlend {
    size_t a = 0, b = 0;
    float weight = 0.0f;
};
KeyBlend keyBlend(const std::vector<TransformKey>& keys, double frame);

// Its matrix at `frame` (unset: a still, posed at the first key), from the file's world to the scene's.
glm::mat4 volumeTransformMatrix(const VolumeTransform& t, std::optional<double> frame = std::nullopt);

struct TransferPoint {
    float value = 0.0f;
    float extinction = 0.0f;
    glm::vec3 albedo{1.0f};
};

// One region of a two-dimensional transfer function (Kniss, Kindlmann and Hansen 2002): a rectangle
// or a triangle in the plane of a voxel's value and its gradient magnitude (value per world unit of
// the file, before the volume's transform).
// Its weight is 1 inside; `fade` (0..1) ramps it from 0 at the edges to 1 at that share of the way
// to the centre, so that a boundary between materials is soft rather than one voxel sharp (a
// gradient range from 0 fades at its upper end only).
constexpr float kAnyGradient = 3.0e38f;    // a rectangle's gradient range without an upper end
struct TransferRegion {
    std::string name;                      // optional: what the region selects ("skin", "bone")
    bool triangle = false;
    glm::vec2 value{0.0f}, gradient{0.0f, kAnyGradient};   // rectangle: [lo, hi] along each axis
    std::array<glm::vec2, 3> corners{};    // triangle: (value, gradient) corners
    float fade = 0.0f;
    float extinction = 0.0f;               // multiplies material.density_scale
    glm::vec3 albedo{1.0f};                // multiplies material.albedo
    // Kniss 2003 Eq. 8 per material: the share of indirect light kept per unit optical depth, in
    // place of effects.indirect's attenuation. Every region of a function has one, or none does.
    std::optional<glm::vec3> transport;
    // Kniss 2003 Eq. 11 per material: how much of effects.surface's shading the material takes,
    // 0..1 (times the gradient's ramp). Every region of a function has one, or none does.
    std::optional<float> surface;
};

// What density_scale's extinction is per: a world unit, or the length of a voxel (the smallest
// edge), so that a look carries over between caches of different scales.
enum class DensityUnits { World, Voxel };

struct Material {
    float density_scale = 1.0f;            // grid value -> extinction per density_units length
    DensityUnits density_units = DensityUnits::World;
    glm::vec3 albedo{0.9f};
    float anisotropy = 0.0f;               // Henyey-Greenstein g
    std::vector<TransferPoint> transfer;   // empty: extinction = density * density_scale
    // Non-empty: each voxel is classified by its value and gradient magnitude before it is
    // interpolated (src/optics/transfer_function_2d.h); excludes `transfer`.
    std::vector<TransferRegion> transfer_2d;
};

// Ambient is uniform light from every direction (radiance color * intensity), occluded only when
// effects.ambient_occlusion is on. Environment is the radiance of a lat-long map from every
// direction (docs/environment.md).
enum class LightType { Directional, Point, Spot, Ambient, Environment };

class EnvironmentMap;

// What the fast methods keep of an environment map beside its median-cut lights: its darkest value
// per channel as ambient light (floor), or nothing (none: the lights carry it all).
enum class EnvironmentRemainder { Floor, None };
inline const std::vector<std::string> kEnvironmentRemainderNames{"floor", "none"};

// An environment light's map and how it is placed and approximated (src/render/environment_lights.h).
struct EnvironmentSettings {
    std::string map;                       // resolved path of a lat-long OpenEXR image (R, G, B)
    std::string map_colorspace;            // its OCIO colour space; "" = the config's scene_linear role
    std::optional<glm::vec3> up;           // where its top row faces; unset: the first volume's up
    float rotation = 0.0f;                 // degrees about up, counter-clockwise seen from above
    bool visible_to_camera = false;        // the beauty's background (alpha 1) where the camera sees it
    int median_cut_lights = 16;            // the fast methods' directional lights (Debevec 2005)
    EnvironmentRemainder remainder = EnvironmentRemainder::Floor;
    // Set by withEnvironmentLights, never read from a scene file: the map in the working space,
    // oriented and scaled by the light's colour and intensity.
    std::shared_ptr<const EnvironmentMap> loaded;
    size_t repaired_pixels = 0;            // of the map's, NaN or infinite (black) or with a channel below 0 (0)
};

struct Light {
    std::string name;                      // optional; light edits may address the light by it
    bool enabled = true;                   // a disabled light is kept in the scene but casts no light
    LightType type = LightType::Directional;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  // the way the light travels
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    float cone_angle = 30.0f;              // spot: outer half-angle, degrees
    float cone_softness = 5.0f;            // spot: degrees of falloff inside the outer angle
    std::string group;                     // its light group (output.aovs "light_groups"); "" = the default group
    // Light linking: the names of the volumes it lights, and of those whose extinction shadows it;
    // unset = every volume. Not for ambient lights.
    std::optional<std::vector<std::string>> volumes;
    std::optional<std::vector<std::string>> shadow_volumes;
    std::optional<EnvironmentSettings> environment;   // type environment
    // Made by withEnvironmentLights for the march, never read from a scene file: one of the median-cut
    // lights or the remainder of the environment light lights[*from_environment].
    std::optional<size_t> from_environment;
};

// A shot camera from another package (camera.file, src/scene/camera_file.h): its pose per frame
// and, where the file has one, its lens.
struct CameraFile {
    std::string path;                      // resolved: a Nuke .chan, or a glTF 2.0 (.gltf, .glb) or FBX scene
    std::string name;                      // glTF/FBX: the camera taken ("" = the file's first)
    VolumeTransform pose;                  // camera-to-world: .chan keys in rotate_order, or a glTF/FBX matrix
    std::vector<float> vertical_fov;       // degrees: one per key of a .chan, one for a glTF/FBX; empty = fov
};

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 look_at{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    std::optional<glm::mat4> matrix;       // camera-to-world; overrides position/look_at/up
    float fov = 40.0f;                     // vertical, degrees (or from focal_length and film_back)
    float focal_length = 0.0f;             // mm; > 0: fov = 2 atan(film_back.y / (2 focal_length))
    glm::vec2 film_back{36.0f, 24.0f};     // mm, width and height (the height fits the frame)
    std::optional<CameraFile> file;        // camera.file: replaces the pose, and fov where it has a lens
    // Depth of field (docs/compositing.md): a thin lens of f-number fstop (0: a pinhole), its
    // aperture focal_length / fstop wide (the focal length of the fov where none is given), in
    // millimetres of which world_unit_mm make a world unit; sharp at focus_distance world units
    // along the view; each pixel's rays spread over the lens (at least lens_samples of them).
    float fstop = 0.0f;
    float focus_distance = 0.0f;
    float world_unit_mm = 1000.0f;
    int lens_samples = 16;
    // Camera-to-world at shutter open and close (camera.motion), blurred under render.motion_blur;
    // the transform above stays the frame's own (EXR metadata, the eye sweep).
    std::optional<std::array<glm::mat4, 2>> motion;
};

enum class Backend { Auto, Cpu, Gl };

// March: the ray marcher with the scene's effects. Reference: an unbiased Monte Carlo path tracer
// (src/reference/reference_renderer.h) on the CPU, to check the march against.
enum class RenderMethod { March, Reference };

struct ReferenceSettings {
    int spp = 64;                          // samples per pixel
    int max_bounces = 16;                  // scattering events per path; 1 = single scattering
    int seed = 1;
    int roulette_depth = 3;                // bounces before Russian roulette may end a path
};

// Velocity motion blur (docs/scene.md, "Motion blur"): each camera ray takes a time within the
// shutter, and the medium is looked up where the velocity grid says it was at that time.
struct MotionBlur {
    float shutter_open = -0.25f;           // frames from the frame's own time
    float shutter_close = 0.25f;
    std::optional<GridRef> velocity;       // unset: the first of vel, v, velocity the file has
    float velocity_scale = 1.0f;
    float fps = 24.0f;                     // the velocity grid is per second; motion is per frame
    int samples = 8;                       // times a pixel spreads over the shutter
};

struct RenderSettings {
    int width = 512;
    int height = 512;
    float step = 0.5f;                     // voxels (of the smallest voxel edge)
    float shadow_step = 1.0f;              // voxels, for ray-marched shadows
    float transmittance_cutoff = 1e-4f;
    float exposure = 0.0f;                 // stops, applied to the beauty and light AOVs before the output transform
    Filter filter = Filter::Trilinear;     // reconstruction of the grids between voxels
    Backend backend = Backend::Auto;
    RenderMethod method = RenderMethod::March;
    ReferenceSettings reference;           // read only with method reference
    std::optional<MotionBlur> motion_blur;
    // A render region (Cycles' border, Arnold's region): [x_min, y_min, x_max, y_max] as fractions
    // of the image, y down from the top row; pixels outside it are not marched and stay empty.
    std::optional<std::array<float, 4>> region;
};

// Whether `b` is a render region (fractions with 0 <= min < max <= 1), and what one is.
bool isRegion(const std::array<float, 4>& b);
inline constexpr const char* kRegionExpected = "expected [x_min, y_min, x_max, y_max], fractions of the image with 0 <= min < max <= 1";

// The pixels [x0, y0) to [x1, y1) a render of `width` x `height` marches: the region's, rounded
// outward to whole pixels, or the whole image.
glm::ivec4 regionPixels(const RenderSettings& render, int width, int height);

// Kniss 2003 Eq. 11: Blinn-Phong surface shading blended in where the density gradient is steep.
struct SurfaceShading {
    float gradient_low = 0.05f;            // |grad density| per voxel where surface shading starts
    float gradient_high = 0.25f;           // ... and where it is complete
    float specular = 0.5f;
    float shininess = 32.0f;
};

// Kniss 2003 Sec. III.D: seeded multi-octave noise perturbing extinction, transport colour and
// the data lookup, in the march and in the light propagation alike.
struct Perturbation {
    int seed = 1;
    float scale = 0.0f;                    // world size of the first octave's tile; 0 = 64 voxels
    int octaves = 3;
    float lacunarity = 2.0f;
    float gain = 0.5f;
    float density = 0.0f;                  // relative extinction amplitude
    float transport = 0.0f;                // relative transport-colour amplitude
    float displacement = 0.0f;             // lookup displacement amplitude, index voxels
    glm::vec3 velocity{0.0f};              // noise drift per frame, world units
    float time = 0.0f;                     // frames added to the sequence frame
};

// The effects: the march's own, and each lighting method's settings, which MethodSettings derives
// from (generated from the methods' method.cmake), so that scene.effects.cone is effects.cone as
// the JSON spells it.
struct Effects : MethodSettings {
    ShadowMethod shadows = ShadowMethod::Raymarch;
    std::optional<SurfaceShading> surface;
    std::optional<Perturbation> perturbation;
    int light_resolution = 128;            // light-grid cells along the volume's longest side
    int light_memory_mb = 2048;            // budget for light grid, SAT, light cache and illumination volume
};

// Light a grid emits (fire, explosions). Each source (at most VX_MAX_EMISSION) maps its grid's
// value to radiance per world unit in the working space; the sources add. Their grids may have
// any topology: the bricks are the union of all grids' bricks. Value 0 is empty space and emits
// nothing (the scene reader enforces it).
enum class EmissionKind { Constant, Blackbody, Ramp };
// Blackbody brightness, as the luminance Y of CIE XYZ: Luminance gives every temperature
// Y = intensity, only the colour changes; Physical scales it with the Planck radiance's Y,
// intensity at reference_temperature.
enum class BlackbodyNormalization { Luminance, Physical };

struct RampPoint {
    float value = 0.0f;
    glm::vec3 color{0.0f};
};

struct EmissionSource {
    GridRef grid;
    EmissionKind kind = EmissionKind::Constant;
    float intensity = 1.0f;
    glm::vec3 color{1.0f};                 // Constant: radiance = value * color * intensity
    float temperature_scale = 1.0f;        // Blackbody: kelvin = value * scale + offset
    float temperature_offset = 0.0f;
    float cutoff = 0.0f;                   // Blackbody: kelvin below which nothing is emitted
    BlackbodyNormalization normalization = BlackbodyNormalization::Luminance;
    float reference_temperature = 1500.0f; // Physical: the kelvin at which luminance = intensity
    std::vector<RampPoint> ramp;           // Ramp: colour by grid value, linear between points,
                                           // clamped beyond them; radiance = colour * intensity
};

// What a volume is to the camera (docs/scene.md, "Roles"): seen; a holdout (it occludes camera and
// light rays, and contributes no colour and no alpha of its own); or unseen, casting shadows only.
enum class VolumeRole { Visible, Matte, ShadowOnly };
inline const std::vector<std::string> kVolumeRoleNames{"visible", "matte", "shadow_only"};

// One volume of the scene (an entry of `volumes`): a cache or a sequence of them, where it sits,
// its material and the light its grids emit.
struct VolumeSpec {
    std::string name;                      // unique in the scene (AOVs, messages); scene_read names it from the file when unset
    std::string path;                      // may contain a #### frame pattern
    std::optional<FrameSet> frames;        // the frames of a #### pattern: [first, last], or "1-240x2,300"
    GridRef density{"density", 0};
    std::optional<GridRef> color;          // Cd, vec3
    LevelSetPolicy level_set = LevelSetPolicy::Reject;
    UpAxis up = UpAxis::Auto;              // frames the default camera and orients the quick form's light
    std::optional<VolumeTransform> transform;
    // Copies placed again on top of `transform`, each still (no keys): the volume renders once per
    // instance, all reading the same bricks; empty: once, at `transform`.
    std::vector<VolumeTransform> instances;
    VolumeRole role = VolumeRole::Visible;
    bool enabled = true;                   // a disabled volume stays in the scene but is neither loaded nor rendered
    // Made by renderedScene from holdouts[*holdout_mesh]'s mesh, never read from a scene file: the
    // mesh's voxelised cells, which shadow the volumes (volume/mesh_voxels.h).
    std::optional<size_t> holdout_mesh;
    Material material;
    std::vector<EmissionSource> emission;
};
// Where `volume` sits at `frame`: its transform's matrix, or the identity. Applied after the
// bricks (which stay in the file's index space), so a move re-reads and re-bricks nothing.
glm::mat4 volumePlacement(const VolumeSpec& volume, std::optional<double> frame);
// Where each copy of `volume` sits at `frame`: each instance's pose after the placement, or the
// placement alone.
std::vector<glm::mat4> instancePlacements(const VolumeSpec& volume, std::optional<double> frame);
// The volumes the march places, instances counted.
struct Scene;
size_t placedVolumeCount(const Scene& scene);
// Whether the scene places several volumes: more than one placed volume, or a volume that is not
// visible (a matte, or shadows only).
bool placesSeveral(const Scene& scene);
// placesSeveral of the scene's own volumes (its mesh holdouts' cells left out): whether the default
// camera frames all volumes' bricks rather than the one's active voxels.
bool framesSeveral(const Scene& scene);
// Whether the scene renders through the march of several volumes (shaders/vx_volumes.h): it places
// several, or links lights to volumes (linksLights).
bool rendersAsSeveral(const Scene& scene);
// The scene as it renders: its disabled volumes left out (scene_read keeps one enabled at least).
Scene withEnabledVolumes(Scene scene);
// The scene as the Renderer renders it: withEnabledVolumes, then one shadow-only volume per mesh
// holdout (VolumeSpec::holdout_mesh), after the scene's own.
Scene renderedScene(Scene scene);
// Whether an enabled volume of the scene has emission sources (one of several emits only when it
// is visible, shaders/vx_volumes.h).
bool emits(const Scene& scene);

enum class PixelType { Half, Float };

// One AOV layer of the EXR; pixel_type unset: the output's pixel_type (depth: always float).
struct AovSpec {
    std::string name;                      // one of knownAovs()
    std::optional<PixelType> pixel_type;
    bool operator==(const AovSpec&) const = default;
};

struct OutputSpec {
    std::string path;                      // may contain #### for sequences
    PixelType pixel_type = PixelType::Half;
    std::string compression = "zip";       // one of knownCompressions()
    std::vector<AovSpec> aovs;             // each of knownAovs() at most once
    std::string preview;                   // 8-bit PNG through color.display/view; "" = none; may contain ####
    bool deep = false;                     // also write deep samples to deepPath(path) (docs/scene.md, Deep output)
    int deep_samples = 16;                 // at most this many a pixel, 1..64
};

// Where the deep image of an output goes: "fire.####.exr" -> "fire.####.deep.exr".
std::string deepPath(const std::string& output_path);

// One grading step, applied in order to the beauty in the working space.
enum class GradeKind { Look, Cdl, CdlFile, Lut };

struct GradeStep {
    GradeKind kind = GradeKind::Cdl;
    std::string look;                      // Look: an OCIO look name, or several as "a, +b"
    std::string file;                      // CdlFile (.cc, .ccc, .cdl) and Lut (.cube, .clf, .spi3d, ...)
    std::string cccid;                     // CdlFile: which correction ("" = the first)
    glm::vec3 slope{1.0f}, offset{0.0f}, power{1.0f};  // Cdl: ASC CDL v1.2
    float saturation = 1.0f;
    bool clamp = false;                    // Cdl, CdlFile: the ASC v1.2 clamp to [0, 1] (off: HDR-safe)
    std::string interpolation = "best";    // Lut: nearest, linear, tetrahedral, best
    std::string space;                     // Cdl, CdlFile, Lut: the colour space it works in ("" = working)
    bool inverse = false;
};

// OpenColorIO colour management (docs/color.md).
struct ColorSettings {
    std::string config;                    // OCIO config file; "" = $OCIO, else voxlux's own config
    std::string working_space;             // lights, albedo, transport colours; "" = the scene_linear role
    std::string output_space;              // of the EXR; "" = the working space
    std::vector<GradeStep> grade;
    bool unpremultiply = true;             // grade colour divided by alpha (where alpha > 0), then premultiplied
    std::string display;                   // preview: "" = the config's default display
    std::string view;                      // preview: "" = the display's default view
};

// A CG surface in front of or inside the volumes that holds them out (holdouts): each camera ray
// stops where it meets it (docs/compositing.md). Either the CG render's depth image, or the CG's
// mesh, which also shadows the volumes through its voxelised cells.
struct Holdout {
    std::string depth;                     // an EXR the CG render wrote, at the render's resolution; # as in a volume's path
    std::string channel = "Z";             // its channel of camera-space Z (as Karma, Arnold and Cycles write it)
    bool ray_distance = false;             // the channel holds the distance along each pixel's ray instead
    std::string mesh;                      // or an OBJ, glTF or FBX file of the CG; # as in a volume's path
    std::optional<VolumeTransform> transform;  // where the mesh sits, as a volume's transform (keys too)
    float voxel_size = 0.0f;               // edge of the mesh's shadowing cells, world units; 0: the volumes' finest voxel
    std::optional<float> shadow_reach;     // how far past the volumes' box the cells are made, world units; unset: its largest side
};

struct Scene {
    std::vector<VolumeSpec> volumes{1};    // at least one, and at least one enabled
    // The first enabled volume (the Renderer's first): the one whose frames, grids and up axis the
    // quick form, the sequence tools and the viewer's timeline take.
    // (The first volume when none is enabled, which only a scene built in code can be.)
    VolumeSpec& volume();
    const VolumeSpec& volume() const;
    std::vector<Light> lights;
    std::vector<Holdout> holdouts;         // the nearest surface of all of them cuts a ray
    std::optional<Camera> camera;          // absent: framed from the volume's bounding box
    RenderSettings render;
    Effects effects;
    ColorSettings color;
    OutputSpec output;
};

// How many enabled lights the scene has that are ambient (`ambient`), or directional, point or spot
// (an environment light counts as neither: its median-cut lights and remainder do).
int enabledLightCount(const Scene& scene, bool ambient);

const std::vector<std::string>& knownAovs();

// The light groups output.aovs "light_groups" splits the beauty into, each written as a layer
// lightgroup.<name> beside lightgroup.emission (the emitted light's own): the groups the lights
// name, in the order they first appear, with "default" for the lights that name none. A scene
// whose lights name no group has the default group alone.
inline const std::string kEmissionLayer = "emission";   // the emitted light's layer, lightgroup.emission
struct LightGroups {
    std::vector<std::string> names;        // empty when the AOV is not asked for
    std::vector<int> of_light;             // per scene light, its group's index in names
};
LightGroups lightGroups(const Scene& scene);
// The marches the light groups take: one per group, and one more for the emitted light when the
// scene emits; 1 without light groups. Under propagation each reads an illumination volume of its
// own.
int lightGroupMarches(const Scene& scene);

// Light linking (lights[i].volumes, shadow_volumes): the distinct pairs of volume lists the enabled
// lights take, in the order they first appear, each a link set; a light with neither key is in the
// set that lights and is shadowed by every volume. Without any link, no sets: the kernel then
// lights every volume by every light as it always did.
struct LinkSet {
    std::optional<std::vector<std::string>> lit;       // sorted names; unset = every volume
    std::optional<std::vector<std::string>> shadows;
    bool operator==(const LinkSet&) const = default;
};
struct LightLinks {
    std::vector<LinkSet> sets;             // empty when no light is linked
    std::vector<int> of_light;             // per scene light, its set (0 when no light is linked)
};
LightLinks lightLinks(const Scene& scene);
// Whether any enabled light names volumes or shadow volumes.
bool linksLights(const Scene& scene);
const std::vector<std::string>& knownCompressions();  // EXR compressions by their OpenEXR names

}  // namespace voxlux
