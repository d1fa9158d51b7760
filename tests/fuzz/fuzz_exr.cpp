// Fuzzes the EXR readers, on in-memory files: the RGBA `voxlux study` compares images with, and
// the one channel a depth holdout reads. Bad input must throw InputError; anything else is a defect.
#include <cstdint>

#include "core/error.h"
#include "in_memory_file.h"
#include "io/exr_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static InMemoryFile file;
    try {
        voxlux::readExrRgba(file.write(data, size));
    } catch (const voxlux::InputError&) {
    }
    try {
        voxlux::readExrChannel(file.write(data, size), "Z");
    } catch (const voxlux::InputError&) {
    }
    return 0;
}
