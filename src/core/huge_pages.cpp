#include "core/huge_pages.h"

#include <cstdint>

#include <sys/mman.h>

namespace voxlux {

void adviseHugePages(void* data, size_t bytes) {
    constexpr uintptr_t kPage = 4096;
    if (bytes < (size_t(4) << 20)) return;
    const uintptr_t first = (reinterpret_cast<uintptr_t>(data) + kPage - 1) & ~(kPage - 1);
    const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kPage - 1);
    // Advice only: a kernel without transparent huge pages refuses it, and nothing changes.
    (void)madvise(reinterpret_cast<void*>(first), end - first, MADV_HUGEPAGE);
}

}  // namespace voxlux
