// The reference renderer's random numbers. Deterministic: every number is a function of the seed,
// the pixel, the sample index and the number's place in the path, never of thread scheduling, and
// sample i is the same at any spp (more samples refine an image; they do not change the first ones).
//
// Two kinds. The path's few decisions that shape a pixel's estimate most (where the camera ray
// scatters, and which way it scatters then) are stratified across the pixel's samples: they are
// dimensions of a Sobol sequence (Joe and Kuo's direction numbers, from Boost.Random), Owen-scrambled
// per pixel by Burley's hash-based nested uniform scramble (JCGT 2020), with the sample index
// shuffled the same way. Any first 2^k samples of a pixel are then a (t, k, s)-net: each of those
// dimensions puts one sample in each of 2^k equal intervals, where independent numbers leave some
// empty and some crowded. Everything else (tracking steps, roulette, later bounces) is a counter-
// based hash. Costs about 100 integer operations per path for the Sobol point.
#pragma once
#include <cstdint>

namespace voxlux {

class ReferenceRng {
public:
    // The stratified dimensions, in the order a path uses them.
    // The time within the shutter (render.motion_blur) and the point of the lens (camera.fstop)
    // come last, so that they leave the others as they were.
    enum Stratified { kCameraScatter = 0, kFirstDirectionU, kFirstDirectionV, kShutterTime, kLensU, kLensV, kStratifiedCount };

    ReferenceRng(uint32_t seed, uint32_t pixel, uint32_t sample);
    float next();                              // uniform in [0, 1): the hashed sequence
    float stratified(Stratified dimension) const;  // uniform in [0, 1): this sample's Sobol coordinate

private:
    uint32_t key_;
    uint32_t pixel_key_;  // the pixel's scrambling seed
    uint32_t sobol_[kStratifiedCount];
    uint32_t dim_ = 0;
};

}  // namespace voxlux
