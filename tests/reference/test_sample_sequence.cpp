// The reference's random numbers (src/reference/sample_sequence.h): the stratified dimensions put
// any first 2^k samples of a pixel one in each of 2^k equal intervals, pixels are scrambled apart,
// and the sequence is fixed per (seed, pixel, sample).
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "reference/sample_sequence.h"

namespace voxlux::test {
namespace {

constexpr ReferenceRng::Stratified kDimensions[] = {ReferenceRng::kCameraScatter, ReferenceRng::kFirstDirectionU,
                                                    ReferenceRng::kFirstDirectionV};

TEST(SampleSequence, EveryPrefixOfAPowerOfTwoIsStratified) {
    for (uint32_t pixel : {0u, 1u, 77u, 65535u})
        for (const auto dim : kDimensions)
            for (int k = 0; k <= 10; ++k) {
                const uint32_t n = 1u << k;
                std::set<uint32_t> strata;
                for (uint32_t s = 0; s < n; ++s) {
                    const float u = ReferenceRng(3, pixel, s).stratified(dim);
                    ASSERT_GE(u, 0.0f);
                    ASSERT_LT(u, 1.0f);
                    strata.insert(uint32_t(u * float(n)));
                }
                EXPECT_EQ(strata.size(), n) << "pixel " << pixel << ", dimension " << dim << ", 2^" << k << " samples";
            }
}

// Independent numbers leave strata empty: 1024 hashed numbers fill about 1 - 1/e of 1024 strata.
TEST(SampleSequence, TheHashedNumbersAreNotStratified) {
    std::set<uint32_t> strata;
    for (uint32_t s = 0; s < 1024; ++s) strata.insert(uint32_t(ReferenceRng(3, 5, s).next() * 1024.0f));
    EXPECT_GT(strata.size(), 600u);
    EXPECT_LT(strata.size(), 700u);
}

// Each pixel's scramble differs, and so does each dimension's: the first samples of neighbouring
// pixels, and the dimensions of one sample, are not the same numbers.
TEST(SampleSequence, PixelsAndDimensionsAreScrambledApart) {
    std::set<float> first;
    for (uint32_t pixel = 0; pixel < 64; ++pixel) first.insert(ReferenceRng(3, pixel, 0).stratified(ReferenceRng::kCameraScatter));
    EXPECT_EQ(first.size(), 64u);
    const ReferenceRng rng(3, 9, 4);
    EXPECT_NE(rng.stratified(ReferenceRng::kFirstDirectionU), rng.stratified(ReferenceRng::kFirstDirectionV));
    EXPECT_NE(rng.stratified(ReferenceRng::kCameraScatter), rng.stratified(ReferenceRng::kFirstDirectionU));
}

TEST(SampleSequence, ASampleIsTheSameWhateverWasDrawnBefore) {
    std::vector<float> forwards, backwards;
    for (uint32_t s = 0; s < 16; ++s) forwards.push_back(ReferenceRng(1, 2, s).stratified(ReferenceRng::kFirstDirectionU));
    for (uint32_t s = 16; s-- > 0;) backwards.insert(backwards.begin(), ReferenceRng(1, 2, s).stratified(ReferenceRng::kFirstDirectionU));
    EXPECT_EQ(forwards, backwards);
}

}  // namespace
}  // namespace voxlux::test
