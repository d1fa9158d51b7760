// Light grid: the dense, usually coarser grid the light passes work on (Schlegel 2011, Fig. 11).
// It covers the occupied bricks' bounding box at a resolution the scene chooses, independent of
// the data's, and box-filters the visible bricks' extinction into it. It is dense on purpose: a
// summed-area table needs every cell. Its size is bounded by effects.light_resolution and by the
// memory budget, never by the data's bounding box.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "kernel/kernel_inputs.h"

namespace voxlux {

// Cells are clamped to this optical depth across one cell. Beyond it a cell is black either way;
// the clamp keeps one absurd voxel (1e30) from setting the SAT's quantum and so from rounding
// every ordinary cell to zero (src/lighting/extinction_sat/summed_volume.h).
constexpr float kMaxCellOpticalDepth = 1e4f;

struct LightGrid {
    glm::ivec3 dims{0};
    glm::vec3 origin{0.0f};        // index-space position of cell (0, 0, 0)'s low corner
    float cell = 1.0f;             // cell edge in index voxels
    int planes = 1;                // 1: extinction; 4: and extinction * (1 - bleeding * albedo) rgb; 0: emission only
    std::vector<float> values;     // plane-major; in a plane x fastest: mean value over the cell
    std::vector<uint8_t> needed;   // 1 where the march may read the light cache (near extinction)
    std::vector<float> emission;   // when asked for: RGB per cell, x fastest: mean emitted radiance
                                   // per world unit over the cell
    std::vector<float> scattering; // with the emission, of several volumes: RGB per cell, the mean
                                   // scattering coefficient (of one volume: its albedo times the extinction)
    std::vector<float> transport_depth;   // when asked for: 3 planes (R, G, B), x fastest: mean
                                          // extinction times -ln(transport colour) over the cell
    uint64_t clamped_cells = 0;    // cells above kMaxCellOpticalDepth, clamped
    size_t cells() const { return size_t(dims.x) * dims.y * dims.z; }
    glm::mat4 lightToIndex() const;
};

// World edge of a light-grid cell: the cube root of its world volume (cells are cubes in index
// space, so this is their edge where voxels are cubic and a mean edge where they are not).
float cellWorldSize(const glm::mat4& light_to_world);

// What a light grid of resolution `resolution` (cells along the longest side) costs in bytes:
// grid, SAT and a light cache of `cache_channels` floats per cell.
size_t lightGridBytes(glm::ivec3 dims, int planes, int cache_channels);

// Cells per axis for a box of `extent` index voxels at `resolution` cells along the longest side.
glm::ivec3 lightGridDims(glm::vec3 extent, int resolution);

// Whether the kernel's 32-bit indices reach every SAT word and light-cache float.
bool lightGridIndexable(glm::ivec3 dims, int planes, int cache_channels);

// The warning for a grid with clamped cells.
std::string clampedCellsWarning(const LightGrid& grid);

// Index-space size of the medium's box (PageTable::medium_min), which light grids cover.
glm::vec3 occupiedExtent(const PageTable& pages);
// The same for the medium of kernel inputs: of several volumes, the shared frame's box of them all.
glm::vec3 lightGridExtent(const KernelInputs& in);

// `requested` cells along the longest side, but no finer than a quarter voxel: finer cells would
// only repeat voxels (a tiny volume at the default 128).
int cappedLightResolution(glm::vec3 extent, int requested);

// What a grid of given dimensions costs, for fitGridResolution.
struct GridCost {
    std::function<size_t(glm::ivec3)> bytes;
    std::function<bool(glm::ivec3)> indexable;   // the kernel's 32-bit indices reach every value
    std::string index_limit;                     // what would overflow them, for the warning
};

// The resolution (cells along the longest side) actually used for a grid over `extent` index
// voxels: `requested`, or the largest below it whose cost fits `budget_bytes` and is indexable.
// Sets `warning` (naming `what` and both resolutions) when it had to reduce.
int fitGridResolution(glm::vec3 extent, int requested, size_t budget_bytes, const GridCost& cost,
                      const std::string& what, std::string& warning);

// The resolution actually used: `requested`, or the largest below it whose light grid, SAT and
// cache fit in `budget_bytes` and are indexable. Sets `warning` (naming the light cache and both
// resolutions) when it had to reduce.
int fitLightResolution(glm::vec3 extent, int requested, int planes, int cache_channels, size_t budget_bytes,
                       std::string& warning);

// What buildLightGrid box-filters into the grid.
struct LightGridContents {
    bool extinction = true;   // the extinction plane and its `needed` mask
    float bleeding = 0.0f;    // > 0, with extinction: the three colour-bleeding planes
    bool emission = false;    // the emitted radiance, when the scene's sources emit
    bool transport = false;   // the transport depth, when the atlas has a transport colour
    int link = VX_ALL_LINKS;  // of several volumes: the extinction of those that shadow this link
                              // set's lights (light linking), and the scattering of those they light
};

// Box-filters the visible bricks into a light grid of `resolution` over the occupied bricks' box;
// of several volumes, the mean of their summed medium over each cell of their shared frame's box.
LightGrid buildLightGrid(const KernelInputs& inputs, int resolution, LightGridContents contents = {});

// Whether every voxel has the material's albedo (one volume, no transfer function or colour grid).
bool uniformAlbedo(const KernelInputs& inputs);

// `extinction` (one plane) with the three colour-bleeding planes of a uniform `albedo` added:
// plane c is the extinction times (1 - bleeding * albedo_c), as buildLightGrid would box-filter it,
// without a second walk over the bricks.
LightGrid withUniformBleeding(const LightGrid& extinction, glm::vec3 albedo, float bleeding);

}  // namespace voxlux
