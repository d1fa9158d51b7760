// A .vdb file read safely. OpenVDB trusts every length and count in a file, and reads past its end
// without complaint: a name length of 3.6e9 allocates 3.6 GB, a tile count of 4e9 loops on a short
// file, and a file cut short leaves the rest of a grid's voxels unset. So the file's structure is
// walked first (header, file metadata, each grid's descriptor and metadata: a few hundred bytes per
// grid, no voxel data), every length checked against the bytes left and every offset against the
// file; then a grid is read by OpenVDB's own reader from a stream that throws on a short read.
#pragma once
#include <fstream>
#include <string>
#include <vector>

#include <openvdb/io/Archive.h>
#include <openvdb/io/GridDescriptor.h>
#include <openvdb/openvdb.h>

namespace voxlux {

// `name` (read from a file) for a one-line message: control bytes as \xHH.
std::string printableName(const std::string& name);

class VdbFile : private openvdb::io::Archive {
public:
    struct Grid {
        std::string name;
        std::string value_type;                // "float", "vec3s", ...
        bool volume = true;                    // a grid voxlux reads (not points)
    };

    // Opens and checks `file`; throws InputError "<file>: truncated: ..." or "<file>: damaged: ...".
    explicit VdbFile(const std::string& file);
    // The stream is tagged with a pointer to metadata_: a VdbFile stays where it was made.
    VdbFile(const VdbFile&) = delete;
    VdbFile& operator=(const VdbFile&) = delete;

    // The grids in file order, and the file's own metadata (creator and so on).
    const std::vector<Grid>& grids() const { return grids_; }
    const openvdb::MetaMap& fileMetadata() const { return file_metadata_; }
    // "'density' (float), 'vel' (vec3s)" for messages, or "none".
    std::string gridList() const;
    // "<file>: no grid named 'density' (grids: 'smoke' (float); --grid smoke to render it)": the
    // hint names `option` and the file's one scalar grid, when it has one and `option` is given.
    std::string noGridNamed(const std::string& name, const std::string& option = "") const;
    // Grid `k`'s metadata alone (its creator, up axis, ...), without its voxels.
    openvdb::MetaMap gridMetadata(size_t k);
    // Grid `k` with its metadata, transform and voxels. Throws InputError, also for a grid that is
    // not a volume.
    openvdb::GridBase::Ptr read(size_t k);

private:
    void walk();
    openvdb::GridBase::Ptr readGrid(size_t k, int depth);

    std::string file_;
    std::ifstream in_;
    std::vector<Grid> grids_;
    std::vector<std::streamoff> descriptors_;  // where each grid's descriptor starts
    std::vector<std::streamoff> grid_metadata_;  // where each grid's metadata starts
    openvdb::io::StreamMetadata::Ptr metadata_;
    openvdb::MetaMap file_metadata_;
};

}  // namespace voxlux
