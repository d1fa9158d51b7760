#include "reference/sample_sequence.h"

#include <boost/random/sobol.hpp>

#include "kernel/kernel_types.h"

namespace voxlux {
namespace {

// The kernel's PCG hash (vx_types.h).
uint32_t pcgHash(uint32_t v) { return kernel::vx_hash(v); }

uint32_t reverseBits(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

// Burley's nested uniform scramble: in bit-reversed order, a hash in which each bit depends only
// on the bits below it (Laine and Karras's form, Burley's constants), so bit i of the result flips
// as a function of the bits above it: an Owen scramble of a [0, 1) value in 32 bits.
uint32_t owenScramble(uint32_t x, uint32_t seed) {
    x = reverseBits(x);
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return reverseBits(x);
}

// Sobol point `index` (0 is the origin), dimension by dimension. Boost's engine numbers its points
// from 1 in Gray-code order: seeding it with index - 1 makes its next point the one whose Gray code
// is `index`, so indices [a 2^k, (a + 1) 2^k) are one aligned block of the sequence, a net.
void sobolPoint(uint32_t index, uint32_t* out) {
    thread_local boost::random::sobol_engine<uint32_t, 32> engine(ReferenceRng::kStratifiedCount);
    if (index == 0) {
        for (int d = 0; d < ReferenceRng::kStratifiedCount; ++d) out[d] = 0;
        return;
    }
    engine.seed(index - 1);
    for (int d = 0; d < ReferenceRng::kStratifiedCount; ++d) out[d] = engine();
}

float toUnit(uint32_t bits) { return float(bits >> 8) * 0x1p-24f; }

}  // namespace

ReferenceRng::ReferenceRng(uint32_t seed, uint32_t pixel, uint32_t sample)
    : key_(pcgHash(seed ^ pcgHash(pixel ^ pcgHash(sample)))), pixel_key_(pcgHash(seed ^ pcgHash(pixel))) {
    // Shuffling the index by a nested scramble keeps any aligned block of 2^k indices together.
    sobolPoint(owenScramble(sample, pixel_key_), sobol_);
}

float ReferenceRng::next() { return toUnit(pcgHash(key_ + pcgHash(dim_++))); }

float ReferenceRng::stratified(Stratified dimension) const {
    return toUnit(owenScramble(sobol_[dimension], pcgHash(pixel_key_ + uint32_t(dimension) + 1u)));
}

}  // namespace voxlux
