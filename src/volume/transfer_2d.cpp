#include "volume/transfer_2d.h"

#include <atomic>
#include <cmath>

#include <openvdb/math/Operators.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>

#include "optics/transfer_function_2d.h"

namespace voxlux {
namespace {

// A property of the selected voxels (albedo, surface weight) carried two voxels out into the
// unselected ones around them (each new voxel the mean of its selected neighbours'): the filters
// interpolate it with the same weights as the extinction, over up to 4 voxels (tricubic), and an
// unselected voxel's value would otherwise blend the grid's background into a material's edge.
template <typename GridT>
typename GridT::Ptr extendSelected(typename GridT::Ptr selected) {
    using Value = typename GridT::ValueType;
    auto out = selected;
    for (int round = 0; round < 2; ++round) {
        auto grown = out->deepCopy();
        openvdb::tools::dilateActiveValues(grown->tree(), 1, openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::EXPAND_TILES);
        openvdb::tree::LeafManager<typename GridT::TreeType> leaves(grown->tree());
        leaves.foreach([&](typename GridT::TreeType::LeafNodeType& leaf, size_t) {
            auto before = out->getConstUnsafeAccessor();
            for (auto it = leaf.beginValueOn(); it; ++it) {
                const openvdb::Coord c = it.getCoord();
                if (before.isValueOn(c)) continue;
                Value sum = openvdb::zeroVal<Value>();
                int n = 0;
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            Value v;
                            if (before.probeValue(c.offsetBy(dx, dy, dz), v)) sum += v, ++n;
                        }
                it.setValue(sum / float(n));   // n >= 1: the voxel was dilated from a neighbour
            }
        });
        out = grown;
    }
    return out;
}

}  // namespace

LoadedVolume applyTransfer2d(const LoadedVolume& raw, const std::vector<TransferRegion>& regions, std::vector<std::string>& warnings) {
    const openvdb::FloatGrid& values = *raw.density;
    // A region may select the boundary just outside the active voxels (a high gradient at a low
    // value), so the classified voxels are the active ones and their neighbours.
    auto extinction = openvdb::FloatGrid::create(0.0f);
    extinction->setTransform(values.transform().copy());
    extinction->setName(values.getName());
    extinction->tree().topologyUnion(values.tree());
    openvdb::tools::dilateActiveValues(extinction->tree(), 1, openvdb::tools::NN_FACE, openvdb::tools::EXPAND_TILES);
    auto albedo = openvdb::Vec3SGrid::create(openvdb::Vec3s(1.0f));
    albedo->setTransform(values.transform().copy());
    albedo->setName("albedo");
    albedo->tree().topologyUnion(extinction->tree());
    openvdb::Vec3SGrid::Ptr transport;
    if (regionsCarryTransport(regions)) {
        transport = openvdb::Vec3SGrid::create(openvdb::Vec3s(1.0f));
        transport->setTransform(values.transform().copy());
        transport->setName("transport");
        transport->tree().topologyUnion(extinction->tree());
    }
    openvdb::FloatGrid::Ptr surface;
    if (regionsCarrySurface(regions)) {
        surface = openvdb::FloatGrid::create(1.0f);
        surface->setTransform(values.transform().copy());
        surface->setName("surface");
        surface->tree().topologyUnion(extinction->tree());
    }

    // An index-space gradient to world units: the inverse transpose of the voxel edges' matrix.
    const glm::mat3 to_world_gradient = glm::transpose(glm::inverse(glm::mat3(raw.index_to_world)));
    std::atomic<std::uint64_t> unusable{0};
    openvdb::tree::LeafManager<openvdb::FloatTree> leaves(extinction->tree());
    leaves.foreach([&](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
        auto acc = values.getConstUnsafeAccessor();   // one per leaf and thread: no registration with the tree
        auto* colour_leaf = albedo->tree().probeLeaf(leaf.origin());   // the same topology: this thread's alone
        auto* transport_leaf = transport ? transport->tree().probeLeaf(leaf.origin()) : nullptr;
        auto* surface_leaf = surface ? surface->tree().probeLeaf(leaf.origin()) : nullptr;
        std::uint64_t bad = 0;
        for (auto it = leaf.beginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            const float v = acc.getValue(c);
            const openvdb::Vec3f g = openvdb::math::ISGradient<openvdb::math::CD_2ND>::result(acc, c);
            const float gradient = glm::length(to_world_gradient * glm::vec3(g.x(), g.y(), g.z()));
            Classified k;
            if (std::isfinite(v) && std::isfinite(gradient)) k = classify2d(regions, v, gradient);
            else ++bad;
            it.setValue(k.extinction);
            colour_leaf->setValueOnly(c, openvdb::Vec3s(k.albedo.x, k.albedo.y, k.albedo.z));
            if (transport_leaf) transport_leaf->setValueOnly(c, openvdb::Vec3s(k.transport.x, k.transport.y, k.transport.z));
            if (surface_leaf) surface_leaf->setValueOnly(c, k.surface);
            if (k.extinction <= 0.0f) {
                it.setValueOff();
                colour_leaf->setValueOff(c);
                if (transport_leaf) transport_leaf->setValueOff(c);
                if (surface_leaf) surface_leaf->setValueOff(c);
            }
        }
        unusable += bad;
    });
    openvdb::tools::pruneInactive(extinction->tree());
    openvdb::tools::pruneInactive(albedo->tree());
    if (transport) openvdb::tools::pruneInactive(transport->tree());
    albedo = extendSelected<openvdb::Vec3SGrid>(albedo);
    if (surface) {
        openvdb::tools::pruneInactive(surface->tree());
        surface = extendSelected<openvdb::FloatGrid>(surface);
    }
    if (unusable > 0)
        warnings.push_back(raw.file + ": " + std::to_string(unusable.load()) +
                           " voxels whose value or gradient is NaN or infinite are transparent under the 2D transfer function");

    LoadedVolume out = raw;
    out.density = extinction;
    out.color = albedo;
    out.transport = transport;
    out.surface = surface;
    return out;
}

}  // namespace voxlux
