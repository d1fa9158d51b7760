#include "grade/cpu_color_transform.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace voxlux {
namespace kernel {
using namespace glm;
#include "vx_grade.h"
}  // namespace kernel

namespace {
namespace OCIO = OCIO_NAMESPACE;

// Pixels per task: enough that OCIO's per-call setup is small against the transform.
constexpr size_t kChunk = 4096;

}  // namespace

void transformColorsCpu(const OCIO::ConstProcessorRcPtr& processor, std::vector<glm::vec4>& rgba,
                        bool unpremultiply) {
    if (processor->isNoOp()) return;
    const OCIO::ConstCPUProcessorRcPtr cpu =
        processor->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32, OCIO::OPTIMIZATION_DEFAULT);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rgba.size(), kChunk), [&](const tbb::blocked_range<size_t>& r) {
        // A copy, since vx_grade_output needs each original pixel.
        std::vector<glm::vec4> graded(r.size());
        for (size_t i = r.begin(); i < r.end(); ++i)
            graded[i - r.begin()] = kernel::vx_grade_input(rgba[i], unpremultiply);
        OCIO::PackedImageDesc image(&graded[0].x, long(graded.size()), 1, 4);
        cpu->apply(image);
        for (size_t i = r.begin(); i < r.end(); ++i)
            rgba[i] = kernel::vx_grade_output(graded[i - r.begin()], rgba[i], unpremultiply);
    });
}

}  // namespace voxlux
