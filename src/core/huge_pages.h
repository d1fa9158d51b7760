// Large buffers in transparent huge pages. The first touch of a buffer of hundreds of MB costs one
// page fault per 4 KiB page, and on a virtual machine a fault is dear: in the profile of a 256^3
// propagation, faulting in the illumination volume took longer than the sweeps that fill it. Where
// the kernel offers transparent huge pages only to memory that asks (`madvise`, as on our machines),
// a buffer advised before its first touch takes one fault per 2 MiB instead. Elsewhere the advice
// is a no-op; contents are never affected.
// Cost: one madvise call per buffer allocated, none when the buffer already has the room.
#pragma once
#include <cstddef>
#include <vector>

namespace voxlux {

// Asks for huge pages over the whole 4 KiB pages of [data, data + bytes), if that is at least 4 MiB.
void adviseHugePages(void* data, size_t bytes);

// Room for n elements in v, memory newly allocated for it advised before any element is written
// (then assign or resize as usual). Where it allocates, v's elements are dropped first, so the
// old and new memory never coexist: for buffers about to be written whole.
template <class T>
void reserveInHugePages(std::vector<T>& v, size_t n) {
    if (v.capacity() >= n) return;
    v = std::vector<T>();
    v.reserve(n);
    adviseHugePages(v.data(), n * sizeof(T));
}

// v.assign(n, value) in memory advised as above.
template <class T>
void assignInHugePages(std::vector<T>& v, size_t n, const T& value) {
    reserveInHugePages(v, n);
    v.assign(n, value);
}

// v.resize(n) in memory advised as above, for a buffer about to be written whole: where it
// allocates, the old elements are not kept.
template <class T>
void resizeInHugePages(std::vector<T>& v, size_t n) {
    reserveInHugePages(v, n);
    v.resize(n);
}

}  // namespace voxlux
