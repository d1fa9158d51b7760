// Fuzzes the VDB loader on in-memory files: the input is a .vdb file, loaded for its "density"
// grid as a render loads it (a level set converted to fog), then listed as `voxlux info` lists it.
// Bad input must throw InputError; anything else is a defect.
#include <cstdint>

#include "core/error.h"
#include "in_memory_file.h"
#include "volume/vdb_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static InMemoryFile file;
    const std::string path = file.write(data, size);
    voxlux::VolumeSpec spec;
    spec.level_set = voxlux::LevelSetPolicy::ConvertToFog;
    try {
        voxlux::loadVolume(path, spec);
    } catch (const voxlux::InputError&) {
    }
    try {
        voxlux::summarizeFile(path);
    } catch (const voxlux::InputError&) {
    }
    return 0;
}
