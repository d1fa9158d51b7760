// The fuzzers' inputs as files that live in memory (memfd), for readers that take a path
// (OpenVDB's io::File, OpenEXR): /proc/self/fd/N names the file, and nothing touches the disk.
#pragma once
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <string>

class InMemoryFile {
public:
    InMemoryFile() : fd_(memfd_create("voxlux-fuzz", 0)) {
        if (fd_ < 0) std::abort();
    }
    // Replaces the file's contents with `data` and returns its path.
    std::string write(const uint8_t* data, size_t size) {
        if (ftruncate(fd_, 0) != 0 || pwrite(fd_, data, size, 0) != ssize_t(size)) std::abort();
        return "/proc/self/fd/" + std::to_string(fd_);
    }

private:
    int fd_;
};
