#include "optics/median_cut.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace voxlux {

namespace {

struct Region {
    glm::ivec4 box;   // x0, y0, x1, y1
    double power;     // luminance above the floor x solid angle
};

class CutWeights {
public:
    CutWeights(const EnvironmentMap& map, glm::vec3 floor) : map_(map), floor_(floor) {}
    glm::vec3 above(int x, int y) const { return glm::max(map_.at({x, y}) - floor_, glm::vec3(0.0f)); }
    double weight(int x, int y) const { return double(environmentLuminance(above(x, y))) * map_.pixelSolidAngle(y); }
    double power(const glm::ivec4& b) const {
        double sum = 0.0;
        for (int y = b.y; y < b.w; ++y)
            for (int x = b.x; x < b.z; ++x) sum += weight(x, y);
        return sum;
    }
    // Splits `r` across its longer side where the power on either side is closest to equal.
    std::pair<Region, Region> split(const Region& r) const {
        const glm::ivec4 b = r.box;
        // The sides as angles: a pixel spans 2 pi / W of azimuth at its latitude's sine, by pi / H.
        const double middle_latitude = std::sin(M_PI * (b.y + b.w) * 0.5 / map_.height());
        const double wide = double(b.z - b.x) * 2.0 * M_PI / map_.width() * middle_latitude, tall = double(b.w - b.y) * M_PI / map_.height();
        const bool across = b.w - b.y == 1 || (b.z - b.x > 1 && wide >= tall);   // a side of one pixel cannot split
        const int lo = across ? b.x : b.y, hi = across ? b.z : b.w;
        std::vector<double> strip(size_t(hi - lo), 0.0);
        for (int y = b.y; y < b.w; ++y)
            for (int x = b.x; x < b.z; ++x) strip[size_t((across ? x : y) - lo)] += weight(x, y);
        double running = 0.0;
        int cut = lo + 1;
        for (int i = lo; i + 1 < hi; ++i) {
            running += strip[size_t(i - lo)];
            cut = i + 1;
            if (running >= r.power * 0.5) break;
        }
        glm::ivec4 first = b, second = b;
        (across ? first.z : first.w) = cut;
        (across ? second.x : second.y) = cut;
        return {{first, power(first)}, {second, power(second)}};
    }
    CutLight light(const Region& r) const {
        CutLight l;
        l.region = r.box;
        glm::dvec3 centroid(0.0), irradiance(0.0);
        for (int y = r.box.y; y < r.box.w; ++y)
            for (int x = r.box.x; x < r.box.z; ++x) {
                centroid += glm::dvec3(map_.pixelDirection(x, y)) * weight(x, y);
                irradiance += glm::dvec3(above(x, y)) * map_.pixelSolidAngle(y);
            }
        // A region of no luminance (a dim colour the floor took) faces its middle.
        const double length = glm::length(centroid);
        l.toward = length > 0.0 ? glm::vec3(centroid / length)
                                : map_.direction({float(r.box.x + r.box.z) * 0.5f / float(map_.width()),
                                                  float(r.box.y + r.box.w) * 0.5f / float(map_.height())});
        l.irradiance = glm::vec3(irradiance);
        return l;
    }

private:
    const EnvironmentMap& map_;
    glm::vec3 floor_;
};

}  // namespace

MedianCut medianCut(const EnvironmentMap& map, int lights, bool floor) {
    MedianCut out;
    if (floor) {
        out.ambient = glm::vec3(std::numeric_limits<float>::max());
        for (const glm::vec3& l : map.radiance()) out.ambient = glm::min(out.ambient, l);
    }
    if (lights <= 0) return out;
    const CutWeights weights(map, out.ambient);
    const glm::ivec4 whole(0, 0, map.width(), map.height());
    std::vector<Region> regions{{whole, weights.power(whole)}};
    const auto splittable = [](const Region& r) { return r.box.z - r.box.x > 1 || r.box.w - r.box.y > 1; };
    while (int(regions.size()) < lights) {
        // The region of the most power that can split (ties: the first made).
        auto next = regions.end();
        for (auto it = regions.begin(); it != regions.end(); ++it)
            if (splittable(*it) && (next == regions.end() || it->power > next->power)) next = it;
        if (next == regions.end()) break;
        const auto [first, second] = weights.split(*next);
        *next = first;
        regions.push_back(second);
    }
    for (const Region& r : regions) out.lights.push_back(weights.light(r));
    return out;
}

}  // namespace voxlux
