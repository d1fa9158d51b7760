// The frames a sequence renders, as a farm writes them: "1-240" (a range), "1-240x2" (every second
// frame), "1,5,10-20" (a list). Taken one at a time by index: a range is never expanded, so
// "1-2000000000" costs nothing before its first frame, and a chunk of it is found in O(ranges).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace voxlux {

struct FrameRange {
    int first = 0;
    int last = 0;   // inclusive; last - first is a multiple of step
    int step = 1;
    bool operator==(const FrameRange&) const = default;
};

class FrameSet {
public:
    FrameSet() = default;
    // A range with a step of 1; throws std::invalid_argument when first > last.
    FrameSet(int first, int last);
    // Parses "A", "A-B", "A-BxS" and comma-separated lists of them, each after the one before
    // (frames increase). Throws std::invalid_argument with the problem, e.g.
    // "expected FIRST-LAST[xSTEP] or a list of them, e.g. 1-240x2,300".
    static FrameSet parse(const std::string& spec);

    int64_t count() const;
    int at(int64_t index) const;                 // 0 <= index < count()
    int first() const { return ranges_.front().first; }
    int last() const { return ranges_.back().last; }
    bool isRange() const { return ranges_.size() == 1 && ranges_[0].step == 1; }   // [first, last] in a scene file
    // Appends `frame`, after the last; a frame next to the last extends its range ("3-7" + 8: "3-8").
    void add(int frame);
    // The frames from `begin` (an index) on, `count` of them at most, as a spec: a farm's chunk.
    FrameSet slice(int64_t begin, int64_t count) const;
    // The frames of this set that `present` holds, and those it does not ("which frames of the range
    // are on disk"): O(present's frames x its ranges), never this set frame by frame, so `present`
    // should be the small set (the files on disk) and this one may be "1-2000000000".
    FrameSet among(const FrameSet& present) const;
    FrameSet notAmong(const FrameSet& present) const;
    // The canonical spec parse() reads back: "1-239x2,300".
    std::string text() const;
    bool operator==(const FrameSet&) const = default;

private:
    void append(FrameRange r);
    std::vector<FrameRange> ranges_;
};

}  // namespace voxlux
