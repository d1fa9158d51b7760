// OpenVDB's file layout (io/Archive.cc, io/File.cc, io/GridDescriptor.cc, MetaMap.cc):
//   header: magic, format version, library version, "has grid offsets", [compression], UUID
//   file metadata: count, then per item a name, a type name and a sized value
//   grid count, then per grid a descriptor (unique name, type, instance parent, grid/block/end
//   offsets); the grid's compression and metadata lie at its grid offset, and the next
//   descriptor at its end offset.
// Strings and values are length-prefixed; the walk checks each length against the bytes left.
#include "volume/vdb_file.h"

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <set>

#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/io.h>

#include "core/error.h"
#include "volume/vdb_loader.h"

namespace voxlux {
namespace {

// Exception text on one line: OpenVDB pads some messages with raw bytes from the file.
std::string oneLine(const char* what) {
    std::string out;
    for (const char* p = what; *p; ++p) {
        const bool space = !std::isgraph(static_cast<unsigned char>(*p));
        if (space && (out.empty() || out.back() == ' ')) continue;
        out += space ? ' ' : *p;
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out;
}

// The grid types voxlux reads: volumes of scalars and vectors. Point grids are listed but not
// read (their attribute tables hold lengths of their own).
bool isVolumeType(const std::string& type) {
    static const std::set<std::string> volumes = {
        openvdb::FloatGrid::gridType(), openvdb::DoubleGrid::gridType(), openvdb::Int32Grid::gridType(),
        openvdb::Int64Grid::gridType(), openvdb::BoolGrid::gridType(),   openvdb::MaskGrid::gridType(),
        openvdb::Vec3SGrid::gridType(), openvdb::Vec3DGrid::gridType(), openvdb::Vec3IGrid::gridType()};
    return volumes.count(type) > 0;
}

// Bounded reads of the file's structure: `end` is the file's size or the end of the grid being read.
class StructureWalk {
public:
    StructureWalk(std::ifstream& in, const std::string& file, int64_t size) : in_(in), file_(file), size_(size) {}

    [[noreturn]] void damaged(const std::string& what) const { throw InputError(file_ + ": damaged: " + what); }

    int64_t at() { return int64_t(in_.tellg()); }
    int64_t size() const { return size_; }

    template <class T>
    T read(const std::string& what, int64_t end) {
        need(sizeof(T), end, what);
        T v{};
        in_.read(reinterpret_cast<char*>(&v), sizeof(T));
        return v;
    }

    void skip(int64_t bytes, const std::string& what, int64_t end) {
        need(bytes, end, what);
        in_.seekg(bytes, std::ios::cur);
    }

    std::string string(const std::string& what, int64_t end) {
        const uint32_t length = read<uint32_t>(what, end);
        need(length, end, what);
        std::string s(length, '\0');
        in_.read(s.data(), length);
        return s;
    }

    // A MetaMap (the file's or a grid's). OpenVDB reads a registered type's value as its own size
    // whatever the stored size says (and would misread everything after), so the two must agree;
    // strings and unknown types are read as stored, and a delayed-load table by its own counts.
    void metadata(const std::string& what, int64_t end) {
        const uint32_t count = read<uint32_t>(what + " count", end);
        for (uint32_t k = 0; k < count; ++k) {
            const std::string name = string(what + " name", end);
            const std::string item = what + " '" + printableName(name) + "'";
            const std::string type = string(item + " type", end);
            const uint32_t bytes = read<uint32_t>(item + " size", end);
            need(bytes, end, item);
            const int64_t value_end = at() + bytes;
            if (type == openvdb::io::DelayedLoadMetadata::staticTypeName()) {
                delayedLoadTable(item, bytes);
            } else if (type != openvdb::StringMetadata::staticTypeName() && openvdb::Metadata::isRegisteredType(type) &&
                       bytes != openvdb::Metadata::createMetadata(type)->size()) {
                damaged(item + " (" + printableName(type) + ") has " + std::to_string(bytes) + " bytes");
            }
            in_.seekg(value_end);
        }
    }

private:
    // A delayed-load table: a mask entry per leaf (count) and its compressed form (bytes). Both
    // are allocated before they are read, so each must fit the file and the item.
    void delayedLoadTable(const std::string& item, uint32_t size) {
        if (size == 0) return;
        const int64_t end = at() + size;
        const uint32_t count = read<uint32_t>(item + " count", end);
        const uint32_t compressed = read<uint32_t>(item + " compressed size", end);
        if (int64_t(count) > size_) damaged(item + " has " + std::to_string(count) + " entries, more than the file's bytes");
        need(compressed, end, item + " compressed table");
    }

    void need(int64_t bytes, int64_t end, const std::string& what) {
        if (bytes >= 0 && bytes <= end - at()) return;
        if (end == size_)
            throw InputError(file_ + ": truncated: " + what + " needs " + std::to_string(bytes) + " bytes at byte " +
                             std::to_string(at()) + " but the file has " + std::to_string(size_));
        damaged(what + " of " + std::to_string(bytes) + " bytes runs past its grid");
    }

    std::ifstream& in_;
    const std::string& file_;
    int64_t size_;
};

}  // namespace

std::string printableName(const std::string& name) {
    std::string out;
    for (unsigned char c : name) {
        if (c >= 0x20 && c != 0x7f) {
            out += char(c);
        } else {
            const char* hex = "0123456789abcdef";
            out += std::string("\\x") + hex[c >> 4] + hex[c & 15];
        }
    }
    return out;
}

VdbFile::VdbFile(const std::string& file) : file_(file), in_(file, std::ios::binary) {
    initOpenVdb();   // the walk asks which grid and metadata types are registered
    if (!std::filesystem::is_regular_file(file)) throw InputError(file + ": not a file");
    if (!in_) throw InputError(file + ": cannot open");
    walk();
    try {
        // As io::File::open tags its stream: OpenVDB's readers look up the format version here.
        in_.seekg(0);
        in_.exceptions(std::ios::failbit | std::ios::badbit);
        readHeader(in_);
        metadata_ = std::make_shared<openvdb::io::StreamMetadata>();
        metadata_->setSeekable(true);
        openvdb::io::setStreamMetadataPtr(in_, metadata_, /*transfer=*/false);
        setFormatVersion(in_);
        setLibraryVersion(in_);
        setDataCompression(in_);
        file_metadata_.readMeta(in_);   // checked by the walk
    } catch (const std::exception& e) {
        throw InputError(file + ": not a readable OpenVDB file (" + std::string(e.what()) + ")");
    }
}

void VdbFile::walk() {
    StructureWalk w(in_, file_, int64_t(std::filesystem::file_size(file_)));
    const int64_t end = w.size();
    if (end < 8 || w.read<int64_t>("magic number", end) != openvdb::OPENVDB_MAGIC)
        throw InputError(file_ + ": not an OpenVDB file (no VDB magic number)");
    const uint32_t version = w.read<uint32_t>("format version", end);
    if (version < openvdb::OPENVDB_FILE_VERSION_FLOAT_FRUSTUM_BBOX || version > openvdb::OPENVDB_FILE_VERSION)
        throw InputError(file_ + ": OpenVDB file format " + std::to_string(version) + " is not supported (221 to " +
                         std::to_string(openvdb::OPENVDB_FILE_VERSION) + ")");
    w.skip(8, "library version", end);
    if (w.read<char>("grid offsets flag", end) == 0)
        throw InputError(file_ + ": an OpenVDB stream without grid offsets is not supported (save it as a file)");
    if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) w.skip(1, "compression flag", end);
    w.skip(36, "UUID", end);
    w.metadata("file metadata", end);
    const int32_t count = w.read<int32_t>("grid count", end);
    if (count < 0) w.damaged("negative grid count " + std::to_string(count));
    for (int32_t g = 0; g < count; ++g) {
        descriptors_.push_back(w.at());
        const std::string unique_name = w.string("grid name", end);
        const std::string grid = "grid '" + printableName(unique_name) + "'";
        std::string type = w.string(grid + " type", end);
        if (type.size() > 10 && type.compare(type.size() - 10, 10, "_HalfFloat") == 0) type.resize(type.size() - 10);
        if (!openvdb::GridBase::isRegistered(type)) w.damaged(grid + " has type '" + printableName(type) + "', which OpenVDB does not know");
        w.string(grid + " instance parent", end);
        const auto grid_pos = w.read<int64_t>(grid + " offsets", end);
        const auto block_pos = w.read<int64_t>(grid + " offsets", end);
        const auto end_pos = w.read<int64_t>(grid + " offsets", end);
        if (end_pos > end)
            throw InputError(file_ + ": truncated: " + grid + " ends at byte " + std::to_string(end_pos) +
                             " but the file has " + std::to_string(end));
        if (!(w.at() <= grid_pos && grid_pos <= block_pos && block_pos <= end_pos))
            w.damaged(grid + " has offsets out of order (" + std::to_string(grid_pos) + ", " + std::to_string(block_pos) +
                      ", " + std::to_string(end_pos) + ")");
        in_.seekg(grid_pos);
        if (version >= openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) w.skip(4, grid + " compression", end_pos);
        grid_metadata_.push_back(w.at());
        w.metadata(grid + " metadata", end_pos);
        w.string(grid + " transform type", end_pos);
        in_.seekg(end_pos);
        grids_.push_back({openvdb::io::GridDescriptor::stripSuffix(unique_name),
                          openvdb::GridBase::createGrid(type)->valueType(), isVolumeType(type)});
    }
}

openvdb::MetaMap VdbFile::gridMetadata(size_t k) {
    openvdb::MetaMap meta;
    try {
        in_.clear();
        in_.seekg(grid_metadata_.at(k));
        meta.readMeta(in_);   // its lengths checked by the walk
    } catch (const std::exception& e) {
        throw InputError(file_ + ": grid '" + printableName(grids_.at(k).name) + "': unreadable metadata (" + e.what() + ")");
    }
    return meta;
}

std::string VdbFile::gridList() const {
    std::string out;
    for (const auto& g : grids_) out += (out.empty() ? "'" : ", '") + printableName(g.name) + "' (" + g.value_type + ")";
    return out.empty() ? "none" : out;
}

std::string VdbFile::noGridNamed(const std::string& name, const std::string& option) const {
    std::vector<const Grid*> scalar;
    for (const auto& g : grids_)
        if (g.volume && (g.value_type == "float" || g.value_type == "double")) scalar.push_back(&g);
    const std::string hint = option.empty() || scalar.size() != 1 ? "" : "; " + option + " " + printableName(scalar[0]->name) + " to render it";
    return file_ + ": no grid named '" + name + "' (grids: " + gridList() + hint + ")";
}

openvdb::GridBase::Ptr VdbFile::read(size_t k) {
    if (!grids_[k].volume)
        throw InputError(file_ + ": grid '" + printableName(grids_[k].name) + "' (" + grids_[k].value_type +
                         ") is not a volume; voxlux reads float, double, integer, bool and vector grids");
    try {
        return readGrid(k, 0);
    } catch (const InputError&) {
        throw;
    } catch (const std::ios_base::failure&) {
        // A short read throws here instead of leaving voxels unset.
        throw InputError(file_ + ": damaged: grid '" + printableName(grids_[k].name) +
                         "' reads past the end of the file (a count or size in its tree is wrong)");
    } catch (const std::exception& e) {
        throw InputError(file_ + ": cannot read grid '" + printableName(grids_[k].name) + "' (" + oneLine(e.what()) + ")");
    }
}

openvdb::GridBase::Ptr VdbFile::readGrid(size_t k, int depth) {
    in_.clear();   // after a failed read
    in_.seekg(descriptors_[k]);
    openvdb::io::GridDescriptor gd;
    openvdb::GridBase::Ptr grid = gd.read(in_);
    gd.seekToGrid(in_);
    Archive::readGrid(grid, gd, in_);
    if (!gd.isInstance()) return grid;
    // An instance shares its parent's tree: the file holds only its metadata and transform.
    for (size_t p = 0; p < descriptors_.size() && depth == 0; ++p) {
        in_.seekg(descriptors_[p]);
        openvdb::io::GridDescriptor other;
        other.read(in_);
        if (other.uniqueName() != gd.instanceParentName() || other.isInstance()) continue;
        openvdb::GridBase::Ptr parent = readGrid(p, depth + 1);
        if (parent->type() != grid->type()) break;
        grid->setTree(parent->baseTreePtr());
        return grid;
    }
    throw InputError(file_ + ": damaged: grid '" + printableName(grids_[k].name) + "' is an instance of '" +
                     printableName(gd.instanceParentName()) + "', which is not a grid of its type in the file");
}

}  // namespace voxlux
